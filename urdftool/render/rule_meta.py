"""What the machine-readable formats say about a rule and a location: the rule's name,
summary, default severity and documentation page, and paths relative to the working folder."""

from __future__ import annotations

import os
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from urdftool.diagnostics import Diagnostic, Report, Severity
from urdftool.lazy import LazyModule
from urdftool.records import record
from urdftool.rules.registry import info
from urdftool.source import Span

if TYPE_CHECKING:
    import hashlib
else:  # OpenSSL's hashes load in ~4 ms; only the fingerprinting formats (SARIF, GitLab) need them
    hashlib = LazyModule("hashlib")

#: the project's home; rule pages live under ``docs/rules/`` there
PROJECT_URL = "https://github.com/urdftool/urdftool"
#: where the rule pages are browsed (``<DOCS_URL>/<CODE>.md``)
RULE_DOCS_URL = f"{PROJECT_URL}/blob/main/docs/rules"


@record
class RuleMeta:
    """A rule as the reports describe it."""

    code: str
    name: str
    summary: str
    severity: Severity
    help_uri: str


def rule_help_uri(code: str) -> str:
    return f"{RULE_DOCS_URL}/{code}.md"


def rule_meta(diagnostic: Diagnostic) -> RuleMeta:
    """The registered rule behind *diagnostic*, or what the diagnostic itself says when the
    code is not in the catalogue."""
    rule = info(diagnostic.code)  # the generated table: no rule module is imported to describe one
    if rule is None:
        return RuleMeta(diagnostic.code, diagnostic.name, diagnostic.name.replace("-", " "),
                        diagnostic.severity, rule_help_uri(diagnostic.code))
    return RuleMeta(rule.code, rule.name, rule.summary, rule.severity, rule_help_uri(rule.code))


def relative_path(path: str) -> str:
    """*path* relative to the working folder with ``/`` separators when it lies below it,
    else absolute."""
    absolute = os.path.abspath(path)
    try:
        rel = os.path.relpath(absolute)
    except ValueError:  # another drive on Windows
        return absolute.replace(os.sep, "/")
    if rel == os.pardir or rel.startswith(os.pardir + os.sep):
        return absolute.replace(os.sep, "/")
    return rel.replace(os.sep, "/")


def end_of(span: Span) -> tuple[int | None, int | None]:
    """End line and column of *span* where the span knows them."""
    end_line: Any = getattr(span, "end_line", None)
    end_column: Any = getattr(span, "end_column", None)
    return (end_line if isinstance(end_line, int) else None,
            end_column if isinstance(end_column, int) else None)


def related_spans(diagnostic: Diagnostic) -> Iterator[tuple[Span, str]]:
    """Secondary locations of *diagnostic* with their labels, when it carries any
    (``related``: spans, ``(span, label)`` pairs or objects with ``span``/``location`` and
    ``label``/``message``)."""
    related: Any = getattr(diagnostic, "related", None) or ()
    for item in related:
        span: Any
        label: Any
        if isinstance(item, Span):
            span, label = item, ""
        elif isinstance(item, tuple) and len(item) == 2:
            span, label = item
            if isinstance(label, Span):
                span, label = label, span
        else:
            span = getattr(item, "span", None) or getattr(item, "location", None)
            label = getattr(item, "label", None) or getattr(item, "message", None) or ""
        if isinstance(span, Span):
            yield span, str(label)


def fingerprint(diagnostic: Diagnostic, path: str, occurrence: int = 0, robot: str | None = None) -> str:
    """A stable identity for a finding that does not move with line numbers: the file (and the
    model, for files with several), the rule, the element and the message (and which repeat it is
    of an identical finding)."""
    parts = [relative_path(path), robot or "", diagnostic.code, diagnostic.element or "",
             diagnostic.message, str(occurrence)]
    return hashlib.sha256("\x1f".join(parts).encode("utf-8")).hexdigest()


def fingerprints(diagnostics: tuple[Diagnostic, ...], path: str, robot: str | None = None) -> list[str]:
    """:func:`fingerprint` of each diagnostic, identical findings told apart by their order."""
    seen: dict[tuple[str, str, str], int] = {}
    out = []
    for d in diagnostics:
        key = (d.code, d.element or "", d.message)
        count = seen.get(key, 0)
        seen[key] = count + 1
        out.append(fingerprint(d, path, count, robot))
    return out


def models_note(report: Report) -> str:
    """``" (3 models)"`` when a checked file held several models (an SDF world): the report
    has one entry per model, and "3 files checked" for one world file would be wrong."""
    return f" ({len(report.files)} models)" if len(report.files) > files_checked(report) else ""


def files_checked(report: Report) -> int:
    """How many files the report covers (a world with several models is one file)."""
    return len({f.path for f in report.files})

