"""The language server's logic without the protocol: check a buffer, place findings on lines,
the hover text for a line, the suppression edit and the fix edits for a finding."""

from __future__ import annotations

import contextlib
import os
import re
import tempfile

from urdftool.catalogue.syntax import InternalError
from urdftool.diagnostics import Applicability, Diagnostic, Fix, Severity
from urdftool.parse import InputError, detect_format
from urdftool.pipeline.check import CheckOptions, check_file
from urdftool.records import record
from urdftool.rules import lookup
from urdftool.rules.docs import rule_markdown

#: an inline suppression comment, as CONTRACTS.md spells it
SUPPRESSION = "<!-- urdftool: ignore[{codes}] -->"
_SUPPRESSION = re.compile(r"^(\s*)<!--\s*urdftool:\s*ignore\[([^\]]*)\]\s*-->\s*$")


@record
class Placed:
    """A finding placed in one document: 0-based line and start/end characters."""

    diagnostic: Diagnostic
    line: int
    start: int
    end: int


def is_checkable(path: str) -> bool:
    return detect_format(path) is not None


def _same(a: str, b: str) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.abspath(a) == os.path.abspath(b)


def _disk_text(path: str) -> str | None:
    try:
        with open(path, encoding="utf-8", newline="") as handle:
            return handle.read()
    except (OSError, UnicodeDecodeError):
        return None


def check_document(path: str, text: str | None, options: CheckOptions) -> list[Diagnostic]:
    """The findings of checking *path* as the editor holds it (*text*; ``None``: as on disk).

    An edited buffer is checked from a hidden temporary copy beside the file, so relative
    includes still resolve; the copy's findings are reported at *path*.
    """
    if text is None or text == _disk_text(path):
        return _check(path, options)
    folder, name = os.path.split(os.path.abspath(path))
    suffix = ".urdf.xacro" if name.endswith(".urdf.xacro") else os.path.splitext(name)[1]
    try:
        fd, copy = tempfile.mkstemp(prefix=f".{name}.", suffix=f".urdftool-lsp{suffix}", dir=folder)
    except OSError:  # a read-only folder: check the copy elsewhere
        fd, copy = tempfile.mkstemp(suffix=suffix)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as handle:
            handle.write(text)
        found = _check(copy, options)
    finally:
        with contextlib.suppress(OSError):
            os.unlink(copy)
    return [_moved(d, copy, path) for d in found]


def _moved(d: Diagnostic, old: str, new: str) -> Diagnostic:
    import dataclasses

    if d.fix is not None and any(_same(e.span.path, old) for e in d.fix.edits):
        edits = tuple(
            dataclasses.replace(e, span=e.span.with_path(new)) if _same(e.span.path, old) else e
            for e in d.fix.edits
        )
        d = dataclasses.replace(d, fix=dataclasses.replace(d.fix, edits=edits))
    if d.location is None or not (d.location.path == old or os.path.abspath(d.location.path) == old):
        return d
    return dataclasses.replace(d, location=d.location.with_path(new),
                               message=d.message.replace(old, new).replace(os.path.basename(old),
                                                                           os.path.basename(new)))


def _check(path: str, options: CheckOptions) -> list[Diagnostic]:
    try:
        reports = check_file(path, options)
    except InputError as exc:
        return [InternalError.diagnostic(str(exc), None)]
    return [d for r in reports for d in r.diagnostics]


def place(diagnostics: list[Diagnostic], path: str, lines: list[str]) -> list[Placed]:
    """Findings located in *path* on their lines (the start tag's name highlighted); findings
    located nowhere, or in no file the editor can show, on the first line."""
    placed = []
    for d in diagnostics:
        loc = d.location
        if loc is not None and loc.line is not None and _same(loc.path, path):
            line = max(0, min(loc.line - 1, max(len(lines) - 1, 0)))
            text = lines[line] if line < len(lines) else ""
            start = max(0, (loc.column or 1) - 1)
            if start > len(text):
                start = 0
            match = re.compile(r"<?[^\s>/]*").match(text, start)
            end = match.end() if match and match.end() > start else len(text.rstrip("\r\n"))
            placed.append(Placed(d, line, start, max(end, start + 1)))
        elif loc is None or loc.line is None or not os.path.exists(loc.path):
            placed.append(Placed(d, 0, 0, 1))
    return placed


def hover_markdown(placed: list[Placed], line: int) -> str | None:
    """The documentation of every rule with a finding on *line* (0-based), or ``None``."""

    pages = []
    for code in dict.fromkeys(p.diagnostic.code for p in placed if p.line == line):
        rule = lookup(code)
        if rule is not None:
            pages.append(rule_markdown(rule))
    return "\n---\n\n".join(pages) if pages else None


@record
class LineEdit:
    """Replace lines [*start*, *end*) (0-based) with *text* (``start == end``: insert)."""

    start: int
    end: int
    text: str


def suppression_edit(lines: list[str], line: int, code: str) -> LineEdit:
    """The edit that silences *code* for the element on *line* (0-based): a new comment line
    before it, indented as the element is, or *code* added to a suppression comment already
    there."""
    if line > 0:
        before = _SUPPRESSION.match(lines[line - 1].rstrip("\r\n"))
        if before is not None:
            codes = [c.strip() for c in before.group(2).split(",") if c.strip()]
            if code in codes:
                return LineEdit(line - 1, line, lines[line - 1])
            ending = lines[line - 1][len(lines[line - 1].rstrip("\r\n")):] or "\n"
            text = before.group(1) + SUPPRESSION.format(codes=",".join([*codes, code])) + ending
            return LineEdit(line - 1, line, text)
    current = lines[line] if line < len(lines) else ""
    indent = current[: len(current) - len(current.lstrip(" \t"))]
    newline = "\r\n" if current.endswith("\r\n") else "\n"
    return LineEdit(line, line, indent + SUPPRESSION.format(codes=code) + newline)


@record
class TextEdit:
    """Replace the text between two LSP positions (0-based line, UTF-16 character) of *path*."""

    path: str
    start: tuple[int, int]
    end: tuple[int, int]
    text: str


def fix_edits(fix: Fix, document: str, buffer: str) -> list[TextEdit] | None:
    """*fix* as editor edits: byte offsets turned into positions in the text the editor holds
    (*buffer* for the open *document*, the file on disk for any other file, such as the
    ``.xacro`` a value was written in). ``None`` when the fix cannot be applied: display-only,
    or an edit without byte offsets."""
    if fix.applicability is Applicability.DISPLAY_ONLY or not fix.edits:
        return None
    out = []
    for edit in fix.edits:
        span = edit.span
        text = buffer if _same(span.path, document) else _disk_text(span.path)
        if text is None or span.offset is None or span.end_offset is None:
            return None
        data = text.encode("utf-8")
        out.append(TextEdit(span.path, _position(data, span.offset), _position(data, span.end_offset),
                            edit.content))
    return out


def _position(data: bytes, offset: int) -> tuple[int, int]:
    """The LSP position of byte *offset*: line, and UTF-16 code units into that line."""
    before = data[: max(0, min(offset, len(data)))].decode("utf-8", errors="replace")
    line = before.count("\n")
    last = before[before.rfind("\n") + 1 :]
    return line, len(last.encode("utf-16-le")) // 2


def severity_rank(severity: Severity) -> int:
    """LSP's DiagnosticSeverity: 1 error, 2 warning, 3 information."""
    return {Severity.ERROR: 1, Severity.WARNING: 2, Severity.INFO: 3}[severity]
