"""Baselines: accept today's findings, fail only on new ones (as mypy and pyright baselines do).

``check --write-baseline FILE`` records every finding as a fingerprint that
does not depend on line numbers or formatting: the rule code, the file
(relative to the baseline's folder), the element in the robot's terms
(``link[forearm]/inertial``) and the message with its numbers blanked. The
same finding moved ten lines down, or in a re-indented file, keeps its
fingerprint; a changed value or a renamed link is a new finding.
``check --baseline FILE`` drops the findings the baseline knows (each
fingerprint as many times as it was recorded) and counts the recorded ones
that are gone, so the baseline can be shrunk.
"""

from __future__ import annotations

import dataclasses
import json
import os
import re
from collections import Counter
from collections.abc import Iterable
from pathlib import Path

from urdftool.diagnostics import Diagnostic, Report
from urdftool.export.write import write_text_atomic
from urdftool.records import record

FORMAT_VERSION = 1
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


class BaselineError(ValueError):
    """A baseline file that cannot be read."""


def message_key(message: str) -> str:
    """*message* with every number replaced by ``#``: a finding whose values drift keeps its key."""
    return _NUMBER.sub("#", " ".join(message.split()))


def fingerprint(diagnostic: Diagnostic, report_path: str, base: Path) -> str:
    """Code, file relative to *base*, element and message key, joined by ``|``."""
    where = diagnostic.location.path if diagnostic.location else report_path
    return "|".join((diagnostic.code, _relative(where, base), diagnostic.element or "",
                     message_key(diagnostic.message)))


def _relative(path: str, base: Path) -> str:
    try:
        return Path(os.path.abspath(path)).relative_to(base.resolve()).as_posix()
    except ValueError:
        return Path(path).name


def fingerprints(report: Report, base: Path) -> Counter[str]:
    return Counter(fingerprint(d, f.path, base) for f in report.files for d in f.diagnostics)


def write_baseline(report: Report, path: str | os.PathLike[str], inputs: Iterable[str] = ()) -> int:
    """Record every finding of *report* in the baseline at *path*; returns how many."""
    base = Path(path).resolve().parent
    counted = fingerprints(report, base)
    document = {
        "urdftool-baseline": FORMAT_VERSION,
        "findings": [{"fingerprint": key, "count": count} for key, count in sorted(counted.items())],
    }
    write_text_atomic(path, json.dumps(document, indent=1) + "\n", inputs=list(inputs))
    return sum(counted.values())


def read_baseline(path: str | os.PathLike[str]) -> Counter[str]:
    """The fingerprints recorded in *path*. Raises :class:`BaselineError`."""
    try:
        document = json.loads(Path(path).read_text(encoding="utf-8"))
        if document.get("urdftool-baseline") != FORMAT_VERSION:
            raise BaselineError(f"{path}: not an urdftool baseline (version {FORMAT_VERSION})")
        return Counter({row["fingerprint"]: int(row["count"]) for row in document["findings"]})
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
        if isinstance(exc, BaselineError):
            raise
        raise BaselineError(f"{path}: cannot read the baseline: {exc}") from exc


@record
class BaselineResult:
    """The report without the known findings, and how many known ones were matched or are gone."""

    report: Report
    known: int
    fixed: int


def apply_baseline(report: Report, baseline: Counter[str], path: str | os.PathLike[str]) -> BaselineResult:
    """Drop from *report* the findings *baseline* (read from *path*) knows."""
    base = Path(path).resolve().parent
    remaining = Counter(baseline)
    files = []
    known = 0
    checked: set[str] = set()
    for file_report in report.files:
        kept = []
        for diagnostic in file_report.diagnostics:
            key = fingerprint(diagnostic, file_report.path, base)
            checked.add(key.split("|")[1])
            if remaining[key] > 0:
                remaining[key] -= 1
                known += 1
            else:
                kept.append(diagnostic)
        files.append(dataclasses.replace(file_report, diagnostics=tuple(kept)))
        checked.add(_relative(file_report.path, base))
    # Only findings of files this run checked can have been fixed; the others were not looked at.
    fixed = sum(n for key, n in remaining.items() if key.split("|")[1] in checked)
    return BaselineResult(Report(tuple(files)), known, fixed)
