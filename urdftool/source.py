"""Where things were written: spans into the files the user edits.

Every node of the model and every diagnostic carries a :class:`Span`. For plain
URDF and SDF the span is the element's start tag in that file. For xacro input it
is the ``.xacro`` file and line where the element was written (inside a macro
body, that is the macro's definition), recovered through :class:`SourceIndex`.

lxml reports only a line per element (the line where the start tag *ends*), so
exact line and column come from a second, position-only pass over the bytes
(:func:`element_starts`) whose element starts are matched to lxml's elements in
document order. Readers that keep that pass for when it is needed give their
nodes deferred spans (:func:`deferred_span`): a Span whose position is looked up
on its first read.
"""

from __future__ import annotations

import bisect
import dataclasses
import functools
import os
import re
import xml.parsers.expat
from collections.abc import Callable, Iterator
from dataclasses import field
from typing import Any

from urdftool.records import record

#: Attribute that carries an element's origin through xacro expansion.
#: Value: ``"<file index>:<line>:<column>"``; stripped before the model is built.
SRC_ATTRIBUTE = "urdftool-src"


@record(order=True)
class Span:
    """A range in a source file: 1-based start line and column (``None`` where unknown).

    ``end_line``/``end_column`` close the range (exclusive column) and
    ``offset``/``end_offset`` give it in bytes from the start of the file, where
    known: what an edit (a :class:`~urdftool.diagnostics.Fix`) needs. Most
    findings only know where an element starts.
    """

    path: str
    line: int | None = None
    column: int | None = None
    end_line: int | None = None
    end_column: int | None = None
    offset: int | None = None
    end_offset: int | None = None

    def __str__(self) -> str:
        if self.line is None:
            return self.path
        if self.column is None:
            return f"{self.path}:{self.line}"
        return f"{self.path}:{self.line}:{self.column}"

    def with_path(self, path: str) -> Span:
        return dataclasses.replace(self, path=path)

    def to_json(self) -> dict[str, Any]:
        """``path``, ``line``, ``column``, and the end and byte offsets where known."""
        out: dict[str, Any] = {"path": self.path, "line": self.line, "column": self.column}
        for key in ("end_line", "end_column", "offset", "end_offset"):
            value = getattr(self, key)
            if value is not None:
                out[key] = value
        return out


#: The position fields of a :class:`Span`, which a deferred span looks up when first read.
_POSITION_FIELDS = ("line", "column", "end_line", "end_column", "offset", "end_offset")
_SPAN_SLOT = {name: vars(Span)[name] for name in (*_POSITION_FIELDS, "path")}


def _position(name: str) -> property:
    """The field *name* of a deferred span: its slot, filled from the lookup on the first read."""
    get = _SPAN_SLOT[name].__get__

    def read(span: _DeferredSpan) -> int | None:
        try:
            value: int | None = get(span, Span)
        except AttributeError:  # not looked up yet
            span._resolve()
            value = get(span, Span)
        return value

    return property(read, doc=f"``Span.{name}``, looked up when first read")


class _DeferredSpan(Span):
    """A :class:`Span` whose position is looked up when a field of it is first read.

    A reader builds one span per element, and most are never read: only a finding
    shows its span. Finding an element's line and column needs a scan of the whole
    document (:func:`element_starts`), which a file without findings never has to
    pay for. Built by :func:`deferred_span`; in every other respect it *is* a Span:
    its ``__class__`` is :class:`Span`, so it is equal to, ordered and hashed with
    plain spans by its fields, ``dataclasses.replace`` gives a plain span, and it
    pickles and copies as one.
    """

    __slots__ = ("_key", "_locate")
    _locate: Callable[[Any], Span | None]
    _key: Any

    line = _position("line")
    column = _position("column")
    end_line = _position("end_line")
    end_column = _position("end_column")
    offset = _position("offset")
    end_offset = _position("end_offset")

    @property  # type: ignore[misc]
    def __class__(self) -> type:  # the class docstring says why
        return Span

    # Built empty by :func:`deferred_span` (a call of the class costs less than
    # ``object.__new__``), not by Span's ``__init__``.
    __init__ = object.__init__

    def _resolve(self) -> None:
        found = self._locate(self._key)
        for name in _POSITION_FIELDS:
            _SPAN_SLOT[name].__set__(self, None if found is None else getattr(found, name))
        # The lookup itself (and the document it reads) stays: a deferred span of an element the
        # model keeps is what keeps that document's position table alive (``parse.xmlio``).
        object.__setattr__(self, "_key", None)

    def __reduce__(self) -> tuple[type, tuple[Any, ...]]:
        return Span, tuple(getattr(self, name) for name in ("path", *_POSITION_FIELDS))


