"""The Python API behind ``import urdftool``."""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Iterable, Mapping
from concurrent.futures import Executor
from pathlib import Path

from urdftool.diagnostics import Diagnostic, FileReport, Report
from urdftool.export import ExportOptions
from urdftool.export.graph import GraphOptions, dot_text, write_diagram
from urdftool.export.write import guard_inputs, model_inputs
from urdftool.facts.simulation import engine_names
from urdftool.facts.simulation.scene import SimOptions
from urdftool.model import Robot
from urdftool.parse import InputError
from urdftool.pipeline import fixes
from urdftool.pipeline.check import CheckOptions, check_file, run_rules
from urdftool.pipeline.convert import (
    Conversion,
    convert_robot,
    graph_findings,
    keep_assets,
    unwritten_output,
    write_conversion,
)
from urdftool.pipeline.diff import DiffError, RobotDiff, compare, diff_files
from urdftool.pipeline.load import NoSuchModel, load_one
from urdftool.rules import Selection

PathLike = str | os.PathLike[str]


class LoadError(Exception):
    """No robot could be built from the file; ``diagnostics`` say why. When the file holds several
    models and none was named, or none of the name asked for, ``models`` are the names it holds
    (pass one as ``model=``); otherwise ``models`` is empty."""

    def __init__(self, message: str, diagnostics: Iterable[Diagnostic] = (), models: Iterable[str] = ()):
        super().__init__(message)
        self.diagnostics = tuple(diagnostics)
        self.models = tuple(models)


def _options(
    xacro_args: Mapping[str, str] | None,
    packages: Mapping[str, PathLike] | None,
    package_paths: Iterable[PathLike],
    select: Iterable[str] | None = None,
    ignore: Iterable[str] | None = None,
) -> CheckOptions:
    return CheckOptions(
        select=tuple(select) if select is not None else None,
        ignore=tuple(ignore or ()),
        xacro_args=dict(xacro_args or {}),
        packages={k: os.fspath(v) for k, v in (packages or {}).items()},
        package_paths=tuple(os.fspath(p) for p in package_paths),
    )


def _input_error(path: PathLike, exc: InputError) -> Exception:
    """The API's exception for an input that cannot be read at all."""
    if not os.path.exists(path):
        return FileNotFoundError(str(exc))
    return ValueError(str(exc))


def load(
    path: PathLike,
    xacro_args: Mapping[str, str] | None = None,
    packages: Mapping[str, PathLike] | None = None,
    package_paths: Iterable[PathLike] = (),
    model: str | None = None,
) -> Robot:
    """Read a URDF, xacro or SDF file into a :class:`~urdftool.model.Robot`.

    *packages* maps package names to folders (for ``package://``, ``$(find)``,
    ``model://``); *package_paths* are folders scanned for ``package.xml``. For
    files with several models (SDF worlds) *model* picks one by name; without it
    such a file is a :class:`LoadError` that lists the models (taking the first
    would answer for a model nobody asked about). Problems found while reading
    are in ``robot.diagnostics``.

    Raises :class:`LoadError` when no robot can be built (the file is not XML, not
    a robot, or xacro fails) and :class:`FileNotFoundError`/:class:`ValueError`
    when the file is missing or of unknown format.
    """
    return _load(path, xacro_args, packages, package_paths, model)[0]


def _load(
    path: PathLike,
    xacro_args: Mapping[str, str] | None,
    packages: Mapping[str, PathLike] | None,
    package_paths: Iterable[PathLike],
    model: str | None,
) -> tuple[Robot, list[str]]:
    """:func:`load`, and the files read to build the robot (the input and its includes)."""
    try:
        first = load_one(os.fspath(path), _options(xacro_args, packages, package_paths), model)
    except InputError as exc:
        raise _input_error(path, exc) from exc
    except NoSuchModel as exc:
        raise LoadError(str(exc), models=exc.models) from exc
    if first.robot is None:
        summary = "; ".join(d.message for d in first.diagnostics[:3])
        raise LoadError(f"{path}: cannot build a robot: {summary}", first.diagnostics)
    return first.robot, [os.fspath(path), *first.files]


