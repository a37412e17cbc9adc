"""From a model to exported files: one path for ``urdftool convert``, the ``to_*`` API and ``sim``.

Every caller goes through :func:`convert_robot`, so they refuse the same
models with the same findings: a model read with structural errors (``S``,
``X``) is not exported; a kinematic model (no ``<inertial>`` anywhere) is not
exported to a simulator without ``--repair-inertia``, with one finding; and
an exporter's own errors (invalid inertia without repair, a joint the target
cannot hold) refuse it too. :func:`write_conversion`
writes the files atomically, never over an input.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Sequence
from dataclasses import field
from pathlib import Path

from urdftool.backends.mesh_cache import export_folder, store_export_file
from urdftool.catalogue.conversion import InertiaNotExportable, SdfDefaultInertia
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.export import ExportOptions, export_model
from urdftool.export.graph import GraphOptions
from urdftool.export.write import guard_inputs, write_bytes_atomic
from urdftool.model import Robot
from urdftool.physics.bodies import kinematics_only
from urdftool.physics.sdf_defaults import SDF_DEFAULT_INERTIAL, defaulted_links, sdf_default_inertials
from urdftool.pipeline.check import run_rules
from urdftool.records import record
from urdftool.rules import Selection

#: Targets that simulate the model, which a kinematic model (no inertia at all) cannot be.
SIMULATED = {"mjcf": "MuJoCo", "pybullet": "PyBullet"}

#: What must be clean before a model is exported: it was read and expanded correctly.
STRUCTURAL = Selection.of(("S", "X"), ())


@record(frozen=False)
class Conversion:
    """What converting one robot to one target gave.

    ``files`` maps paths relative to the output's folder to their bytes (the
    output itself under its own name); nothing is in it when ``refused``.
    ``diagnostics`` are the findings that refused it, or the exporter's report
    of what it dropped or changed.
    """

    robot: Robot
    target: str
    out: Path
    files: dict[str, bytes] = field(default_factory=dict)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    refused: bool = False
    #: every file the model was read from (never to be written over)
    inputs: list[str] = field(default_factory=list)

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity is Severity.ERROR]

    @property
    def text(self) -> str:
        """The main output as text."""
        return self.files[self.out.name].decode("utf-8")


def structural_errors(robot: Robot) -> list[Diagnostic]:
    """Errors that mean the model was not read faithfully, so no export can be faithful."""
    return [d for d in run_rules(robot, STRUCTURAL) if d.severity is Severity.ERROR]


def graph_findings(robot: Robot, options: GraphOptions) -> list[Diagnostic]:
    """The findings a diagram marks (none with ``diagnostics=False``).

    A diagram runs no simulation: the runtime family (``R``) is off unless
    selected. Raises :class:`~urdftool.rules.UnknownSelector` for a bad selector.
    """
    if not options.diagnostics:
        return []
    ignore = options.ignore if options.select is not None else ("R", *options.ignore)
    return run_rules(robot, Selection.of(options.select, ignore))


def convert_robot(
    robot: Robot,
    target: str,
    out: str | os.PathLike[str],
    options: ExportOptions,
    inputs: Sequence[str] = (),
) -> Conversion:
    """Export *robot* to *target* as if written to *out*; nothing is written here.

    Raises :class:`~urdftool.export.UnknownTarget` for a target with no exporter.
    """
    where = Path(out)
    sources = list(inputs) or ([robot.path] if robot.path else [])
    structural = structural_errors(robot)
    if structural:
        return Conversion(robot, target, where, diagnostics=structural, refused=True, inputs=sources)
    defaulted: list[Diagnostic] = []
    if target in WRITES_SDF_DEFAULTS:
        robot, defaulted = _sdf_defaults_written(robot, target)
    if target in SIMULATED and not options.repair_inertia and kinematics_only(robot):
        refusal = InertiaNotExportable.diagnostic(
            f"robot '{robot.name}' has no <inertial> in any link (a kinematic model); "
            f"{SIMULATED[target]} needs the mass and inertia of every moving link",
            robot.span,
            element="robot",
            help="add <inertial> to the links, or export with --repair-inertia for a minimal stand-in "
            "(each change is reported)",
            data={"reason": "kinematics-only"},
        )
        return Conversion(robot, target, where, diagnostics=[refusal], refused=True, inputs=sources)
    if target == "dot":
        graph = GraphOptions.of(options.extra)
        options = dataclasses.replace(options, findings=tuple(graph_findings(robot, graph)))
    result = export_model(robot, target, where, options)
    diagnostics = distinct([*defaulted, *result.diagnostics])
    if result.failed:
        return Conversion(robot, target, where, diagnostics=diagnostics, refused=True, inputs=sources)
    return Conversion(robot, target, where, result.files, diagnostics, inputs=sources)


#: Targets whose format has no default inertial of its own: an SDF link without ``<inertial>``
#: is written with SDFormat's (1 kg, unit inertia), so the export weighs what gz-sim weighs.
WRITES_SDF_DEFAULTS = frozenset({"mjcf", "pybullet", "urdf"})


def _sdf_defaults_written(robot: Robot, target: str) -> tuple[Robot, list[Diagnostic]]:
    """*robot* with SDFormat's default inertial written on each SDF link that has none, and an
    info per link saying so."""
    notes = [
        SdfDefaultInertia.diagnostic(
            f"link '{link.name}' has no <inertial>: written for {target} with SDFormat's default, "
            "1 kg and 1 kg·m² about each axis, which gz-sim and Gazebo give it",
            link.span, element=f"link[{link.name}]", severity=Severity.INFO,
            data={"link": link.name, "mass": SDF_DEFAULT_INERTIAL.mass, "reason": "sdf-default"},
        )
        for link in defaulted_links(robot)
    ]
    return sdf_default_inertials(robot), notes


#: Targets whose text refers to files written beside it (meshes converted for the engine).
WRITES_ASSETS = frozenset({"mjcf", "pybullet"})


def unwritten_output(name: str, target: str) -> Path:
    """Where an export that is not written (the Python API without *out*) is planned: in the
    mesh cache's export folder for a target that may need converted meshes, whose files are kept
    there and referred to by absolute path (:func:`keep_assets`); else *name* in the working
    directory (nothing is written)."""
    folder = export_folder() if target in WRITES_ASSETS else None
    return (folder or Path.cwd()) / name


def keep_assets(conversion: Conversion) -> str | None:
    """Write the files the text of an unwritten export refers to (converted meshes) into the
    mesh cache's export folder, where :func:`unwritten_output` planned them; ``None`` when they
    are there (or there are none), else why they are not."""
    assets = {rel: data for rel, data in conversion.files.items() if rel != conversion.out.name}
    if not assets:
        return None
    folder = export_folder()
    if folder is None or conversion.out.parent != folder:
        return "the mesh cache is off (URDFTOOL_NO_CACHE), so there is no folder to write them to"
    failed = [rel for rel, data in sorted(assets.items()) if not store_export_file(folder, rel, data)]
    return f"{folder / failed[0]} cannot be written" if failed else None


def distinct(diagnostics: Sequence[Diagnostic]) -> list[Diagnostic]:
    """*diagnostics* without repeats: the first of those with the same code, message, element
    and location. A xacro macro called three times for one joint (franka_description's
    ``gazebo-joint``, once per transmission type) writes three identical ``<gazebo>`` blocks;
    the user wrote one line, and three identical findings on it say nothing more."""
    seen: set[tuple[str, str, str | None, str]] = set()
    out = []
    for d in diagnostics:
        key = (d.code, d.message, d.element, str(d.location))
        if key not in seen:
            seen.add(key)
            out.append(d)
    return out


def output_paths(conversion: Conversion) -> list[Path]:
    """Where each file of *conversion* goes, the output itself included."""
    folder = conversion.out.resolve().parent
    return [folder / rel for rel in sorted(conversion.files)]


def write_conversion(conversion: Conversion) -> list[Path]:
    """Write every file of *conversion* atomically; refuse before writing anything over an input.

    Raises :class:`~urdftool.export.write.OutputError`.
    """
    paths = output_paths(conversion)
    for path in paths:
        guard_inputs(path, conversion.inputs)
    folder = conversion.out.resolve().parent
    for rel, data in sorted(conversion.files.items()):
        write_bytes_atomic(folder / rel, data, conversion.inputs)
    return paths
