"""What a model rule may read: the robot, its tree, the facts about it, and the run's options."""

from __future__ import annotations

from collections.abc import Callable, Hashable, Mapping
from dataclasses import field
from typing import Any

from urdftool.model import KinematicTree, Robot
from urdftool.records import record

#: Keys of :attr:`CheckContext.options` that the pipeline sets for the facts, here so that the
#: pipeline names them without importing the facts (and their readers) a run may not need.
SRDF_OPTION = "srdf"
CONTROLLERS_OPTION = "controllers"
SIM_OPTION = "sim"


@record(frozen=False, eq=False)  # one run's state, equal only to itself
class CheckContext:
    """The robot under check, its kinematic tree, run-wide options and the facts computed so far.

    ``cache`` holds each fact once computed (mesh survey, mass properties, the
    dynamics pass, the simulation), so rules that share a fact share its cost.
    ``simulator`` is the smoke simulation, installed by the pipeline when one is
    asked for (see :mod:`urdftool.facts.simulation`).
    """

    robot: Robot
    tree: KinematicTree
    options: Mapping[str, Any] = field(default_factory=dict)
    cache: dict[Hashable, Any] = field(default_factory=dict)
    simulator: Callable[..., Any] | None = None
