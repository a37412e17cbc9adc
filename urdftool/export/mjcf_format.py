"""Number and pose formatting for MJCF: exact, stable text.

Floats are written with Python's shortest round-trip representation, so the
number MuJoCo parses is bit-for-bit the number urdftool computed (verification
at 1e-9 needs no slack for printing) and reruns give identical bytes.
"""

from __future__ import annotations

import numpy as np

from urdftool.export.numbers import vec
from urdftool.model.pose import Matrix, Pose, matrix_to_quaternion


def quat_of(rotation: Matrix) -> tuple[float, float, float, float]:
    """Unit quaternion ``(w, x, y, z)`` of a rotation matrix, exact for the identity."""
    if np.array_equal(rotation, np.eye(3)):
        return (1.0, 0.0, 0.0, 0.0)
    return matrix_to_quaternion(rotation)


def pose_attributes(pose: Pose) -> dict[str, str]:
    """``pos`` and ``quat`` of a frame in its parent, omitting identity parts."""
    out: dict[str, str] = {}
    if any(v != 0.0 for v in pose.xyz):
        out["pos"] = vec(pose.xyz)
    if any(v != 0.0 for v in pose.rpy):
        q = quat_of(pose.rotation)
        if q != (1.0, 0.0, 0.0, 0.0):
            out["quat"] = vec(q)
    return out


def transform_attributes(transform: Matrix) -> dict[str, str]:
    """``pos`` and ``quat`` of a 4×4 transform, omitting identity parts."""
    out: dict[str, str] = {}
    t = transform[:3, 3]
    if any(v != 0.0 for v in t):
        out["pos"] = vec(t)
    q = quat_of(transform[:3, :3])
    if q != (1.0, 0.0, 0.0, 0.0):
        out["quat"] = vec(q)
    return out
