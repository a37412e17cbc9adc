"""Where an element of a parsed document was written.

A document's elements find their start tags in one of two ways:

- **stamped**: every element carries :data:`~urdftool.source.SRC_ATTRIBUTE`
  (``"line:column:path"``), which survives any later transformation (xacro
  expansion writes it, the SDF reader's element copies keep it);
- **tabled**: a reader that walks the document once (URDF, SRDF) keeps a
  :class:`PositionTable` beside the tree instead. Its spans are *deferred*
  (:func:`urdftool.source.deferred_span`): an element's line and column are
  looked up when its span is first read, which for a file without findings is
  never. The elements a model keeps (``<gazebo>``,
  ``<transmission>``, ``<ros2_control>`` blocks) are marked with the table's key
  (``"@<n>"``), so :func:`span_of` finds their children's positions through
  the table later, for as long as a span of that document is alive.
"""

from __future__ import annotations

import itertools
import re
import sys
import weakref
from collections.abc import Iterator

from lxml import etree

from urdftool.records import record
from urdftool.source import (
    SRC_ATTRIBUTE,
    LinePositions,
    Span,
    deferred_span,
    element_starts,
    expat_element_starts,
    needs_expat,
    start_tag_offsets,
)

#: Position tables that marked elements refer to, by key; a table lives as long as a span or a
#: document that uses it.
_TABLES: weakref.WeakValueDictionary[str, PositionTable] = weakref.WeakValueDictionary()
_KEYS = itertools.count(1)


#: An element's index in document order: the elements before it that are not its ancestors,
#: and its ancestors (counted in C, without a Python object per element).
_DOCUMENT_INDEX = etree.XPath("count(preceding::*) + count(ancestor::*)")
#: Elements located by their index before the table keeps a dict of every element: counting
#: the elements before one is cheap, but not a hundred times over.
_COUNTED_LOOKUPS = 4


