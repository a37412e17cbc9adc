"""The typed robot model: frozen dataclasses and the kinematic-tree view."""

from urdftool.model.geometry import Box, Capsule, Cylinder, Ellipsoid, Geometry, Mesh, Plane, Sphere
from urdftool.model.pose import IDENTITY, Pose
from urdftool.model.robot import (
    Calibration,
    Collision,
    Dynamics,
    Extension,
    Inertial,
    Joint,
    JointType,
    Limit,
    Link,
    LoopClosure,
    Material,
    Mimic,
    Robot,
    SafetyController,
    Visual,
)
from urdftool.model.tree import KinematicTree

__all__ = [
    "IDENTITY",
    "Box",
    "Calibration",
    "Capsule",
    "Collision",
    "Cylinder",
    "Dynamics",
    "Ellipsoid",
    "Extension",
    "Geometry",
    "Inertial",
    "Joint",
    "JointType",
    "KinematicTree",
    "Limit",
    "Link",
    "LoopClosure",
    "Material",
    "Mesh",
    "Mimic",
    "Plane",
    "Pose",
    "Robot",
    "SafetyController",
    "Sphere",
    "Visual",
]
