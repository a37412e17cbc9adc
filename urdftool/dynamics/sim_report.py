"""The smoke simulation as a report: what ``urdftool sim`` prints and ``urdftool.simulate`` returns.

Each model of the file gets the findings of the runtime rules (``R``), the
exporters' findings when they refuse it, and the reader's errors (a model
that cannot be read, or is read with errors, says so instead of passing).
"""

from __future__ import annotations

from urdftool.check import CheckOptions, run_rules
from urdftool.diagnostics import Diagnostic, FileReport, Report, Severity
from urdftool.dynamics.sim import rule_options_for
from urdftool.dynamics.sim_scene import SimOptions
from urdftool.model import Robot
from urdftool.parse import read
from urdftool.rules import Selection

#: The rules a simulation report runs.
RUNTIME = Selection.of(("R",), ())


def simulate_robot(robot: Robot, options: SimOptions) -> FileReport:
    """The runtime findings for one loaded robot, with the reader's errors."""
    found = run_rules(robot, RUNTIME, rule_options_for(options))
    errors = [d for d in robot.diagnostics if d.severity is Severity.ERROR]
    diagnostics = sorted({_key(d): d for d in [*errors, *found]}.values(), key=Diagnostic.sort_key)
    return FileReport(robot.path, robot.format, robot.name, tuple(diagnostics))


def simulate_file(path: str, options: SimOptions, check_options: CheckOptions,
                  model: str | None = None) -> Report:
    """Every model in *path* (or the one named *model*). Raises :class:`~urdftool.parse.InputError`."""
    reports = []
    for loaded in read(path, check_options.xacro_args, check_options.resolver()):
        if loaded.robot is None:
            if model is None:
                reports.append(FileReport(loaded.path, loaded.format, None, tuple(loaded.diagnostics)))
            continue
        if model is None or loaded.robot.name == model:
            reports.append(simulate_robot(loaded.robot, options))
    return Report(tuple(reports))


def _key(d: Diagnostic) -> tuple[object, ...]:
    return (d.code, d.message, d.location)
