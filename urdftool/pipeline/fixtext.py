"""The source text a fix edits: byte offsets of start tags, attribute values and whole elements.

Fixes never re-serialise XML. They find, in the bytes of the file the user
edits, the start tag a finding points at (line and character column, as the
readers stamp them), lex that one tag, and name byte ranges in it: an attribute's
name, its value between the quotes, the element's name, the whole element
through its end tag. Everything else in the file stays byte for byte.

Only UTF-8 (and ASCII) files are edited; a file in another encoding gets no fix.
"""

from __future__ import annotations

import itertools
import os
import re
from dataclasses import field

from urdftool.records import record
from urdftool.source import Span

_NAME = re.compile(rb"[A-Za-z_:][\w.:-]*")
_SPACE = re.compile(rb"\s*")
_DECLARED = re.compile(rb"^\s*<\?xml[^>]*encoding\s*=\s*[\"']([^\"']+)[\"']")
_ENTITIES = {"&lt;": "<", "&gt;": ">", "&amp;": "&", "&quot;": '"', "&apos;": "'"}
_ENTITY = re.compile(r"&(lt|gt|amp|quot|apos|#[0-9]+|#x[0-9a-fA-F]+);")


def unescape(raw: str) -> str:
    """An attribute value as XML reads it (the five entities and character references)."""

    def one(match: re.Match[str]) -> str:
        text = match.group(0)
        if text in _ENTITIES:
            return _ENTITIES[text]
        body = match.group(1)
        return chr(int(body[2:], 16) if body.startswith("#x") else int(body[1:]))

    return _ENTITY.sub(one, raw)


def escape(value: str, quote: str = '"') -> str:
    """*value* written inside an attribute quoted with *quote*."""
    out = value.replace("&", "&amp;").replace("<", "&lt;")
    return out.replace(quote, "&quot;" if quote == '"' else "&apos;")


@record
class Attribute:
    name: str
    name_start: int
    name_end: int
    #: the value's bytes, between the quotes
    value_start: int
    value_end: int
    quote: str
    raw: str

    @property
    def value(self) -> str:
        return unescape(self.raw)


@record
class Tag:
    """One start tag: where it is, its name and its attributes (byte offsets into the file)."""

    name: str
    start: int
    name_end: int
    #: offset just after ``>``
    end: int
    self_closing: bool
    attributes: tuple[Attribute, ...]

    def attribute(self, name: str) -> Attribute | None:
        return next((a for a in self.attributes if a.name == name), None)


