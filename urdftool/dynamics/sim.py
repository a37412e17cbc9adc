"""The bundled smoke simulation: one robot, a few seconds, MuJoCo and PyBullet, numbers out.

:func:`simulate` prepares the scene once (:mod:`~urdftool.dynamics.sim_scene`),
runs each requested engine on urdftool's own export of the robot, and returns
what each measured (:class:`~urdftool.dynamics.sim_record.EngineRun`). The
verdicts (``sim-unstable``, ``sim-drift``…) are the ``R`` rules' reading of
these numbers (:mod:`urdftool.rules.runtime`). Deterministic: fixed timestep,
no randomness, the same input gives the same numbers (except wall time).
"""

from __future__ import annotations

import importlib.util
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from urdftool.dynamics.sim_record import EngineRun
from urdftool.dynamics.sim_scene import ENGINES, Scene, SimOptions, prepare
from urdftool.model import Robot

#: engine -> (module to import, display name)
ENGINE_INFO = {"mujoco": ("mujoco", "MuJoCo"), "pybullet": ("pybullet", "PyBullet")}

#: Rule options that carry the simulation switches through ``check``.
OPTION = "sim"


@dataclass
class SimResult:
    """The scene and every engine's run, in the order asked for."""

    scene: Scene
    runs: list[EngineRun]


def engine_names(choice: str) -> tuple[str, ...]:
    """``mujoco``, ``pybullet`` or ``all`` as a tuple of engines."""
    return ENGINES if choice == "all" else (choice,)


def display_name(engine: str) -> str:
    return ENGINE_INFO[engine][1]


def _runner(engine: str) -> Callable[[Scene, SimOptions], EngineRun]:
    if engine == "mujoco":
        from urdftool.dynamics.sim_mujoco import run_mujoco

        return run_mujoco
    from urdftool.dynamics.sim_pybullet import run_pybullet

    return run_pybullet


def simulate(robot: Robot, options: SimOptions) -> SimResult:
    """Run the smoke simulation of *robot* in each engine of *options*."""
    scene = prepare(robot)
    runs = []
    for engine in options.engines:
        if importlib.util.find_spec(ENGINE_INFO[engine][0]) is None:
            runs.append(EngineRun(engine, unavailable=f"{display_name(engine)} is not installed"))
            continue
        runs.append(_runner(engine)(scene, options))
    return SimResult(scene, runs)


def options_from(rule_options: Mapping[str, Any]) -> SimOptions | None:
    """The simulation options carried by ``check --sim`` (``None`` when the simulation is off)."""
    if not rule_options.get(OPTION):
        return None
    return SimOptions(
        engines=tuple(rule_options.get("sim_engines", ENGINES)),
        duration=float(rule_options.get("sim_duration", SimOptions.duration)),
        timestep=rule_options.get("sim_timestep"),
        hold=bool(rule_options.get("sim_hold", False)),
        repair_inertia=bool(rule_options.get("repair_inertia", False)),
    )


def rule_options_for(options: SimOptions) -> dict[str, Any]:
    """The inverse of :func:`options_from`: what ``check`` passes to the R rules."""
    return {OPTION: True, "sim_engines": list(options.engines), "sim_duration": options.duration,
            "sim_timestep": options.timestep, "sim_hold": options.hold,
            "repair_inertia": options.repair_inertia}