_set_path = _SPAN_SLOT["path"].__set__
_set_locate = vars(_DeferredSpan)["_locate"].__set__
_set_key = vars(_DeferredSpan)["_key"].__set__


def deferred_span(path: str, locate: Callable[[Any], Span | None], key: Any) -> Span:
    """A span in *path* whose position is ``locate(key)``, called when a position field is first
    read (a ``None`` result leaves them ``None``). *locate* must give the same answer whenever it
    is called: the span is a value, compared and hashed by its fields."""
    span: Span = _DeferredSpan()
    _set_path(span, path)
    _set_locate(span, locate)
    _set_key(span, key)
    return span


def is_deferred(span: Span | None) -> bool:
    """Whether *span* is a :func:`deferred_span` (``type``, not ``isinstance``: it passes for a Span)."""
    return type(span) is _DeferredSpan


def settled(span: Span) -> Span:
    """*span* as a plain :class:`Span` with its position looked up: what a finding keeps once
    the check is over, so that the finding does not keep the document and its position table
    alive (a report per file of a many-file run would keep every document with a finding)."""
    if type(span) is not _DeferredSpan:
        return span
    return Span(span.path, span.line, span.column, span.end_line, span.end_column, span.offset,
                span.end_offset)


#: In a document lxml has accepted, every ``<`` is markup: a comment, a CDATA section or a
#: processing instruction (each skipped whole, since its text may hold ``<``), an end tag or a
#: declaration (``</``, ``<!``), or an element's start tag, which the group captures.
_MARKUP = re.compile(rb"<(?:!--.*?-->|!\[CDATA\[.*?\]\]>|\?.*?\?>|([^/!?]))", re.S)


def needs_expat(data: bytes) -> bool:
    """Whether the scan of the bytes cannot serve *data* and expat's position pass must: a
    document type declaration (whose literals may hold ``<``), or a lone carriage return (a line
    break for expat, and so for every line number urdftool reports)."""
    return b"<!DOCTYPE" in data or (b"\r" in data and data.count(b"\r") != data.count(b"\r\n"))


def element_starts(data: bytes) -> list[tuple[int, int]]:
    """Return the (line, column) of every element start tag, in document order.

    Columns are 1-based character columns, as expat counts them: a multi-byte
    UTF-8 character is one column (``'<a x="ää"/><b/>'`` puts ``<b`` at column
    12). Only called on documents that lxml has already accepted with entity
    expansion off, so the text is well-formed UTF-8 and every ``<`` outside
    comments, CDATA and processing instructions is markup: a scan of the bytes
    finds the start tags without a Python call per element, as expat's
    position pass did. A document type declaration (whose literals may hold
    ``<``) or a lone carriage return (a line break for expat, and so for every
    line number urdftool reports) goes to expat instead.
    """
    if needs_expat(data):
        return expat_element_starts(data)
    ascii_only = data.isascii()  # then a column is a byte count
    starts: list[tuple[int, int]] = []
    append = starts.append
    count, rfind = data.count, data.rfind
    line, line_start, previous = 1, 0, 0
    characters = 0  # characters from the start of the line to the previous start tag
    for match in _MARKUP.finditer(data):
        if match.lastindex is None:  # a comment, CDATA or a processing instruction
            continue
        offset = match.start()
        breaks = count(b"\n", previous, offset)
        if breaks:
            line += breaks
            line_start = rfind(b"\n", previous, offset) + 1
        if ascii_only:
            append((line, offset - line_start + 1))
        else:
            # Only the text since the previous tag (or the line break) is decoded, so a long line
            # of many elements costs its length once, not once per element. Both ends are '<' or
            # a line start: never inside a multi-byte character.
            since = line_start if breaks else previous
            characters = (0 if breaks else characters) + len(data[since:offset].decode("utf-8", "replace"))
            append((line, characters + 1))
        previous = offset
    return starts