@record(frozen=False)
class SourceText:
    """The bytes of one file, with line starts, for turning positions into byte offsets."""

    path: str
    data: bytes
    _starts: list[int] = field(default_factory=list)
    #: start tags lexed so far, by offset: a CAD export misspells the same attributes on every
    #: joint, and each finding on a tag asks for it again
    _tags: dict[int, Tag | None] = field(default_factory=dict)

    @classmethod
    def read(cls, path: str) -> SourceText | None:
        """The file's text, or ``None`` when it cannot be read or is not UTF-8."""
        try:
            with open(path, "rb") as handle:
                data = handle.read()
        except OSError:
            return None
        return cls.of(path, data)

    @classmethod
    def of(cls, path: str, data: bytes) -> SourceText | None:
        if data.startswith((b"\xff\xfe", b"\xfe\xff", b"\x00")) or (len(data) > 1 and data[1:2] == b"\x00"):
            return None
        declared = _DECLARED.match(data)
        if declared and declared.group(1).decode("ascii", "replace").lower() not in {
            "utf-8", "utf8", "us-ascii", "ascii"
        }:
            return None
        try:
            data.decode("utf-8")
        except UnicodeDecodeError:
            return None
        return cls(os.fspath(path), data)

    def _line_starts(self) -> list[int]:
        if not self._starts:
            # Each line starts one byte after the previous line's end: summed in C, not per line.
            lines = self.data.split(b"\n")[:-1]
            self._starts = list(itertools.accumulate(map((1).__add__, map(len, lines)), initial=0))
        return self._starts

    def offset(self, line: int, column: int) -> int | None:
        """The byte offset of a 1-based line and character column."""
        starts = self._line_starts()
        if not 0 < line <= len(starts) or column < 1:
            return None
        begin = starts[line - 1]
        stop = starts[line] if line < len(starts) else len(self.data)
        text = self.data[begin:stop].decode("utf-8")
        if column - 1 > len(text):
            return None
        return begin + len(text[: column - 1].encode("utf-8"))

    def position(self, offset: int) -> tuple[int, int]:
        """The 1-based line and character column of a byte offset."""
        starts = self._line_starts()
        lo, hi = 0, len(starts) - 1
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if starts[mid] <= offset:
                lo = mid
            else:
                hi = mid - 1
        column = len(self.data[starts[lo]:offset].decode("utf-8", "replace")) + 1
        return lo + 1, column

    def span(self, start: int, end: int) -> Span:
        """A :class:`Span` with lines, columns and byte offsets."""
        line, column = self.position(start)
        end_line, end_column = self.position(end)
        return Span(self.path, line, column, end_line, end_column, start, end)

    def tag_at(self, span: Span | None, name: str | None = None) -> Tag | None:
        """The start tag at *span* (the ``<`` or any position inside the tag), optionally named *name*."""
        if span is None or span.line is None or span.path != self.path:
            return None
        offset = self.offset(span.line, span.column or 1)
        if offset is None:
            return None
        # ``<`` cannot stand inside an attribute value: the nearest one before is the tag's.
        start = self.data.rfind(b"<", 0, offset + 1)
        if start < 0:
            return None
        tag = self._tags[start] if start in self._tags else self._tags.setdefault(start, self.lex(start))
        if tag is None or offset >= tag.end or (name is not None and local(tag.name) != name):
            return None
        return tag

    def lex(self, start: int) -> Tag | None:
        """Lex the start tag beginning at byte *start*."""
        data = self.data
        if data[start:start + 1] != b"<":
            return None
        match = _NAME.match(data, start + 1)
        if match is None:
            return None
        name = match.group(0).decode("utf-8")
        name_end = match.end()
        pos = name_end
        attributes: list[Attribute] = []
        while True:
            pos = _SPACE.match(data, pos).end()  # type: ignore[union-attr]
            if data.startswith(b"/>", pos):
                return Tag(name, start, name_end, pos + 2, True, tuple(attributes))
            if data.startswith(b">", pos):
                return Tag(name, start, name_end, pos + 1, False, tuple(attributes))
            attr = _NAME.match(data, pos)
            if attr is None:
                return None
            pos = _SPACE.match(data, attr.end()).end()  # type: ignore[union-attr]
            if not data.startswith(b"=", pos):
                return None
            pos = _SPACE.match(data, pos + 1).end()  # type: ignore[union-attr]
            quote = data[pos:pos + 1]
            if quote not in (b'"', b"'"):
                return None
            close = data.find(quote, pos + 1)
            if close < 0:
                return None
            attributes.append(Attribute(
                attr.group(0).decode("utf-8"), attr.start(), attr.end(), pos + 1, close,
                quote.decode("ascii"), data[pos + 1:close].decode("utf-8"),
            ))
            pos = close + 1

    def element_end(self, tag: Tag) -> int | None:
        """The byte offset just after the element that *tag* starts (its end tag), or ``None``."""
        if tag.self_closing:
            return tag.end
        data = self.data
        depth = 1
        pos = tag.end
        while depth:
            lt = data.find(b"<", pos)
            if lt < 0:
                return None
            for opener, closer in ((b"<!--", b"-->"), (b"<![CDATA[", b"]]>"), (b"<?", b"?>")):
                if data.startswith(opener, lt):
                    stop = data.find(closer, lt + len(opener))
                    if stop < 0:
                        return None
                    pos = stop + len(closer)
                    break
            else:
                if data.startswith(b"</", lt):
                    stop = data.find(b">", lt)
                    if stop < 0:
                        return None
                    depth -= 1
                    pos = stop + 1
                else:
                    inner = self.lex(lt)
                    if inner is None:
                        return None
                    depth += 0 if inner.self_closing else 1
                    pos = inner.end
        return pos

    def end_tag_name(self, tag: Tag, end: int) -> tuple[int, int] | None:
        """The byte range of the name in the end tag of the element *tag* starts, ending at *end*."""
        if tag.self_closing:
            return None
        lt = self.data.rfind(b"</", tag.end, end)
        if lt < 0:
            return None
        match = _NAME.match(self.data, lt + 2)
        return (match.start(), match.end()) if match else None

    def removal(self, start: int, end: int) -> tuple[int, int]:
        """The range to delete to drop ``[start, end)``: with its indentation and line break when
        it stands alone on its lines."""
        data = self.data
        line_start = data.rfind(b"\n", 0, start) + 1
        line_end = data.find(b"\n", end)
        line_end = len(data) if line_end < 0 else line_end
        before = data[line_start:start]
        after = data[end:line_end]
        if before.strip() == b"" and after.strip() == b"":
            stop = line_end + 1 if line_end < len(data) else line_end
            return line_start, stop
        return start, end


def local(name: str) -> str:
    """A tag name without its namespace prefix."""
    return name.rsplit(":", 1)[-1]
