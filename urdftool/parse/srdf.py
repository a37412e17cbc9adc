"""The home configuration of a robot from its SRDF (MoveIt semantic description).

An SRDF's ``<group_state>`` elements name joint configurations (``standing``,
``half_sitting``, ``home``, ``default``). urdftool uses one of them as the
robot's home: the MJCF keyframe ``home`` and the stance a free robot starts
in on the floor (``convert --scene``).

Discovery (:func:`find_srdf`): ``NAME.srdf`` beside the model, else the
SRDFs in ``../srdf/`` (the ROS package layout ``urdf/`` + ``srdf/``, and
``robots/`` + ``srdf/`` in example-robot-data). Only 1-DOF values are read
(a multi-value entry such as a floating ``root_joint`` is skipped), and only
group states whose joints the robot has count. Of those, the first named like a
stance (:data:`PREFERRED`) wins, else the one covering the most joints.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Mapping
from dataclasses import dataclass
from pathlib import Path

from lxml import etree

from urdftool.safe_files import read_regular

#: Names of group states taken as the home configuration, best first.
PREFERRED = ("standing", "half_sitting", "home", "stand", "default", "neutral", "ready",
             "straight_standing", "init")


@dataclass(frozen=True)
class GroupState:
    name: str
    values: Mapping[str, float]


def read_group_states(path: str | Path) -> list[GroupState]:
    """Every ``<group_state>`` of the SRDF at *path* with its 1-DOF joint values (none on error)."""
    try:
        data = read_regular(str(path), "model")
        parser = etree.XMLParser(resolve_entities=False, no_network=True, huge_tree=False)
        root = etree.fromstring(data, parser)
    except (OSError, ValueError, etree.XMLSyntaxError):
        return []
    states: list[GroupState] = []
    for state in root.iter("group_state"):
        values: dict[str, float] = {}
        for joint in state.iter("joint"):
            name, text = joint.get("name"), (joint.get("value") or "").split()
            if not name or len(text) != 1:
                continue
            try:
                value = float(text[0])
            except ValueError:
                continue
            if math.isfinite(value):
                values[name] = value
        if values:
            states.append(GroupState(state.get("name") or "", values))
    return states


def find_srdf(model_path: str, robot_name: str | None) -> list[Path]:
    """SRDF files that may describe the model at *model_path*, nearest first."""
    if not model_path:
        return []
    model = Path(model_path)
    found: list[Path] = []
    for stem in dict.fromkeys(s for s in (model.stem.split(".")[0], robot_name) if s):
        candidate = model.with_name(f"{stem}.srdf")
        if candidate.is_file():
            found.append(candidate)
    folder = model.parent.parent / "srdf"
    if folder.is_dir():
        found.extend(sorted(p for p in folder.glob("*.srdf") if p.is_file() and p not in found))
    return found


def choose_state(states: list[GroupState], joints: Collection[str]) -> GroupState | None:
    """The group state to use as home for a robot with *joints*: every name must be one of them."""
    fitting = [s for s in states if set(s.values) <= set(joints)]
    if not fitting:
        return None
    for name in PREFERRED:
        for state in fitting:
            if state.name.lower() == name:
                return state
    return max(fitting, key=lambda s: len(s.values))


def home_from_srdf(model_path: str, robot_name: str | None,
                   joints: Collection[str]) -> tuple[Path, GroupState] | None:
    """The SRDF and group state giving the home configuration of the model, if any."""
    best: tuple[Path, GroupState] | None = None
    for path in find_srdf(model_path, robot_name):
        state = choose_state(read_group_states(path), joints)
        if state is None:
            continue
        preferred = state.name.lower() in PREFERRED
        if best is None or (preferred and best[1].name.lower() not in PREFERRED) or (
                preferred == (best[1].name.lower() in PREFERRED)
                and len(state.values) > len(best[1].values)):
            best = (path, state)
    return best
