"""Diagnostics are data: what rule fired, where, why, and the numbers behind it."""

from __future__ import annotations

import enum
from collections.abc import Iterable, Mapping
from dataclasses import field
from typing import Any

from urdftool.records import record
from urdftool.source import Span, is_deferred, settled


class Severity(str, enum.Enum):
    """How bad a finding is; ``error`` fails ``check``, ``warning`` fails with ``--strict``."""

    ERROR = "error"
    WARNING = "warning"
    INFO = "info"

    @property
    def rank(self) -> int:
        return {"error": 2, "warning": 1, "info": 0}[self.value]


class Applicability(str, enum.Enum):
    """How safe a fix is to apply without review (as in ruff and rustc)."""

    #: cannot change what a consumer computes, or restores what the author evidently meant
    SAFE = "safe"
    #: changes physics or meaning: applied only with ``--unsafe-fixes``
    UNSAFE = "unsafe"
    #: shown, never applied (the value comes from an expression or is shared)
    DISPLAY_ONLY = "display-only"


@record
class Edit:
    """Replace the text of ``span`` (byte offsets required) with ``content``."""

    span: Span
    content: str

    def to_json(self) -> dict[str, Any]:
        return {"location": self.span.to_json(), "content": self.content}


@record
class Fix:
    """A repair of a finding: edits to the file the user edits, with how safe they are."""

    message: str
    edits: tuple[Edit, ...]
    applicability: Applicability = Applicability.SAFE

    def to_json(self) -> dict[str, Any]:
        return {"message": self.message, "applicability": self.applicability.value,
                "edits": [e.to_json() for e in self.edits]}


@record
class Related:
    """A secondary location of a finding: the other duplicate, the macro call, the property's line."""

    span: Span
    label: str

    def to_json(self) -> dict[str, Any]:
        return {"location": self.span.to_json(), "label": self.label}


@record
class Diagnostic:
    """One finding.

    ``element`` is a path in the robot's terms (``link[forearm]/inertial``);
    ``data`` holds the numbers behind the message for tools to use;
    ``related`` are secondary locations and ``fix`` an optional repair.
    """

    code: str
    name: str
    severity: Severity
    message: str
    location: Span | None = None
    element: str | None = None
    help: str | None = None
    data: Mapping[str, Any] = field(default_factory=dict)
    related: tuple[Related, ...] = ()
    fix: Fix | None = None

    def detached(self) -> Diagnostic:
        """This finding with plain spans (:func:`~urdftool.source.settled`): a finding that
        outlives its check holds no document of the model."""
        location, related, fix = self.location, self.related, self.fix
        moved = False
        if location is not None and is_deferred(location):
            location, moved = settled(location), True
        if related and any(is_deferred(r.span) for r in related):
            related, moved = tuple(Related(settled(r.span), r.label) for r in related), True
        if fix is not None and any(is_deferred(e.span) for e in fix.edits):
            edits = tuple(Edit(settled(e.span), e.content) for e in fix.edits)
            fix, moved = Fix(fix.message, edits, fix.applicability), True
        if not moved:
            return self
        # Built field by field, not by dataclasses.replace: a fifth of its cost, for every finding
        # of every check. tests/test_report_lifetime.py fails when a field is added to the record
        # and not here, so that none is dropped.
        return Diagnostic(self.code, self.name, self.severity, self.message, location, self.element,
                          self.help, self.data, related, fix)

    def sort_key(self) -> tuple[str, int, int, str, str]:
        loc = self.location
        return (
            loc.path if loc else "",
            (loc.line or 0) if loc else 0,
            (loc.column or 0) if loc else 0,
            self.code,
            self.message,
        )

    def to_json(self) -> dict[str, Any]:
        """The contract's diagnostic; ``related`` and ``fix`` appear only when present."""
        loc = self.location
        out: dict[str, Any] = {
            "code": self.code,
            "name": self.name,
            "severity": self.severity.value,
            "message": self.message,
            "location": (
                {"path": loc.path, "line": loc.line, "column": loc.column} if loc else None
            ),
            "element": self.element,
            "help": self.help,
            "data": dict(self.data),
        }
        if self.related:
            out["related"] = [r.to_json() for r in self.related]
        if self.fix is not None:
            out["fix"] = self.fix.to_json()
        return out


@record
class FileReport:
    """The findings for one model read from one file."""

    path: str
    format: str
    robot: str | None
    diagnostics: tuple[Diagnostic, ...]
    #: the MoveIt SRDF read beside the model and checked with it, if any
    srdf: str | None = None
    #: the ros2_control controllers YAML files read for the model
    controllers: tuple[str, ...] = ()

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "path": self.path,
            "format": self.format,
            "robot": self.robot,
            "diagnostics": [d.to_json() for d in self.diagnostics],
        }
        # Written only when read, so a report of a model checked alone keeps its old shape.
        if self.srdf is not None:
            out["srdf"] = self.srdf
        if self.controllers:
            out["controllers"] = list(self.controllers)
        return out

    def read_with(self) -> list[tuple[str, str]]:
        """``(kind, path)`` of every file read beside the model to check it: its SRDF, then its
        controllers files."""
        out = [("SRDF", self.srdf)] if self.srdf is not None else []
        return out + [("controllers", path) for path in self.controllers]


def _count(diagnostics: Iterable[Diagnostic], severity: Severity) -> int:
    return sum(1 for d in diagnostics if d.severity is severity)


@record
class Report:
    """The result of checking one or more models."""

    files: tuple[FileReport, ...]

    @property
    def diagnostics(self) -> tuple[Diagnostic, ...]:
        return tuple(d for f in self.files for d in f.diagnostics)

    @property
    def errors(self) -> tuple[Diagnostic, ...]:
        return tuple(d for d in self.diagnostics if d.severity is Severity.ERROR)

    @property
    def warnings(self) -> tuple[Diagnostic, ...]:
        return tuple(d for d in self.diagnostics if d.severity is Severity.WARNING)

    @property
    def ok(self) -> bool:
        """True when nothing is at error severity."""
        return not self.errors

    def failed(self, strict: bool = False) -> bool:
        """True when the report should fail a CI gate (warnings too with *strict*)."""
        return bool(self.errors or (strict and self.warnings))

    def summary(self) -> dict[str, int]:
        diags = self.diagnostics
        return {
            "files": len(self.files),
            "errors": _count(diags, Severity.ERROR),
            "warnings": _count(diags, Severity.WARNING),
            "infos": _count(diags, Severity.INFO),
        }
