"""Inline suppressions: ``<!-- urdftool: ignore[CODE,name] -->`` comments in the files the user edits.

A comment on an element's line, or alone on the line before it, silences
those rules' findings located on that line; ``<!-- urdftool:
ignore-file[CODE] -->`` anywhere silences them for the whole file. Findings
point at the file and line where an element was written, so a comment in a
``.xacro`` file also silences every element expanded from that line (a macro
body line covers every call of the macro). A suppression that silences
nothing is reported as ``unused-suppression``, as ruff reports an unused
``# noqa``.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from dataclasses import field

from urdftool.catalogue.syntax import UnusedSuppression
from urdftool.diagnostics import Diagnostic
from urdftool.records import record
from urdftool.rules import Selection, lookup
from urdftool.rules.selection import suggestion
from urdftool.safe_files import read_up_to
from urdftool.source import Span

#: ``<!-- urdftool: ignore[S009, unknown-attribute] -->`` and ``ignore-file[...]``
COMMENT = re.compile(r"<!--\s*urdftool:\s*(ignore|ignore-file)\s*\[([^\]]*)\]\s*-->")
#: Files larger than this are not scanned for suppressions (the readers' caps apply anyway).
MAX_SCAN_BYTES = 64 * 1024 * 1024


@record(frozen=False, eq=False)  # one run's state, equal only to itself
class Suppression:
    """One comment: where it is, whether it covers the file, and the codes or names it lists."""

    span: Span
    whole_file: bool
    selectors: tuple[str, ...]
    #: selectors that silenced at least one finding
    used: set[str] = field(default_factory=set)

    def covers(self, line: int | None) -> bool:
        return self.whole_file or (line is not None and line in (self.span.line, (self.span.line or 0) + 1))


def scan(path: str) -> list[Suppression]:
    """The suppression comments in the file at *path* (none when it cannot be read)."""
    try:
        data = read_up_to(path, "model", cap=MAX_SCAN_BYTES)  # a regular file: never a FIFO's wait
    except OSError:
        return []
    if b"urdftool:" not in data:  # most files have no comment: skip decoding them (ASCII in UTF-8)
        return []
    text = data.decode("utf-8", errors="replace")
    found = []
    for number, line in enumerate(text.splitlines(), 1):
        for match in COMMENT.finditer(line):
            selectors = tuple(s.strip() for s in match.group(2).split(",") if s.strip())
            found.append(Suppression(Span(path, number, match.start() + 1), match.group(1) == "ignore-file",
                                     selectors))
    return found


def _matches(selector: str, diagnostic: Diagnostic) -> bool:
    return selector.upper() == diagnostic.code or selector.lower() == diagnostic.name


def apply(diagnostics: Sequence[Diagnostic], files: Iterable[str], selection: Selection) -> list[Diagnostic]:
    """*diagnostics* less those a comment in *files* silences, plus one finding per unused selector.

    A selector counts as unused only when its rule ran (is selected): a suppression of a rule
    switched off elsewhere is not wrong. An unknown code or name is always reported.
    """
    return apply_to_models([diagnostics], files, selection)[0]


def apply_to_models(reports: Sequence[Sequence[Diagnostic]], files: Iterable[str],
                    selection: Selection) -> list[list[Diagnostic]]:
    """:func:`apply` for the models of one file (an SDF world) at once: a comment is unused
    only when no model's finding used it, and each file is scanned once. The unused-suppression
    findings go with the first model, as the file's own findings do."""
    by_file: dict[str, list[Suppression]] = {}
    for path in dict.fromkeys(files):
        found = scan(path)
        if found:
            by_file[path] = found
    if not by_file:
        return [list(r) for r in reports]
    out = [_silence(r, by_file) for r in reports]
    if out:
        out[0].extend(_unused(by_file, selection, [d for kept in out for d in kept]))
    return out


def _silence(diagnostics: Sequence[Diagnostic], by_file: dict[str, list[Suppression]]) -> list[Diagnostic]:
    """*diagnostics* less those a comment silences; each comment records the selectors it used."""
    kept = []
    for diagnostic in diagnostics:
        location = diagnostic.location
        silenced = False
        for suppression in by_file.get(location.path, []) if location else []:
            if not suppression.covers(location.line if location else None):
                continue
            for selector in suppression.selectors:
                if _matches(selector, diagnostic):
                    suppression.used.add(selector)
                    silenced = True
        if not silenced:
            kept.append(diagnostic)
    return kept


#: how far (lines) from an unused comment a finding of its rule may be to be pointed at
NEAREST_LINES = 30
_REMOVE = "remove it from the comment (or the comment, when nothing is left)"


def _nearest_help(suppression: Suppression, code: str, kept: Sequence[Diagnostic]) -> str:
    """Where the finding the comment probably meant is (a comment above ``<inertial>`` misses
    the finding on ``<inertia>``), or the advice to remove the selector."""
    line = suppression.span.line or 0
    near = [(abs(d.location.line - line), d.location.line, d) for d in kept
            if d.code == code and d.location is not None and d.location.path == suppression.span.path
            and d.location.line is not None and abs(d.location.line - line) <= NEAREST_LINES]
    if suppression.whole_file or not near:
        return _REMOVE
    _, at, diagnostic = min(near, key=lambda item: item[:2])
    what = f" ({diagnostic.element})" if diagnostic.element else ""
    return (f"the nearest {code} finding is on line {at}{what}: put the comment on that line or alone "
            f"on the line before it")


def _unused(by_file: dict[str, list[Suppression]], selection: Selection,
            kept: Sequence[Diagnostic]) -> Iterable[Diagnostic]:
    if not selection.enabled(UnusedSuppression):
        return
    for suppressions in by_file.values():
        for suppression in suppressions:
            for selector in suppression.selectors:
                if selector in suppression.used:
                    continue
                rule = lookup(selector)
                if rule is None:
                    why = f"'{selector}' is no rule code or name{suggestion(selector)}"
                    advice = _REMOVE
                elif not selection.enabled(rule):
                    continue
                else:
                    why = f"no {rule.code} ({rule.name}) finding is on {_scope(suppression)}"
                    advice = _nearest_help(suppression, rule.code, kept)
                yield UnusedSuppression.diagnostic(
                    f"unused suppression: {why}",
                    suppression.span,
                    help=advice,
                    data={"selector": selector, "file_level": suppression.whole_file},
                )


def _scope(suppression: Suppression) -> str:
    if suppression.whole_file:
        return "this file"
    return f"line {suppression.span.line} or {(suppression.span.line or 0) + 1}"
