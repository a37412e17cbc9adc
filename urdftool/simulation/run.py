"""The bundled smoke simulation: one robot, a few seconds, MuJoCo and PyBullet, numbers out.

:func:`simulate` prepares the scene once (:mod:`~urdftool.facts.simulation.scene`),
asks the caller's *export* for the file each engine loads — the pipeline hands
in exactly what ``urdftool convert`` writes — and returns what each engine
measured (:class:`~urdftool.facts.simulation.record.EngineRun`). The verdicts
(``sim-unstable``, ``sim-drift``…) are the ``R`` rules' reading of these
numbers (:mod:`urdftool.rules.runtime`). Deterministic: fixed timestep, no
randomness, the same input gives the same numbers (except wall time).
"""

from __future__ import annotations

import importlib.util
import tempfile
from collections.abc import Callable
from dataclasses import field
from pathlib import Path

from urdftool.diagnostics import Diagnostic
from urdftool.facts.simulation import ENGINE_INFO, SimResult, display_name
from urdftool.facts.simulation.record import EngineRun
from urdftool.facts.simulation.scene import Scene, SimOptions, prepare
from urdftool.model import Robot
from urdftool.records import record
from urdftool.simulation.mujoco import run_mujoco
from urdftool.simulation.pybullet import run_pybullet


@record(frozen=False)
class Exported:
    """The file an engine is to load, or why there is none, and the command that writes it."""

    command: str
    path: Path | None = None
    refused: list[Diagnostic] = field(default_factory=list)


#: Writes the export of a robot for one engine into a folder: (robot, engine, folder, options, scene).
Export = Callable[[Robot, str, Path, SimOptions, Scene], Exported]

RUNNERS: dict[str, Callable[[Scene, Path, SimOptions], EngineRun]] = {
    "mujoco": run_mujoco,
    "pybullet": run_pybullet,
}


def simulate(robot: Robot, options: SimOptions, export: Export) -> SimResult:
    """Run the smoke simulation of *robot* in each engine of *options*, on the files *export* writes."""
    scene = prepare(robot)
    runs = []
    with tempfile.TemporaryDirectory(prefix="urdftool-sim-") as temporary:
        for engine in options.engines:
            if importlib.util.find_spec(ENGINE_INFO[engine][0]) is None:
                runs.append(EngineRun(engine, unavailable=f"{display_name(engine)} is not installed"))
                continue
            folder = Path(temporary) / engine
            folder.mkdir()
            exported = export(robot, engine, folder, options, scene)
            if exported.path is None:
                run = EngineRun(engine, refused=exported.refused)
            else:
                run = RUNNERS[engine](scene, exported.path, options)
            run.loaded = exported.command
            runs.append(run)
    return SimResult(scene, runs)
