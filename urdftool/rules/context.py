"""What a model rule may read: the robot, its tree, the facts about it, and the run's options."""

from __future__ import annotations

from collections.abc import Hashable, Mapping
from dataclasses import dataclass, field
from typing import Any

from urdftool.model import KinematicTree, Robot


@dataclass
class CheckContext:
    """The robot under check, its kinematic tree, run-wide options and a per-model cache."""

    robot: Robot
    tree: KinematicTree
    options: Mapping[str, Any] = field(default_factory=dict)
    cache: dict[Hashable, Any] = field(default_factory=dict)
