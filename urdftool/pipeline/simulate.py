"""The smoke simulation in the pipeline: what ``urdftool sim`` prints and ``urdftool.simulate`` returns.

Each engine loads exactly the bytes ``urdftool convert`` writes for it
(:func:`export_for_engine`, through :func:`~urdftool.pipeline.convert.convert_robot`),
and the run says which command that is. Each model of the file gets the
findings of the runtime rules (``R``), the export's findings when it is
refused, and the reader's errors (a model that cannot be read, or is read
with errors, says so instead of passing).
"""

from __future__ import annotations

from pathlib import Path

from urdftool.diagnostics import Diagnostic, FileReport, Report, Severity
from urdftool.export import ExportOptions
from urdftool.facts.simulation import SimResult, rule_options_for
from urdftool.facts.simulation.scene import Scene, SimOptions
from urdftool.model import Robot
from urdftool.pipeline.check import CheckOptions, run_rules
from urdftool.pipeline.convert import convert_robot, write_conversion
from urdftool.pipeline.load import load_models, no_such_model
from urdftool.rules import Selection
from urdftool.simulation.run import Exported, simulate

#: The rules a simulation report runs.
RUNTIME = Selection.of(("R",), ())

#: engine -> (export target, file name, extra ``convert`` flags)
ENGINE_EXPORTS = {
    "mujoco": ("mjcf", "robot.xml", ()),
    "pybullet": ("pybullet", "robot.urdf", ("--to", "pybullet")),
}


def export_options_for(engine: str, options: SimOptions, scene: Scene) -> ExportOptions:
    """What ``convert`` is run with for *engine*: a floor under robots that move about (MJCF)."""
    return ExportOptions(scene=engine == "mujoco" and scene.floating, repair_inertia=options.repair_inertia)


def export_for_engine(robot: Robot, engine: str, folder: Path, options: SimOptions, scene: Scene) -> Exported:
    """Write ``urdftool convert``'s output for *engine* into *folder*."""
    target, name, flags = ENGINE_EXPORTS[engine]
    export_options = export_options_for(engine, options, scene)
    words = ["urdftool", "convert", Path(robot.path).name or "robot", "-o", name, *flags]
    words += ["--scene"] * export_options.scene + ["--repair-inertia"] * export_options.repair_inertia
    conversion = convert_robot(robot, target, folder / name, export_options)
    if conversion.refused:
        return Exported(" ".join(words), refused=conversion.errors)
    write_conversion(conversion)
    return Exported(" ".join(words), folder / name)


def simulator(robot: Robot, options: SimOptions) -> SimResult:
    """The :data:`~urdftool.facts.simulation.Simulator` for ``sim`` and ``check --sim``."""
    return simulate(robot, options, export_for_engine)


def simulate_robot(robot: Robot, options: SimOptions) -> FileReport:
    """The runtime findings for one loaded robot, with the reader's errors."""
    found = run_rules(robot, RUNTIME, rule_options_for(options))
    errors = [d for d in robot.diagnostics if d.severity is Severity.ERROR]
    diagnostics = sorted({_key(d): d for d in [*errors, *found]}.values(), key=Diagnostic.sort_key)
    return FileReport(robot.path, robot.format, robot.name, tuple(diagnostics))


def simulate_file(path: str, options: SimOptions, check_options: CheckOptions,
                  model: str | None = None) -> Report:
    """Every model in *path* (or the one named *model*). Raises :class:`~urdftool.parse.InputError`
    and :class:`~urdftool.pipeline.load.NoSuchModel`."""
    reports = []
    models = load_models(path, check_options)
    if model is not None and not any(m.robot and m.robot.name == model for m in models):
        raise no_such_model(path, model, (m.robot.name for m in models if m.robot))
    for loaded in models:
        if loaded.robot is None:
            if model is None:
                reports.append(FileReport(loaded.path, loaded.format, None, tuple(loaded.diagnostics)))
            continue
        if model is None or loaded.robot.name == model:
            reports.append(simulate_robot(loaded.robot, options))
    return Report(tuple(reports))


def _key(d: Diagnostic) -> tuple[object, ...]:
    return (d.code, d.message, d.location)
