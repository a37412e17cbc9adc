"""Diagnostics are data: what rule fired, where, why, and the numbers behind it."""

from __future__ import annotations

import enum
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from urdftool.source import Span


class Severity(str, enum.Enum):
    """How bad a finding is; ``error`` fails ``check``, ``warning`` fails with ``--strict``."""

    ERROR = "error"
    WARNING = "warning"
    INFO = "info"

    @property
    def rank(self) -> int:
        return {"error": 2, "warning": 1, "info": 0}[self.value]


@dataclass(frozen=True)
class Diagnostic:
    """One finding.

    ``element`` is a path in the robot's terms (``link[forearm]/inertial``);
    ``data`` holds the numbers behind the message for tools to use.
    """

    code: str
    name: str
    severity: Severity
    message: str
    location: Span | None = None
    element: str | None = None
    help: str | None = None
    data: Mapping[str, Any] = field(default_factory=dict)

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
        loc = self.location
        return {
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


@dataclass(frozen=True)
class FileReport:
    """The findings for one model read from one file."""

    path: str
    format: str
    robot: str | None
    diagnostics: tuple[Diagnostic, ...]

    def to_json(self) -> dict[str, Any]:
        return {
            "path": self.path,
            "format": self.format,
            "robot": self.robot,
            "diagnostics": [d.to_json() for d in self.diagnostics],
        }


def _count(diagnostics: Iterable[Diagnostic], severity: Severity) -> int:
    return sum(1 for d in diagnostics if d.severity is severity)


@dataclass(frozen=True)
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