def start_tag_offsets(data: bytes) -> Iterator[int] | None:
    """The byte offset of every element start tag's ``<``, in document order, or ``None`` when
    :func:`element_starts` would hand the document to expat (a DOCTYPE, a lone carriage return).
    The cheap part of the scan: turning an offset into a position is left to
    :class:`LinePositions`, for the few elements whose position is read. An iterator: the scan
    goes as far into the text as the offsets are read (most files with a finding have one or
    two, so the text after the last element asked for is not scanned)."""
    if needs_expat(data):
        return None
    return (match.start() for match in _MARKUP.finditer(data) if match.lastindex is not None)


@record(frozen=False, eq=False)  # one document's counts, equal only to itself
class LinePositions:
    """The 1-based (line, character column) of byte offsets in *data*, as :func:`element_starts`
    counts them, for offsets asked one at a time in any order. The line breaks before an offset
    are counted (in C) from the nearest offset asked before it, so many lookups in one file
    cost about one pass over it, not one pass each."""

    data: bytes
    #: offsets asked so far, sorted, and the line breaks before each
    _offsets: list[int] = field(default_factory=lambda: [0])
    _breaks: list[int] = field(default_factory=lambda: [0])

    def position(self, offset: int) -> tuple[int, int]:
        data = self.data
        line_start = data.rfind(b"\n", 0, offset) + 1
        prefix = data[line_start:offset]
        column = len(prefix) if prefix.isascii() else len(prefix.decode("utf-8", "replace"))
        known = bisect.bisect_right(self._offsets, line_start) - 1
        breaks = self._breaks[known] + data.count(b"\n", self._offsets[known], line_start)
        if self._offsets[known] != line_start:
            self._offsets.insert(known + 1, line_start)
            self._breaks.insert(known + 1, breaks)
        return breaks + 1, column + 1


def expat_element_starts(data: bytes) -> list[tuple[int, int]]:
    """:func:`element_starts` by expat's own position pass (a Python call per element)."""
    positions: list[tuple[int, int]] = []
    parser = xml.parsers.expat.ParserCreate()
    # Entity declarations were refused earlier; expat must never expand any.
    parser.SetParamEntityParsing(xml.parsers.expat.XML_PARAM_ENTITY_PARSING_NEVER)
    append = positions.append

    def start(_name: str, _attrs: dict[str, str]) -> None:
        append((parser.CurrentLineNumber, parser.CurrentColumnNumber + 1))

    parser.StartElementHandler = start
    try:
        parser.Parse(data, True)
    finally:
        # The handler and the parser refer to each other: a cycle that would keep the list of
        # positions alive while the collector is paused (urdftool.pipeline.check).
        parser.StartElementHandler = None
    return positions


_ATTR_CACHE_LIMIT = 64


@functools.lru_cache(maxsize=256)
def _attribute_pattern(attribute: str) -> re.Pattern[str]:
    """``attribute=`` as a whole name (not the tail of ``xlink:attribute``), compiled once."""
    return re.compile(r"(?<![\w:.-])" + re.escape(attribute) + r"\s*=")


#: Byte-order marks of the encodings that are not ASCII-compatible, the longest first.
BOMS: tuple[tuple[bytes, str], ...] = (
    (b"\x00\x00\xfe\xff", "utf-32-be"),
    (b"\xff\xfe\x00\x00", "utf-32-le"),
    (b"\xfe\xff", "utf-16-be"),
    (b"\xff\xfe", "utf-16-le"),
)
#: The XML declaration's encoding name (group 2).
DECLARED_ENCODING = re.compile(rb"^(\s*<\?xml[^>]*?encoding\s*=\s*[\"'])([A-Za-z0-9._:-]*)([\"'])")
UTF8_NAMES = frozenset({"utf-8", "utf8", "us-ascii", "ascii"})


