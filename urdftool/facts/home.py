"""The robot at its home configuration (every joint at 0): each link frame's world pose.

Several rule families place the robot at home (the mirror-symmetry rules, the
robot's size that judges mesh units, camera frames); the forward kinematics of
a large robot is many 4×4 products, so it is computed once per check.
"""

from __future__ import annotations

from urdftool.facts.context import CheckContext
from urdftool.model.pose import Matrix


def home_poses(ctx: CheckContext) -> dict[str, Matrix]:
    """World pose (4×4, metres) of every link frame at q = 0, roots at the identity.

    Shared by every rule of the run: read it, never write into it.
    """
    key = "home-poses"
    if key not in ctx.cache:
        ctx.cache[key] = ctx.tree.forward_kinematics()
    poses: dict[str, Matrix] = ctx.cache[key]
    return poses
