"""Exporters: the model written for other tools (MJCF, URDF, PyBullet URDF, SDF, DOT).

Each target is a module with ``export(robot, out, options) -> ExportResult``
(pure: it returns bytes, it writes nothing); a target that can be verified
has a verifier module beside it (:data:`VERIFIERS`) with
``verify(robot, out, options) -> VerifyResult``, which loads the written
output in the real engine and compares numbers with the source. Verifiers
import their exporter, never the other way round. ``urdftool convert``
and the ``to_*`` functions of the Python API go through :func:`export_model`.
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Mapping
from dataclasses import field
from pathlib import Path
from typing import Any, Protocol

from urdftool.diagnostics import Diagnostic, Severity
from urdftool.model import Robot
from urdftool.records import record

#: target -> module implementing it
TARGETS: dict[str, str] = {
    "mjcf": "urdftool.export.mjcf",
    "urdf": "urdftool.export.urdf",
    "pybullet": "urdftool.export.pybullet",
    "sdf": "urdftool.export.sdf",
    "dot": "urdftool.export.graph",
}

#: target -> module whose ``verify(robot, out, options)`` loads the output in its engine
VERIFIERS: dict[str, str] = {
    "mjcf": "urdftool.export.mjcf_verify",
    "pybullet": "urdftool.export.pybullet_verify",
}

#: output suffix -> target
SUFFIX_TARGETS: dict[str, str] = {
    ".xml": "mjcf",
    ".mjcf": "mjcf",
    ".urdf": "urdf",
    ".sdf": "sdf",
    ".dot": "dot",
    ".gv": "dot",
}


@record
class ExportOptions:
    """Switches shared by the exporters; each reads the ones it understands."""

    #: "auto" | "free" | "fixed"
    floating_base: str = "auto"
    #: "none" | "position" | "velocity" | "motor" | "auto"
    actuators: str = "none"
    repair_inertia: bool = False
    copy_assets: bool = False
    #: MJCF: add a ground plane and a light
    scene: bool = False
    #: reference every mesh by absolute path instead of relative to OUT: source meshes where they
    #: are, files the export writes (converted meshes) under OUT's folder (the Python API without
    #: an output file plans OUT in the mesh cache's ``exports/`` folder and keeps them there)
    absolute_mesh_paths: bool = False
    #: anything target-specific (graph: rankdir, collapse_fixed, ...)
    extra: Mapping[str, Any] = field(default_factory=dict)
    #: the model's findings, for targets that show them (the graph marks links and joints)
    findings: tuple[Diagnostic, ...] = ()
    #: PyBullet: merge links on fixed joints into the links that carry them
    fuse_fixed: bool = False


@record(frozen=False)
class ExportResult:
    """What an exporter produced: files (relative to the output's folder) and findings.

    ``files`` maps a path relative to the folder of OUT to its bytes; OUT itself
    is the key ``out.name``. Nothing is written when ``failed``.
    """

    files: dict[str, bytes] = field(default_factory=dict)
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def failed(self) -> bool:
        return any(d.severity is Severity.ERROR for d in self.diagnostics)


@record(frozen=False)
class VerifyResult:
    """The engine's view of the output compared with the source."""

    ok: bool
    #: rows of (quantity, max error, tolerance, passed) for the printed table
    rows: list[tuple[str, float, float, bool]] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)


class Exporter(Protocol):
    def __call__(self, robot: Robot, out: Path, options: ExportOptions) -> ExportResult: ...


class UnknownTarget(ValueError):
    """No exporter for that target or output suffix."""


def target_for(out: str | os.PathLike[str], to: str | None = None) -> str:
    """The export target named by *to*, else by OUT's suffix."""
    if to:
        if to not in TARGETS:
            raise UnknownTarget(f"unknown target '{to}' (choose from {', '.join(TARGETS)})")
        return to
    suffix = Path(out).suffix.lower()
    if suffix not in SUFFIX_TARGETS:
        raise UnknownTarget(
            f"cannot tell the target from '{suffix or Path(out).name}'; use --to "
            + "|".join(TARGETS)
        )
    return SUFFIX_TARGETS[suffix]


def _module(target: str) -> Any:
    try:
        return importlib.import_module(TARGETS[target])
    except ModuleNotFoundError as exc:
        if exc.name == TARGETS[target]:
            raise UnknownTarget(f"export to {target} is not available in this version") from exc
        raise


def export_model(
    robot: Robot, target: str, out: str | os.PathLike[str], options: ExportOptions
) -> ExportResult:
    """Run the exporter for *target*; returns the files it would write."""
    return _module(target).export(robot, Path(out), options)  # type: ignore[no-any-return]


def verify_model(
    robot: Robot, target: str, out: str | os.PathLike[str], options: ExportOptions
) -> VerifyResult:
    if target not in VERIFIERS:
        raise UnknownTarget(f"--verify is not available for {target}")
    module = importlib.import_module(VERIFIERS[target])
    return module.verify(robot, Path(out), options)  # type: ignore[no-any-return]