@record(frozen=False, eq=False)  # one document's positions, equal only to itself
class PositionTable:
    """Where the start tag of each element of *root* stands in *data*, the bytes it was parsed
    from, looked up on request (:meth:`locate`).

    The i-th start tag in the bytes is the i-th element in document order. The first lookup
    finds every start tag's offset (one regular expression over the bytes); each lookup then
    turns one offset into a line and column, in C. A file with a finding or two pays for that
    and no more; one with many gets a dict from element to index after a few lookups.
    A document the scan does not serve (a DOCTYPE, a lone carriage return) or where it
    disagrees with lxml takes the full table of :func:`position_table`.
    """

    root: etree._Element
    data: bytes
    path: str
    #: the start-tag offsets scanned so far, and the scan that finds the rest
    _offsets: list[int] | None = None
    _scan: Iterator[int] | None = None
    _lines: LinePositions | None = None
    _index: dict[etree._Element, int] | None = None
    _lookups: int = 0
    #: every element's position, when the offsets cannot serve
    _found: dict[etree._Element, tuple[int, int]] | None = None
    _key: str | None = None
    #: the byte offset where each line starts (index 0: line 1), once a lookup by line ran
    _line_starts: list[int] | None = None
    _line_scan: Iterator[int] | None = None

    def span(self, element: etree._Element) -> Span:
        """Where *element*'s start tag was written, looked up when first read."""
        return deferred_span(self.path, self.locate, element)

    def locate(self, element: etree._Element) -> Span | None:
        """The span of *element*, or of its nearest ancestor in the table."""
        if self._found is None:
            position = self._position_on_line(element) or self._position(element)
            if position is not None:
                return Span(self.path, position[0], position[1])
            if self._found is None:
                self._found = position_table(self.root, self.data)
        node: etree._Element | None = element
        while node is not None:
            found = self._found.get(node)
            if found is not None:
                return Span(self.path, found[0], found[1])
            node = node.getparent()
        return None

    def _position_on_line(self, element: etree._Element) -> tuple[int, int] | None:
        """*element*'s position found on the line lxml records for it, or ``None`` when that line
        does not settle it (the other lookups then decide).

        lxml's ``sourceline`` is the line of the ``>`` that ends the start tag. When that line
        holds exactly one ``<name`` and no ``>`` stands between the line's start and it before
        a ``<`` does, the start tag began on this line and that ``<name`` is its own: had the tag
        begun on an earlier line, the line would open inside the tag, whose text holds no ``<``,
        and its ``>`` would come first. A tag split over lines, a second element of the same
        name on the line, or a ``<name`` in a comment leave the answer to the start-tag offsets.
        """
        line = element.sourceline
        data = self.data
        if not line or line >= 65535 or element.getroottree().getroot() is not self.root:
            return None  # libxml2 caps the lines it counts; a copy has no line of this document
        starts = self._line_starts
        if starts is None:
            if needs_expat(data):  # a DOCTYPE or a lone carriage return: lines lxml counts otherwise
                return None
            starts = self._line_starts = [0]
            self._line_scan = map(_MATCH_END, _LINE_BREAK.finditer(data))  # (in C: no frame per line)
        if line >= len(starts) and self._line_scan is not None:  # scan as far as the line's end
            starts.extend(itertools.islice(self._line_scan, line + 1 - len(starts)))
        if line > len(starts):
            return None
        begin = starts[line - 1]
        end = starts[line] if line < len(starts) else len(data)
        name = element.tag if element.prefix is None else f"{element.prefix}:{etree.QName(element).localname}"
        if not isinstance(name, str):
            return None
        opening = b"<" + name.encode("utf-8")
        found = -1
        at = data.find(opening, begin, end)
        while at != -1:
            if data[at + len(opening):at + len(opening) + 1] in _AFTER_NAME:
                if found != -1:
                    return None  # two start tags of this name on the line
                found = at
            at = data.find(opening, at + 1, end)
        if found == -1:
            return None
        closing = data.find(b">", begin, found)
        if closing != -1 and not -1 < data.find(b"<", begin, found) < closing:
            return None  # the line may open inside a tag begun on an earlier line
        prefix = data[begin:found]
        column = len(prefix) if prefix.isascii() else len(prefix.decode("utf-8", "replace"))
        return line, column + 1

    def _position(self, element: etree._Element) -> tuple[int, int] | None:
        """*element*'s position from the start-tag offsets, or ``None`` to take the full table."""
        if self._offsets is None:
            self._scan = start_tag_offsets(self.data)
            if self._scan is None:
                return None
            self._offsets = []
        if self._index is not None:
            index = self._index.get(element)
        elif element.getroottree().getroot() is not self.root:
            return None  # not an element of this document (a copy of one, say)
        else:
            self._lookups += 1
            if self._lookups > _COUNTED_LOOKUPS:
                self._index = {node: i for i, node in enumerate(self.root.iter(etree.Element))}
                if len(self._index) != self._start_tags():  # the scan disagrees with lxml
                    return None
                index = self._index.get(element)
            else:
                index = int(_DOCUMENT_INDEX(element))
        offset = None if index is None else self._start_tag(index)
        if offset is None:
            return None
        # The start tag found must be this element's, or the scan and lxml disagree.
        name = element.tag if element.prefix is None else f"{element.prefix}:{etree.QName(element).localname}"
        if not isinstance(name, str):
            return None
        end = offset + 1 + len(name.encode("utf-8"))
        if self.data[offset + 1:end] != name.encode("utf-8") or self.data[end:end + 1] not in _AFTER_NAME:
            return None
        if self._lines is None:
            self._lines = LinePositions(self.data)
        return self._lines.position(offset)

    def _start_tag(self, index: int) -> int | None:
        """The offset of the start tag of the element at *index* in document order, scanning the
        text only as far as that tag (``None`` past the last one)."""
        offsets = self._offsets
        assert offsets is not None
        if index >= len(offsets) and self._scan is not None:
            offsets.extend(itertools.islice(self._scan, index + 1 - len(offsets)))
        return offsets[index] if index < len(offsets) else None

    def _start_tags(self) -> int:
        """How many start tags the text holds (the scan finished)."""
        assert self._offsets is not None
        if self._scan is not None:
            self._offsets.extend(self._scan)
            self._scan = None
        return len(self._offsets)

    def mark(self, element: etree._Element) -> None:
        """Mark *element* (kept by the model) so that :func:`span_of` finds it and its
        descendants through this table."""
        if self._key is None:
            self._key = f"@{next(_KEYS)}"
            _TABLES[self._key] = self
        if element.get(SRC_ATTRIBUTE) is None:
            element.set(SRC_ATTRIBUTE, self._key)


#: What may follow an element's name in its start tag.
_AFTER_NAME = frozenset({b" ", b"\t", b"\r", b"\n", b"/", b">"})
_LINE_BREAK = re.compile(b"\n")
_MATCH_END = re.Match.end


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