def check(
    path_or_robot: PathLike | Robot,
    select: Iterable[str] | None = None,
    ignore: Iterable[str] | None = None,
    xacro_args: Mapping[str, str] | None = None,
    packages: Mapping[str, PathLike] | None = None,
    package_paths: Iterable[PathLike] = (),
) -> Report:
    """Check a file (every model in it) or an already loaded robot.

    *select* and *ignore* take rule codes, code prefixes or names, as on the
    command line. Raises :class:`ValueError` for an unknown selector and
    :class:`FileNotFoundError` for a missing file.
    """
    if isinstance(path_or_robot, Robot):
        selection = Selection.of(select, ignore)
        robot = path_or_robot
        diags = fixes.attach(run_rules(robot, selection))
        return Report((FileReport(robot.path, robot.format, robot.name, tuple(diags)),))
    options = _options(xacro_args, packages, package_paths, select, ignore)
    options.selection()  # raises UnknownSelector (a ValueError) early
    try:
        return Report(tuple(check_file(os.fspath(path_or_robot), options)))
    except InputError as exc:
        raise _input_error(path_or_robot, exc) from exc


def _check_path(path: str, options: CheckOptions) -> Report:
    """One file's report (module level, so executors in other processes can pickle it)."""
    try:
        return Report(tuple(check_file(path, options)))
    except InputError as exc:
        raise _input_error(path, exc) from exc


def check_many(
    paths: Iterable[PathLike],
    executor: Executor | None = None,
    *,
    select: Iterable[str] | None = None,
    ignore: Iterable[str] | None = None,
    xacro_args: Mapping[str, str] | None = None,
    packages: Mapping[str, PathLike] | None = None,
    package_paths: Iterable[PathLike] = (),
) -> list[Report]:
    """Check many files, each on *executor* when given: one :class:`Report` per path, in order.

    *executor* is any :class:`concurrent.futures.Executor`: a process pool, or a
    cluster's (``distributed.Client(...).get_executor()`` for Dask,
    ``ray.util.ActorPool``-backed executors for Ray). Work is sent with
    ``executor.submit`` and results are plain, picklable dataclasses, so nothing
    but urdftool itself needs to be installed on the workers. Without an
    executor the files are checked here, one after the other. Raises as
    :func:`check` does.
    """
    options = _options(xacro_args, packages, package_paths, select, ignore)
    options.selection()  # raises UnknownSelector (a ValueError) before any work is sent
    files = [os.fspath(p) for p in paths]
    if executor is None:
        return [_check_path(path, options) for path in files]
    futures = [executor.submit(_check_path, path, options) for path in files]
    return [future.result() for future in futures]


def to_dot(
    robot_or_path: PathLike | Robot,
    out: PathLike | None = None,
    *,
    rankdir: str = "TB",
    collapse_fixed: bool = False,
    diagnostics: bool = True,
    select: Iterable[str] | None = None,
    ignore: Iterable[str] | None = None,
    keep_dot: bool = False,
    xacro_args: Mapping[str, str] | None = None,
    packages: Mapping[str, PathLike] | None = None,
    package_paths: Iterable[PathLike] = (),
    model: str | None = None,
) -> str:
    """The kinematic tree as Graphviz DOT text; also written to *out* when given.

    *out* ending in ``.dot``/``.gv`` gets the text; ``.pdf``, ``.svg`` or ``.png``
    is rendered with Graphviz's ``dot`` (with *keep_dot*, the text is also
    written beside it, suffix ``.dot``). *rankdir* is TB, LR, BT or RL;
    *collapse_fixed* merges links joined by fixed joints; *diagnostics* marks
    links and joints with error/warning findings of the rules chosen by
    *select*/*ignore*. The other arguments are those of :func:`load`.

    Raises :class:`ValueError` for a bad option or suffix,
    ``urdftool.export.graph.GraphvizNotFound`` when ``dot`` is needed and
    missing, and ``GraphvizFailed`` when it fails.
    """
    options = GraphOptions.of({"rankdir": rankdir, "collapse_fixed": collapse_fixed,
                               "diagnostics": diagnostics, "select": select, "ignore": ignore})
    robot, inputs = _robot_and_inputs(robot_or_path, xacro_args, packages, package_paths, model)
    _guard_output(out, inputs)
    text = dot_text(robot, options, graph_findings(robot, options))
    if out is not None:
        write_diagram(text, out, inputs, keep_dot)
    return text


class ConversionRefused(ValueError):
    """The target cannot hold the model (a closed chain in URDF, a ball joint…); ``diagnostics`` say where."""

    def __init__(self, message: str, diagnostics: Iterable[Diagnostic] = ()):
        super().__init__(message)
        self.diagnostics = tuple(diagnostics)


def _robot_and_inputs(
    robot_or_path: PathLike | Robot,
    xacro_args: Mapping[str, str] | None,
    packages: Mapping[str, PathLike] | None,
    package_paths: Iterable[PathLike],
    model: str | None,
) -> tuple[Robot, list[str]]:
    """The robot to export and the files it came from, meshes included (never to be written over)."""
    if isinstance(robot_or_path, Robot):
        return robot_or_path, model_inputs(robot_or_path)
    robot, files = _load(robot_or_path, xacro_args, packages, package_paths, model)
    return robot, model_inputs(robot, files)


