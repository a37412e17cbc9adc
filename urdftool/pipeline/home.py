"""The robot's home configuration from its SRDF: the stance a free robot starts in, and the
MJCF keyframe ``home``.

An SRDF's ``<group_state>`` elements name joint configurations (``standing``,
``half_sitting``, ``home``). When the model itself gives none, the SRDF found
beside it (:func:`urdftool.pipeline.srdf.find_srdf`, read by
:func:`urdftool.parse.srdf.read_srdf`) supplies one: only one-value joints are
read (a floating ``root_joint`` entry is skipped), only states whose joints the
robot has count, and of those the first named like a stance (:data:`PREFERRED`)
wins, else the one covering the most joints.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Collection, Iterator, Mapping
from pathlib import Path

from urdftool.parse import Loaded
from urdftool.parse.packages import PackageResolver
from urdftool.parse.srdf import Srdf, read_srdf
from urdftool.pipeline.srdf import find_srdf
from urdftool.records import record

#: Names of group states taken as the home configuration, best first.
PREFERRED = ("standing", "half_sitting", "home", "stand", "default", "neutral", "ready",
             "straight_standing", "init")


@record
class HomeState:
    """A named joint configuration (rad or m per one-DOF joint)."""

    name: str
    values: Mapping[str, float]


def group_states(srdf: Srdf) -> list[HomeState]:
    """Every group state of *srdf* with its finite one-value joints."""
    out = []
    for state in srdf.group_states:
        values = {v.name: v.values[0] for v in state.joints
                  if len(v.values) == 1 and math.isfinite(v.values[0])}
        if values:
            out.append(HomeState(state.name or "", values))
    return out


def choose_state(states: list[HomeState], joints: Collection[str]) -> HomeState | None:
    """The state to use as home for a robot with *joints*: every name it sets must be one of them."""
    fitting = [s for s in states if set(s.values) <= set(joints)]
    for name in PREFERRED:
        for state in fitting:
            if state.name.lower() == name:
                return state
    return max(fitting, key=lambda s: len(s.values), default=None)


def with_home(loaded: Loaded, resolver: PackageResolver) -> Loaded:
    """*loaded* with its robot's home from the SRDF beside it, when the model gives none."""
    robot = loaded.robot
    if robot is None or robot.home is not None:
        return loaded
    # a loop's cut joint is a joint of the robot too (Cassie's SRDF sets its spring cuts)
    joints = [j.name for j in robot.joints] + [c.joint.name for c in robot.loop_closures]
    nearby = _nearby(loaded.path, robot.name, resolver)
    candidates = [loaded.srdf] if loaded.srdf is not None else list(nearby)
    states = [s for srdf in candidates if (s := choose_state(group_states(srdf), joints)) is not None]
    if not states:
        return loaded
    # a state named like a stance first, then the one setting the most joints
    state = min(states, key=lambda s: (s.name.lower() not in PREFERRED, -len(s.values)))
    return dataclasses.replace(loaded, robot=dataclasses.replace(robot, home=dict(state.values)))


def _nearby(model_path: str, robot_name: str | None, resolver: PackageResolver) -> Iterator[Srdf]:
    """The SRDF check would use, else every SRDF in the ``srdf/`` folder beside the model's
    (example-robot-data keeps ``robots/`` and ``srdf/`` side by side, one SRDF for several
    variants of a robot); unreadable ones are skipped (check reports them)."""
    found = find_srdf(model_path, robot_name)
    folder = Path(model_path).resolve().parent.parent / "srdf"
    paths = [found] if found else sorted(str(p) for p in folder.glob("*.srdf") if p.is_file())
    for path in paths:
        try:
            yield read_srdf(path, resolver)
        except OSError:
            continue
