"""Applying fixes: byte edits to the files the user edits, re-checked, written atomically.

``check --fix`` applies every safe fix (``--unsafe-fixes`` the unsafe ones too),
checks again and repeats until nothing more is fixable (at most
:data:`MAX_ROUNDS` rounds), so a second run changes nothing. Edits are applied
by byte offset to the file's own bytes: comments, indentation, attribute order,
quoting and line endings outside the edited ranges stay as they were. A file
whose fixed text would not parse is not written. ``--diff`` computes the same
edits and returns a unified diff instead of writing.
"""

from __future__ import annotations

import difflib
import os
from collections.abc import Iterable, Sequence
from dataclasses import field

from urdftool.diagnostics import Applicability, Diagnostic, Edit, Report
from urdftool.export.write import OutputError, write_bytes_atomic
from urdftool.parse.xmlio import parse_bytes
from urdftool.pipeline.check import CheckOptions, check_files
from urdftool.records import record

#: rounds of fix-and-recheck before giving up (each round applies every non-overlapping edit)
MAX_ROUNDS = 6


def applicable(diagnostic: Diagnostic, unsafe: bool = False) -> bool:
    """True when *diagnostic* has a fix that a run with (or without) ``--unsafe-fixes`` applies."""
    fix = diagnostic.fix
    if fix is None or not fix.edits:
        return False
    if fix.applicability is Applicability.SAFE:
        return True
    return unsafe and fix.applicability is Applicability.UNSAFE


def apply_edits(data: bytes, edits: Iterable[Edit]) -> tuple[bytes, list[Edit]]:
    """*data* with the non-overlapping *edits* applied (by byte offset), and the edits applied.

    An edit that overlaps one already taken is left for the next round; an edit identical to one
    taken (two findings from one macro body) is applied once.
    """
    taken: list[Edit] = []
    seen: set[tuple[int, int, str]] = set()
    for edit in sorted(edits, key=lambda e: (e.span.offset or 0, e.span.end_offset or 0)):
        start, end = edit.span.offset, edit.span.end_offset
        if start is None or end is None or not 0 <= start <= end <= len(data):
            continue
        key = (start, end, edit.content)
        if key in seen:
            continue
        if taken and _overlaps(taken[-1], start, end):
            continue
        seen.add(key)
        taken.append(edit)
    out = data
    for edit in reversed(taken):
        start, end = edit.span.offset or 0, edit.span.end_offset or 0
        out = out[:start] + edit.content.encode("utf-8") + out[end:]
    return out, taken


def _overlaps(previous: Edit, start: int, end: int) -> bool:
    p_start, p_end = previous.span.offset or 0, previous.span.end_offset or 0
    if start < p_end:
        return True
    # two insertions at one point, or an insertion at the edge of a replacement: order unclear
    return start == p_end and (start == end or p_start == p_end)


@record(frozen=False)
class FileChange:
    """One file the fixes changed: its bytes before and after, and the findings fixed."""

    path: str
    before: bytes
    after: bytes
    fixed: list[Diagnostic] = field(default_factory=list)


@record(frozen=False)
class FixResult:
    """What a fix run did: the files changed, the files refused and the report after fixing."""

    changes: dict[str, FileChange]
    refused: list[str]
    report: Report
    rounds: int

    @property
    def fixed(self) -> list[Diagnostic]:
        return [d for change in self.changes.values() for d in change.fixed]

    def diff(self) -> str:
        """A unified diff of every change (paths as given; applies with ``patch -p0`` or
        ``git apply -p0``)."""
        return "".join(unified_diff(c.path, c.before, c.after) for c in self.changes.values()
                       if c.before != c.after)


def _planned(report: Report, unsafe: bool) -> dict[str, list[Diagnostic]]:
    by_file: dict[str, list[Diagnostic]] = {}
    for diagnostic in report.diagnostics:
        if applicable(diagnostic, unsafe) and diagnostic.fix is not None:
            paths = {edit.span.path for edit in diagnostic.fix.edits}
            if len(paths) == 1:
                by_file.setdefault(paths.pop(), []).append(diagnostic)
    return by_file


def _apply_file(path: str, data: bytes, diagnostics: Sequence[Diagnostic]) -> tuple[bytes, list[Diagnostic]]:
    """Apply the fixes of *diagnostics* whose edits all fit; a fix is applied whole or not at all."""
    edits: list[Edit] = []
    fixed: list[Diagnostic] = []
    for diagnostic in diagnostics:
        assert diagnostic.fix is not None
        trial = edits + list(diagnostic.fix.edits)
        _, taken = apply_edits(data, trial)
        if len(taken) == len({(e.span.offset, e.span.end_offset, e.content) for e in trial}):
            edits = trial
            fixed.append(diagnostic)
    out, _ = apply_edits(data, edits)
    return out, fixed


def fix_files(paths: Sequence[str], options: CheckOptions, unsafe: bool = False, write: bool = True,
              jobs: int = 1) -> FixResult:
    """Fix the findings in *paths* (and the files they include) until nothing more is fixable.

    With *write* false nothing is written: one round of edits is computed and returned (for
    ``--diff``). Raises :class:`~urdftool.export.write.OutputError` when a file cannot be written.
    """
    changes: dict[str, FileChange] = {}
    refused: list[str] = []
    report = check_files(paths, options, jobs=jobs)
    rounds = 0
    while rounds < MAX_ROUNDS:
        planned = _planned(report, unsafe)
        planned = {p: d for p, d in planned.items() if p not in refused}
        if not planned:
            break
        rounds += 1
        progressed = False
        for path, diagnostics in planned.items():
            try:
                with open(path, "rb") as handle:
                    data = handle.read()
            except OSError as exc:
                refused.append(path)
                raise OutputError(f"{path}: cannot read: {exc.strerror or exc}") from exc
            after, fixed = _apply_file(path, data, diagnostics)
            if after == data:
                continue
            document, _problems = parse_bytes(after, path, stamp=False, kind="model")
            if document is None:
                refused.append(path)
                continue
            change = changes.setdefault(path, FileChange(path, data, data))
            change.after = after
            change.fixed.extend(fixed)
            progressed = True
            if write:
                write_bytes_atomic(path, after)
        if not write or not progressed:
            break
        report = check_files(paths, options, jobs=jobs)
    return FixResult(changes, refused, report, rounds)


def unified_diff(path: str, before: bytes, after: bytes, context: int = 3) -> str:
    """A unified diff of one file's bytes (UTF-8), marking a last line without a line break."""
    old, new = _lines(before.decode("utf-8")), _lines(after.decode("utf-8"))
    name = diff_path(path)
    out = []
    for line in difflib.unified_diff(old, new, name, name, n=context):
        if line.startswith(("---", "+++")):
            out.append(line.rstrip("\n") + "\n")
        elif not line.endswith("\n"):
            out.append(line + "\n\\ No newline at end of file\n")
        else:
            out.append(line)
    return "".join(out)


def _lines(text: str) -> list[str]:
    """Lines split at ``\n`` only (a ``\r`` stays on its line, as patch expects)."""
    lines = [line + "\n" for line in text.split("\n")]
    lines[-1] = lines[-1][:-1]
    return lines if lines[-1] else lines[:-1]


def diff_path(path: str) -> str:
    """*path* as a diff names it: relative to the working folder when inside it, without ``./``."""
    relative = os.path.relpath(path)
    if relative.startswith(os.pardir + os.sep) or relative == os.pardir:
        return os.path.normpath(path)
    return relative.replace(os.sep, "/")
