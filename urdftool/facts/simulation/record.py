"""What a run of the smoke simulation measured, and the recorder both engines feed step by step.

Units: s, m, rad, m/s, rad/s, J. Joint speeds and limit violations are for
one-DOF joints (rad or m). The base is the root link's frame (its origin) in
the world; for a robot bolted to the world it does not move.
"""

from __future__ import annotations

import math
from dataclasses import field
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
else:
    # NumPy is imported on first use: a structural check must not pay for it.
    from urdftool.lazy import numpy as np

from urdftool.diagnostics import Diagnostic
from urdftool.model import Joint
from urdftool.records import record

#: Part of the run at the end over which "still moving" is measured (fraction).
LATE_FRACTION = 0.1


@record
class Penetration:
    """Two links whose collision geometry overlaps at the first step, by ``depth`` (m)."""

    link_a: str
    link_b: str
    depth: float


@record
class LimitViolation:
    """The furthest a joint went beyond a limit (rad or m), and when (s)."""

    joint: str
    amount: float
    position: float
    bound: float
    time: float


@record(frozen=False)
class EngineRun:
    """One engine's run. ``refused`` holds why it did not run (exporter or engine findings)."""

    engine: str
    refused: list[Diagnostic] = field(default_factory=list)
    #: the command whose output the engine loaded (``urdftool convert IN -o robot.xml --scene``)
    loaded: str | None = None
    #: why the engine could not be used at all (not installed)
    unavailable: str | None = None
    timestep: float = 0.0
    steps: int = 0
    wall_time: float = 0.0
    #: time (s) of the first non-finite state, ``None`` when the state stayed finite
    diverged_at: float | None = None
    max_joint_speed: float = 0.0
    fastest_joint: str | None = None
    #: the largest joint speed over the last part of the run (LATE_FRACTION)
    late_joint_speed: float = 0.0
    late_fastest_joint: str | None = None
    max_base_speed: float = 0.0
    energy_initial: float = 0.0
    energy_max: float = 0.0
    energy_final: float = 0.0
    #: total mass × g × the robot's height (J): what "a lot of energy" means for this robot
    energy_scale: float = 1.0
    base_displacement: float = 0.0
    #: mean horizontal base speed (m/s) over the last part of the run
    base_late_speed: float = 0.0
    #: horizontal distance (m) the base travelled in the second half of the run
    base_late_distance: float = 0.0
    penetrations: list[Penetration] = field(default_factory=list)
    #: whether the run simulates contacts between links of the robot: MuJoCo does (its default,
    #: less the pairs the export excludes); PyBullet loads without self-collision (its default),
    #: so the overlaps it measures at the start in a second client are never contacts of the run
    self_collision: bool = True
    #: the largest distance (m) between the two anchors of a loop closure over the run
    #: (MuJoCo's connect and weld equalities); ``None`` without a closed loop
    loop_gap: float | None = None
    limit_violations: list[LimitViolation] = field(default_factory=list)
    #: largest |q_follower - (multiplier · q_leader + offset)| (rad or m) over the run, and where
    mimic_error: float = 0.0
    mimic_joint: str | None = None

    @property
    def ran(self) -> bool:
        return not self.refused and self.unavailable is None

    @property
    def energy_growth(self) -> float:
        """Largest rise of the total energy above its start, relative to :attr:`energy_scale`."""
        return (self.energy_max - self.energy_initial) / self.energy_scale

    @property
    def penetration_depth(self) -> float:
        return max((p.depth for p in self.penetrations), default=0.0)

    def summary(self) -> dict[str, Any]:
        """The numbers for a report's ``data`` (JSON-ready; ``wall_time`` varies between runs)."""
        if not self.ran:
            return {"engine": self.engine, "ran": False, "unavailable": self.unavailable,
                    "refused": [d.code for d in self.refused], "loaded": self.loaded}
        return {
            "engine": self.engine, "ran": True, "loaded": self.loaded, "timestep": self.timestep,
            "steps": self.steps,
            "duration": round(self.steps * self.timestep, 9), "finite": self.diverged_at is None,
            "diverged_at": self.diverged_at,
            "max_joint_speed": self.max_joint_speed, "fastest_joint": self.fastest_joint,
            "max_base_speed": self.max_base_speed,
            "energy_initial": self.energy_initial, "energy_max": self.energy_max,
            "energy_final": self.energy_final, "energy_drift": self.energy_growth,
            "final_base_displacement": self.base_displacement,
            "base_late_speed": self.base_late_speed, "base_late_distance": self.base_late_distance,
            "penetration_depth": self.penetration_depth,
            "penetrating_pairs": [[p.link_a, p.link_b, p.depth] for p in self.penetrations],
            "self_collision": self.self_collision,
            "limit_violations": [{"joint": v.joint, "amount": v.amount, "time": v.time}
                                 for v in self.limit_violations],
            **({"max_mimic_error": self.mimic_error, "worst_mimic_joint": self.mimic_joint}
               if self.mimic_joint else {}),
            **({"max_loop_gap": self.loop_gap} if self.loop_gap is not None else {}),
            "wall_time": round(self.wall_time, 3),
        }


