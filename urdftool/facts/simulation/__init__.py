"""The smoke simulation as a fact: its options, what each engine measured, and who runs it.

Running a simulation needs an export (MuJoCo and PyBullet load urdftool's own
MJCF and URDF), and exporters sit above the rules. So this layer only names the
fact: the data (:class:`SimResult`, :mod:`.record`, :mod:`.scene`) and a
:data:`Simulator` slot on the check context. The pipeline fills the slot with
:func:`urdftool.simulation.run.simulate` when a simulation is asked for; the
runtime rules read :func:`simulation` and never run an engine themselves.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any

from urdftool.facts.context import SIM_OPTION, CheckContext
from urdftool.facts.simulation.options import ENGINES, SimOptions
from urdftool.model import Robot
from urdftool.records import record

if TYPE_CHECKING:  # the scene and the records load physics code a run without --sim never needs
    from urdftool.facts.simulation.record import EngineRun
    from urdftool.facts.simulation.scene import Scene

#: engine -> (module to import, display name)
ENGINE_INFO = {"mujoco": ("mujoco", "MuJoCo"), "pybullet": ("pybullet", "PyBullet")}

#: Rule options that carry the simulation switches through ``check``.
OPTION = SIM_OPTION


@record(frozen=False)
class SimResult:
    """The scene and every engine's run, in the order asked for."""

    scene: Scene
    runs: list[EngineRun]


#: Runs the smoke simulation of a robot (installed on the context by the pipeline).
Simulator = Callable[[Robot, SimOptions], SimResult]


def engine_names(choice: str) -> tuple[str, ...]:
    """``mujoco``, ``pybullet`` or ``all`` as a tuple of engines."""
    return ENGINES if choice == "all" else (choice,)


def display_name(engine: str) -> str:
    """The engine's name as users know it."""
    return ENGINE_INFO[engine][1]


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


def simulation(ctx: CheckContext) -> SimResult | None:
    """The smoke simulation of this robot, run once per check.

    ``None`` when no simulation was asked for, the robot has no links, or no
    simulator was installed on the context.
    """
    if "sim" not in ctx.cache:
        options = options_from(ctx.options)
        run = ctx.simulator
        ctx.cache["sim"] = run(ctx.robot, options) if run and options and ctx.robot.links else None
    return ctx.cache["sim"]  # type: ignore[no-any-return]