def _guard_output(out: PathLike | None, inputs: list[str]) -> None:
    """Refuse, before any work, an output that is an input or not a regular file."""
    if out is not None:
        guard_inputs(out, inputs)


def _converted(
    target: str,
    suffix: str,
    robot: Robot,
    inputs: list[str],
    out: PathLike | None,
    options: ExportOptions,
) -> str:
    """Convert through the pipeline (as ``urdftool convert`` does); with *out*, write the files.

    Raises :class:`ConversionRefused` with the same findings ``convert`` prints.
    """
    if out is not None:
        _guard_output(out, inputs)
        where = Path(out)
    else:
        # nothing to write beside: every mesh by absolute path, converted ones kept in the cache
        where = unwritten_output(f"{robot.name or 'robot'}{suffix}", target)
        options = dataclasses.replace(options, absolute_mesh_paths=True)
    conversion: Conversion = convert_robot(robot, target, where, options, inputs)
    if conversion.refused:
        reasons = "; ".join(d.message for d in conversion.errors[:5])
        raise ConversionRefused(f"{robot.name}: not converted to {target}: {reasons}", conversion.diagnostics)
    if out is not None:
        write_conversion(conversion)
    elif (problem := keep_assets(conversion)) is not None:
        count = len(conversion.files) - 1
        raise ConversionRefused(
            f"{robot.name}: the {target} text refers to {count} converted mesh file(s) that must be written "
            f"somewhere, and {problem}; pass out=PATH to write them beside the output",
            conversion.diagnostics)
    return conversion.text


def to_urdf(
    robot_or_path: PathLike | Robot,
    out: PathLike | None = None,
    *,
    xacro_args: Mapping[str, str] | None = None,
    packages: Mapping[str, PathLike] | None = None,
    package_paths: Iterable[PathLike] = (),
    model: str | None = None,
    flavor: str = "urdf",
    repair_inertia: bool = False,
    copy_assets: bool = False,
    fuse_fixed: bool = False,
) -> str:
    """A flattened URDF of a URDF, xacro or SDF model, as text; also written to *out* when given.

    Raises :class:`ConversionRefused` (with located diagnostics) for what URDF
    cannot hold: closed chains, ball/universal/revolute2/screw/gearbox joints.
    The other arguments are those of :func:`load`.

    ``flavor="pybullet"`` gives the PyBullet-ready URDF (docs/pybullet.md):
    mesh paths relative to *out* (converted meshes and, with *copy_assets*,
    all meshes are written to ``assets/`` beside it), an explicit inertial on
    every link, invalid inertia refused unless *repair_inertia*. Without *out*
    mesh paths are absolute, converted meshes kept in the mesh cache's
    ``exports/`` folder, as for :func:`to_mjcf`.
    *fuse_fixed* (PyBullet) merges links on fixed joints into the links that carry them.
    """
    if flavor not in ("urdf", "pybullet"):
        raise ValueError(f"unknown URDF flavor '{flavor}' (choose urdf or pybullet)")
    robot, inputs = _robot_and_inputs(robot_or_path, xacro_args, packages, package_paths, model)
    options = ExportOptions(repair_inertia=repair_inertia, copy_assets=copy_assets, fuse_fixed=fuse_fixed)
    return _converted(flavor, ".urdf", robot, inputs, out, options)


def to_sdf(
    robot_or_path: PathLike | Robot,
    out: PathLike | None = None,
    *,
    xacro_args: Mapping[str, str] | None = None,
    packages: Mapping[str, PathLike] | None = None,
    package_paths: Iterable[PathLike] = (),
    model: str | None = None,
) -> str:
    """An SDF 1.7 model, as text; also written to *out* when given.

    Raises :class:`ConversionRefused` for what SDF cannot hold (planar joints).
    The other arguments are those of :func:`load`.
    """
    robot, inputs = _robot_and_inputs(robot_or_path, xacro_args, packages, package_paths, model)
    return _converted("sdf", ".sdf", robot, inputs, out, ExportOptions())


