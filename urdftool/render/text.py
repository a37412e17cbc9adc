"""Compiler-style text: ``path:line:col: severity[CODE name] message``, an excerpt, ``note:``
for each related location, ``help:``."""

from __future__ import annotations

import os
import re
from collections.abc import Iterable

from urdftool.diagnostics import Diagnostic, Report, Severity
from urdftool.render.rule_meta import files_checked, models_note
from urdftool.source import SourceIndex

_COLOURS = {Severity.ERROR: "\x1b[31;1m", Severity.WARNING: "\x1b[33;1m", Severity.INFO: "\x1b[36;1m"}
_RESET = "\x1b[0m"
_BOLD = "\x1b[1m"


def display_path(path: str) -> str:
    """*path* relative to the working directory when it lies below it."""
    try:
        rel = os.path.relpath(path)
    except ValueError:
        return path
    return path if rel.startswith("..") else rel


def render_diagnostic(d: Diagnostic, sources: SourceIndex, colour: bool = False, excerpt: bool = True) -> str:
    sev = d.severity.value
    if colour:
        sev = f"{_COLOURS[d.severity]}{sev}{_RESET}"
    where = "" if d.location is None else f"{display_path(str(d.location))}: "
    if colour and where:
        where = f"{_BOLD}{where}{_RESET}"
    lines = [f"{where}{sev}[{d.code} {d.name}] {d.message}"]
    if excerpt and d.location is not None and d.location.line is not None:
        text = sources.line_text(d.location)
        if text is not None:
            lines.extend(_excerpt(text, d.location.line, d.location.column))
    for related in d.related:
        lines.append(f"  note: {related.label} at {display_path(str(related.span))}")
    if d.help:
        lines.append(f"  help: {d.help}")
    return "\n".join(lines)


def read_with(report: Report) -> str:
    """The files read beside the models (SRDF, controllers YAML) and checked with them, named when
    they are few and counted when many: a check that used an SRDF the user did not name says so
    (one beside the model is read unless ``--no-srdf``)."""
    pairs = [(f.path, kind, path) for f in report.files for kind, path in f.read_with()]
    if not pairs:
        return ""
    files = files_checked(report)
    if len(pairs) <= _NAMED:
        return "\n".join(f"also read: {display_path(path)} ({kind}"
                         + (f" of {display_path(model)})" if files > 1 else ")")
                         for model, kind, path in pairs)
    kinds = {kind: len({model for model, k, _ in pairs if k == kind}) for _, kind, _ in pairs}
    counted = ", ".join(f"the {kind} of {count}" for kind, count in kinds.items())
    return f"also read: {counted} of the {files} files (--format json names each)"


#: companion files named one by one up to this many; more are counted
_NAMED = 3


#: excerpts are cut to this many characters around the column
EXCERPT_WIDTH = 120
_CONTROL = re.compile(r"[\x00-\x08\x0b-\x1f\x7f]")


def _excerpt(text: str, line: int, column: int | None) -> list[str]:
    """The source line (control characters shown as '?', long lines cut around the
    column) and a caret under the column."""
    raw = text.rstrip()
    caret = None
    if column is not None and column <= len(raw) + 1:
        caret = len(raw[: column - 1].expandtabs(4))
    text = _CONTROL.sub("?", raw.expandtabs(4))
    start = 0
    if len(text) > EXCERPT_WIDTH:
        start = max(0, min((caret or 0) - EXCERPT_WIDTH // 2, len(text) - EXCERPT_WIDTH))
        text = ("…" if start else "") + text[start : start + EXCERPT_WIDTH] + (
            "…" if start + EXCERPT_WIDTH < len(text) else ""
        )
    gutter = f"{line:>5} | "
    out = [gutter + text]
    if caret is not None:
        offset = caret - start + (1 if start else 0)
        out.append(" " * (len(gutter) - 2) + "| " + " " * offset + "^")
    return out


def render_text(report: Report, colour: bool = False, quiet: bool = False) -> str:
    """The whole report as text; *quiet* prints only the summary line and errors."""
    sources = SourceIndex()
    chunks: list[str] = []
    for file_report in report.files:
        diags: Iterable[Diagnostic] = file_report.diagnostics
        if quiet:
            diags = [d for d in diags if d.severity is Severity.ERROR]
        chunks.extend(render_diagnostic(d, sources, colour) for d in diags)
    if not quiet and (read := read_with(report)):
        chunks.append(read)
    summary = report.summary()
    files = files_checked(report)
    noun = "file" if files == 1 else "files"
    chunks.append(
        f"{files} {noun} checked{models_note(report)}: {summary['errors']} error(s), "
        f"{summary['warnings']} warning(s), {summary['infos']} info"
    )
    return "\n\n".join(chunks) + "\n"
