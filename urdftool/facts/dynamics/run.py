"""The dynamics pass of ``urdftool check``: whether it runs, and its result for one robot.

It runs by default when Pinocchio is installed; ``check --no-dynamics`` (rule
option ``dynamics=False``) turns it off, and then Pinocchio is not imported.
"""

from __future__ import annotations

import importlib.util
from collections.abc import Mapping
from typing import Any

from urdftool.budgets import budget
from urdftool.facts.dynamics.analysis import SAMPLES, analyse
from urdftool.facts.dynamics.coverage import NotCovered, floating_base, not_covered
from urdftool.facts.dynamics.linear import gravity_loads, moving_dof
from urdftool.model import KinematicTree, Robot
from urdftool.physics.bodies import kinematics_only
from urdftool.physics.sdf_defaults import sdf_default_inertials
from urdftool.records import record

#: Rule option that turns the pass on or off (default on).
OPTION = "dynamics"
#: Rule option: random configurations sampled besides the zero configuration.
SAMPLES_OPTION = "dynamics_samples"


@record
class Skipped:
    """The pass ran but could not say anything meaningful about the robot."""

    why: NotCovered


def enabled(options: Mapping[str, Any]) -> bool:
    """True unless switched off, and Pinocchio can be imported (found without importing it)."""
    if not options.get(OPTION, True):
        return False
    return importlib.util.find_spec("pinocchio") is not None


def dynamics_of(robot: Robot, tree: KinematicTree, options: Mapping[str, Any]) -> Any:
    """:class:`~urdftool.facts.dynamics.analysis.DynamicsAnalysis`, :class:`Skipped`, or ``None``
    when the pass is off or there is nothing to compute (no links, or a kinematic model with no
    ``<inertial>`` at all, which ``kinematics-only`` reports once)."""
    if not enabled(options) or not robot.links or kinematics_only(robot):
        return None
    reason = not_covered(robot, tree)
    if reason is not None:
        return Skipped(reason)
    robot = sdf_default_inertials(robot)
    floating, why = floating_base(robot, tree)
    samples = int(options.get(SAMPLES_OPTION, SAMPLES))
    if moving_dof(tree) > budget("dynamics-dof"):
        # Pinocchio's Data grows about as DOF³ and the conditioning needs dense DOF×DOF
        # matrices: large models get the linear gravity pass only (and a note that says so).
        return gravity_loads(robot, tree, floating, why, samples)
    return analyse(robot, tree, floating, why, samples)
