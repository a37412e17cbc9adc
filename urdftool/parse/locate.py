"""Where an element of a parsed document was written.

A document's elements find their start tags in one of two ways:

- **stamped**: every element carries :data:`~urdftool.source.SRC_ATTRIBUTE`
  (``"line:column:path"``), which survives any later transformation (xacro
  expansion writes it, the SDF reader's element copies keep it);
- **tabled**: a reader that walks the document once (URDF, SRDF) keeps a
  :class:`PositionTable` beside the tree instead. Its spans are *deferred*
  (:func:`urdftool.source.deferred_span`): the scan of the bytes that finds each
  element's line and column runs when a span is first read, which for a file
  without findings is never. The elements a model keeps (``<gazebo>``,
  ``<transmission>``, ``<ros2_control>`` blocks) are marked with the table's key
  (``"@<n>"``), so :func:`span_of` finds their children's positions through
  the table later, for as long as a span of that document is alive.
"""

from __future__ import annotations

import itertools
import sys
import weakref

from lxml import etree

from urdftool.records import record
from urdftool.source import SRC_ATTRIBUTE, Span, deferred_span, element_starts, expat_element_starts

#: Position tables that marked elements refer to, by key; a table lives as long as a span or a
#: document that uses it.
_TABLES: weakref.WeakValueDictionary[str, PositionTable] = weakref.WeakValueDictionary()
_KEYS = itertools.count(1)


@record(frozen=False, eq=False)  # one document's positions, equal only to itself
class PositionTable:
    """Every element's start tag in *data*, the bytes *root* was parsed from, looked up
    on the first request (:meth:`locate`) and kept from then on."""

    root: etree._Element
    data: bytes
    path: str
    _found: dict[etree._Element, tuple[int, int]] | None = None
    _key: str | None = None

    def span(self, element: etree._Element) -> Span:
        """Where *element*'s start tag was written, looked up when first read."""
        return deferred_span(self.path, self.locate, element)

    def locate(self, element: etree._Element) -> Span | None:
        """The span of *element*, or of its nearest ancestor in the table."""
        found = self._found
        if found is None:
            found = self._found = position_table(self.root, self.data)
            self.data = b""  # read once; the table holds what was needed
        node: etree._Element | None = element
        while node is not None:
            position = found.get(node)
            if position is not None:
                return Span(self.path, position[0], position[1])
            node = node.getparent()
        return None

    def mark(self, element: etree._Element) -> None:
        """Mark *element* (kept by the model) so that :func:`span_of` finds it and its
        descendants through this table."""
        if self._key is None:
            self._key = f"@{next(_KEYS)}"
            _TABLES[self._key] = self
        if element.get(SRC_ATTRIBUTE) is None:
            element.set(SRC_ATTRIBUTE, self._key)


def encode_src(path: str, line: int, column: int) -> str:
    return f"{line}:{column}:{path}"


def decode_src(value: str) -> Span | None:
    try:
        line, column, path = value.split(":", 2)
        # One path object for every span of a file, not a copy per element of a 100k-link model.
        return Span(sys.intern(path), int(line), int(column))
    except ValueError:
        return None


def span_of(element: etree._Element) -> Span | None:
    """The span recorded on *element*, or on its nearest ancestor that has one (for an element
    of a tabled document, through the table its marked ancestor names)."""
    node: etree._Element | None = element
    while node is not None:
        value = node.get(SRC_ATTRIBUTE)
        if value is not None:
            if value.startswith("@"):
                table = _TABLES.get(value)
                return table.locate(element) if table is not None else None
            return decode_src(value)
        node = node.getparent()
    return None


def position_table(root: etree._Element, data: bytes) -> dict[etree._Element, tuple[int, int]]:
    """Every element's start-tag (line, column); the i-th start tag is the i-th lxml element."""
    elements = list(root.iter(etree.Element))  # elements only: no comments, PIs or entities
    starts = element_starts(data)
    if len(starts) != len(elements):  # the scan of the bytes missed something: ask expat
        try:
            starts = expat_element_starts(data)
        except Exception:  # expat disagreeing with libxml2: fall back to lxml's lines
            starts = []
    if len(starts) == len(elements):
        return dict(zip(elements, starts, strict=True))
    return {element: (element.sourceline or 1, 1) for element in elements}


def stamp_positions(root: etree._Element, data: bytes, path: str) -> None:
    """Stamp every element of *root* with its position in *data*."""
    # encode_src, inlined: this runs once per element of every file read
    for element, (line, column) in position_table(root, data).items():
        element.set(SRC_ATTRIBUTE, f"{line}:{column}:{path}")