def sniff_encoding(data: bytes) -> str | None:
    """UTF-16/32 by byte-order mark, or by the NUL pattern of ``<`` and other ASCII
    characters at the start (XML 1.0 appendix F); ``None`` for ASCII-compatible text."""
    for bom, name in BOMS:
        if data.startswith(bom):
            return name
    head = data[:4]
    if len(head) < 4:
        return None
    zero = [b == 0 for b in head]
    if zero == [True, True, True, False]:
        return "utf-32-be"
    if zero == [False, True, True, True]:
        return "utf-32-le"
    if zero == [True, False, True, False]:
        return "utf-16-be"
    if zero == [False, True, False, True]:
        return "utf-16-le"
    return None


def decode_source(data: bytes) -> str:
    """The text of a source file as the readers decode it (``parse.xmlio.to_utf8``): UTF-16/32
    by byte-order mark or NUL pattern, else the encoding the XML declaration names, else UTF-8;
    bytes that do not decode become U+FFFD. A UTF-8 byte-order mark is dropped, as the readers
    drop it, so that columns on the first line agree with theirs."""
    encoding = sniff_encoding(data)
    if encoding is not None:
        bom = next((b for b, name in BOMS if name == encoding and data.startswith(b)), b"")
        return data[len(bom):].decode(encoding, "replace")
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    match = DECLARED_ENCODING.match(data)
    if match is not None and match.group(2).decode("ascii").lower() not in UTF8_NAMES:
        try:
            return data.decode(match.group(2).decode("ascii"), "replace")
        except LookupError:  # an unknown encoding: the reader has reported it
            pass
    return data.decode("utf-8", "replace")


@record(frozen=False, eq=False)  # one run's state, equal only to itself
class SourceIndex:
    """The texts of the files a model was read from, for locating attributes.

    ``files`` lists paths by the index used in :data:`SRC_ATTRIBUTE` values.
    """

    files: list[str] = field(default_factory=list)
    _lines: dict[str, list[str]] = field(default_factory=dict)

    def add_file(self, path: str, text: str | None = None) -> int:
        """Register *path* (and optionally its text); return its index."""
        path = os.fspath(path)
        if path in self.files:
            index = self.files.index(path)
        else:
            self.files.append(path)
            index = len(self.files) - 1
        if text is not None:
            self._lines[path] = text.split("\n")
        return index

    def lines(self, path: str) -> list[str]:
        if path not in self._lines:
            try:
                with open(path, "rb") as handle:
                    self._lines[path] = decode_source(handle.read()).split("\n")
            except OSError:
                self._lines[path] = []
        return self._lines[path]

    def line_text(self, span: Span) -> str | None:
        """The text of the span's line, or ``None`` when unavailable."""
        if span.line is None:
            return None
        lines = self.lines(span.path)
        if 0 < span.line <= len(lines):
            return lines[span.line - 1]
        return None

    def attribute_span(self, element: Span, attribute: str) -> Span:
        """Locate ``attribute=`` inside the start tag that begins at *element*.

        Start tags may span lines; the search covers up to 20 lines and falls back
        to the element's own span.
        """
        if element.line is None:
            return element
        lines = self.lines(element.path)
        pattern = _attribute_pattern(attribute)
        first = element.line - 1
        for offset in range(20):
            index = first + offset
            if index >= len(lines):
                break
            text = lines[index]
            start = (element.column or 1) - 1 if offset == 0 else 0
            match = pattern.search(text, start)
            close = text.find(">", start)
            if match and (close < 0 or match.start() < close):
                return Span(element.path, index + 1, match.start() + 1)
            if close >= 0:
                break
        return element

    def decode(self, value: str) -> Span | None:
        """Turn a :data:`SRC_ATTRIBUTE` value back into a span."""
        try:
            index, line, column = (int(part) for part in value.split(":"))
            return Span(self.files[index], line, column)
        except (ValueError, IndexError):
            return None

    def encode(self, index: int, line: int, column: int) -> str:
        return f"{index}:{line}:{column}"
