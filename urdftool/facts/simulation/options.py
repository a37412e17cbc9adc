"""The smoke simulation's options: light enough for the command line to build them without
loading the scene code (see :mod:`.scene`)."""

from __future__ import annotations

from urdftool.records import record

ENGINES = ("mujoco", "pybullet")
#: Default length of a run (s).
DURATION = 2.0


@record
class SimOptions:
    """How to run the smoke simulation.

    ``timestep`` (s) ``None`` keeps each engine's default (MuJoCo 2 ms, PyBullet
    1/240 s), the step users get; ``hold`` adds a PD controller at the start pose
    (torques clipped at each joint's effort limit); ``repair_inertia`` lets the
    exporters repair invalid inertia instead of refusing the model.
    """

    engines: tuple[str, ...] = ENGINES
    duration: float = DURATION
    timestep: float | None = None
    hold: bool = False
    repair_inertia: bool = False
