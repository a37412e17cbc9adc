"""Total mass and centre of mass of a robot, from its own kinematics (no dynamics library).

The centre of mass is in the root link's frame with every joint at 0 (the pose
the file describes): the mass-weighted mean of each link's ``<inertial>``
origin placed by forward kinematics. Links without ``<inertial>`` weigh
nothing; links off the tree (a second root) are placed at the origin.
"""

from __future__ import annotations

from urdftool.model import KinematicTree, Robot
from urdftool.model.pose import Vec3


def center_of_mass(robot: Robot, tree: KinematicTree | None = None) -> Vec3 | None:
    """The centre of mass (m) in the root frame at q = 0, or ``None`` when nothing has mass."""
    import numpy as np

    tree = tree or KinematicTree.of(robot)
    poses = tree.forward_kinematics()
    total = 0.0
    moment = np.zeros(3)
    for link in robot.links:
        inertial = link.inertial
        if inertial is None or inertial.mass <= 0:
            continue
        pose = poses.get(link.name, np.eye(4))
        moment += inertial.mass * (pose[:3, :3] @ np.asarray(inertial.origin.xyz, dtype=float) + pose[:3, 3])
        total += inertial.mass
    if total <= 0:
        return None
    x, y, z = (float(v) for v in moment / total)
    return (x, y, z)