def to_mjcf(
    robot_or_path: PathLike | Robot,
    out: PathLike | None = None,
    *,
    floating_base: str = "auto",
    actuators: str = "none",
    repair_inertia: bool = False,
    copy_assets: bool = False,
    scene: bool = False,
    xacro_args: Mapping[str, str] | None = None,
    packages: Mapping[str, PathLike] | None = None,
    package_paths: Iterable[PathLike] = (),
    model: str | None = None,
) -> str:
    """A MuJoCo MJCF model of a URDF, xacro or SDF model, as text.

    With *out*, the file and its converted mesh assets (``assets/`` beside it)
    are written atomically, never over an input, and meshes are referenced
    relative to *out*. Without it every mesh is referenced by absolute path, so
    the text loads from anywhere (``mujoco.MjModel.from_xml_string``): meshes
    MuJoCo reads where they are, meshes it cannot read (COLLADA) converted into
    the mesh cache's ``exports/`` folder (content-addressed; ConversionRefused
    when the cache is off). Options as in ``urdftool convert``:
    *floating_base* ``auto|free|fixed``, *actuators* ``none|position|velocity|motor|auto``,
    *repair_inertia*, *copy_assets*, *scene* (ground plane and light); see
    docs/mjcf.md. Raises :class:`ConversionRefused` with located diagnostics
    (e.g. physically invalid inertia without *repair_inertia*).
    """
    robot, inputs = _robot_and_inputs(robot_or_path, xacro_args, packages, package_paths, model)
    options = ExportOptions(floating_base=floating_base, actuators=actuators, repair_inertia=repair_inertia,
                            copy_assets=copy_assets, scene=scene)
    return _converted("mjcf", ".xml", robot, inputs, out, options)


def simulate(
    path_or_robot: PathLike | Robot,
    *,
    engine: str = "all",
    duration: float = 2.0,
    timestep: float | None = None,
    hold: bool = False,
    repair_inertia: bool = False,
    xacro_args: Mapping[str, str] | None = None,
    packages: Mapping[str, PathLike] | None = None,
    package_paths: Iterable[PathLike] = (),
    model: str | None = None,
) -> Report:
    """The bundled smoke simulation (``urdftool sim``) of a file's models or a loaded robot.

    *engine* is ``mujoco``, ``pybullet`` or ``all``; *duration* and *timestep*
    are in seconds (*timestep* ``None``: each engine's default); *hold* holds
    the joints with PD at the start pose; *repair_inertia* lets the exporters
    repair invalid inertia. The report holds the runtime findings (``R``) and
    one ``sim-summary`` per engine whose ``data["summary"]`` has the numbers.
    Raises :class:`ValueError` for an unknown engine or an unreadable file and
    :class:`FileNotFoundError` for a missing one.
    """
    # Function-level: the simulation brings NumPy and the engine adapters.
    from urdftool.pipeline.simulate import simulate_file, simulate_robot

    if engine not in ("mujoco", "pybullet", "all"):
        raise ValueError(f"unknown engine '{engine}' (choose mujoco, pybullet or all)")
    options = SimOptions(engine_names(engine), duration, timestep, hold, repair_inertia)
    if isinstance(path_or_robot, Robot):
        return Report((simulate_robot(path_or_robot, options),))
    try:
        return simulate_file(os.fspath(path_or_robot), options, _options(xacro_args, packages, package_paths),
                             model)
    except InputError as exc:
        raise _input_error(path_or_robot, exc) from exc


def diff(
    old: PathLike | Robot,
    new: PathLike | Robot,
    xacro_args: Mapping[str, str] | None = None,
    packages: Mapping[str, PathLike] | None = None,
    package_paths: Iterable[PathLike] = (),
    model: str | None = None,
    findings: bool = True,
) -> RobotDiff:
    """What changed from *old* to *new* (files or loaded robots), as ``urdftool diff`` reports it.

    Both files are read with the same xacro arguments and packages. Links and joints are matched
    by name, then by position in the tree (``link_renames``, ``joint_renames``); each
    :class:`~urdftool.pipeline.diff.Change` says what moved and by how much (link poses at the zero
    configuration in mm and degrees, masses in %). With *findings*, the rules run on both sides
    and findings that appeared or disappeared are changes too. Raises :class:`LoadError` when a
    side cannot be read into a robot.
    """
    options = _options(xacro_args, packages, package_paths)
    if isinstance(old, Robot) and isinstance(new, Robot):
        selection = options.selection()
        return compare(old, new, run_rules(old, selection) if findings else [],
                       run_rules(new, selection) if findings else [])
    if isinstance(old, Robot) or isinstance(new, Robot):
        raise TypeError("diff: pass two paths or two robots")
    try:
        return diff_files(os.fspath(old), os.fspath(new), options, model, findings)
    except DiffError as exc:
        raise LoadError(str(exc), exc.diagnostics) from exc
    except InputError as exc:
        raise _input_error(old if not os.path.exists(new) else new, exc) from exc
    except NoSuchModel as exc:
        raise LoadError(str(exc), models=exc.models) from exc