class Recorder:
    """Collects one engine's state at every step and reduces it to an :class:`EngineRun`.

    *joints* are the one-DOF joints recorded, in the order of the position and
    velocity vectors passed to :meth:`record`.
    """

    def __init__(self, run: EngineRun, joints: list[Joint], steps: int, timestep: float):
        self.run = run
        self.joints = joints
        self.timestep = timestep
        self.steps = steps
        self.lower = np.array([_limit(j, "lower") for j in joints])
        self.upper = np.array([_limit(j, "upper") for j in joints])
        self.positions = np.zeros((steps, len(joints)))
        self.speeds = np.zeros((steps, len(joints)))
        self.base = np.zeros((steps, 3))
        self.base_speed = np.zeros(steps)
        self.energy = np.zeros(steps)
        self.count = 0

    def record(self, positions: Any, velocities: Any, base: Any, base_velocity: Any, energy: float) -> bool:
        """Store one step; ``False`` (stop) once the state is no longer finite."""
        k = self.count
        values = (positions, velocities, base, base_velocity, [energy])
        if not all(np.all(np.isfinite(np.asarray(v, dtype=float))) for v in values):
            self.run.diverged_at = k * self.timestep
            return False
        self.positions[k] = positions
        self.speeds[k] = np.abs(velocities)
        self.base[k] = base
        self.base_speed[k] = float(np.linalg.norm(base_velocity))
        self.energy[k] = energy
        self.count += 1
        return True

    def finish(self, wall_time: float, energy_scale: float) -> EngineRun:
        run, n = self.run, self.count
        run.timestep, run.steps, run.wall_time = self.timestep, n, wall_time
        run.energy_scale = max(energy_scale, 1e-9)
        if n == 0:
            return run
        speeds, late = self.speeds[:n], self.speeds[max(0, n - max(1, int(n * LATE_FRACTION))):n]
        if self.joints:
            run.max_joint_speed, run.fastest_joint = _largest(speeds, self.joints)
            run.late_joint_speed, run.late_fastest_joint = _largest(late, self.joints)
        run.max_base_speed = float(self.base_speed[:n].max())
        run.energy_initial, run.energy_max = float(self.energy[0]), float(self.energy[:n].max())
        run.energy_final = float(self.energy[n - 1])
        self._base_motion(n)
        run.limit_violations = self._violations(n)
        self._mimics(n)
        return run

    def _mimics(self, n: int) -> None:
        """How far each recorded mimic joint strays from what it follows (both recorded)."""
        column = {joint.name: k for k, joint in enumerate(self.joints)}
        for k, joint in enumerate(self.joints):
            mimic = joint.mimic
            if mimic is None or mimic.joint not in column:
                continue
            target = mimic.multiplier * self.positions[:n, column[mimic.joint]] + mimic.offset
            error = float(np.max(np.abs(self.positions[:n, k] - target)))
            if self.run.mimic_joint is None or error > self.run.mimic_error:
                self.run.mimic_error, self.run.mimic_joint = error, joint.name

    def _base_motion(self, n: int) -> None:
        base = self.base[:n]
        self.run.base_displacement = float(np.linalg.norm(base[-1] - base[0]))
        half = base[n // 2:, :2]
        steps = np.linalg.norm(np.diff(half, axis=0), axis=1)
        self.run.base_late_distance = float(steps.sum())
        late = max(1, int(n * LATE_FRACTION))
        tail = base[n - late - 1:, :2] if n > late else base[:, :2]
        span = (len(tail) - 1) * self.timestep
        self.run.base_late_speed = float(np.linalg.norm(tail[-1] - tail[0]) / span) if span > 0 else 0.0

    def _violations(self, n: int) -> list[LimitViolation]:
        out = []
        positions = self.positions[:n]
        below = self.lower - positions
        above = positions - self.upper
        for column, joint in enumerate(self.joints):
            if not math.isfinite(self.lower[column]):
                continue
            worst_low, worst_high = int(np.argmax(below[:, column])), int(np.argmax(above[:, column]))
            low, high = below[worst_low, column], above[worst_high, column]
            row, amount, bound = (worst_low, low, self.lower[column]) if low >= high \
                else (worst_high, high, self.upper[column])
            if amount > 0:
                out.append(LimitViolation(joint.name, float(amount), float(positions[row, column]),
                                          float(bound), row * self.timestep))
        return out


def _largest(speeds: Any, joints: list[Joint]) -> tuple[float, str]:
    per_joint = speeds.max(axis=0)
    column = int(np.argmax(per_joint))
    return float(per_joint[column]), joints[column].name


def _limit(joint: Joint, side: str) -> float:
    limit = joint.limit
    value = getattr(limit, side) if limit is not None else None
    usable = limit is not None and limit.lower is not None and limit.upper is not None \
        and limit.lower < limit.upper and joint.type.value in ("revolute", "prismatic")
    return float(value) if usable and value is not None else math.nan
