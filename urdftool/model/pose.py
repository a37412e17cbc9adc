"""Rigid transforms in URDF's convention.

A :class:`Pose` is a translation ``xyz`` (metres) and fixed-axis roll-pitch-yaw
``rpy`` (radians): the rotation is ``Rz(yaw) @ Ry(pitch) @ Rx(roll)``, applied
to points expressed in the child frame to express them in the parent frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

# NumPy is imported inside the functions: reading and structurally checking a
# robot must not pay its import time (a CLI cold start is dominated by it).
if TYPE_CHECKING:
    import numpy.typing as npt

    Matrix = npt.NDArray[Any]
else:
    Matrix = Any

Vec3 = tuple[float, float, float]

ZERO3: Vec3 = (0.0, 0.0, 0.0)


def rpy_to_matrix(rpy: Vec3) -> Matrix:
    """3×3 rotation matrix for fixed-axis roll, pitch, yaw (radians)."""
    import numpy as np

    r, p, y = rpy
    cr, sr = math.cos(r), math.sin(r)
    cp, sp = math.cos(p), math.sin(p)
    cy, sy = math.cos(y), math.sin(y)
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def matrix_to_rpy(rotation: Matrix) -> Vec3:
    """Fixed-axis roll, pitch, yaw (radians) of a 3×3 rotation matrix."""
    r = rotation
    pitch = math.atan2(-r[2, 0], math.hypot(r[0, 0], r[1, 0]))
    if abs(abs(pitch) - math.pi / 2) < 1e-9:
        # Gimbal lock: only roll - yaw (or roll + yaw) is defined; put it all in yaw.
        yaw = math.atan2(-r[0, 1], r[1, 1])
        return (0.0, pitch, yaw)
    roll = math.atan2(r[2, 1], r[2, 2])
    yaw = math.atan2(r[1, 0], r[0, 0])
    return (roll, pitch, yaw)


def matrix_to_quaternion(rotation: Matrix) -> tuple[float, float, float, float]:
    """Unit quaternion ``(w, x, y, z)`` with ``w >= 0`` for a rotation matrix."""
    m = rotation
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    if trace > 0:
        s = 2.0 * math.sqrt(trace + 1.0)
        w, x, y, z = 0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        w, x, y, z = (m[2, 1] - m[1, 2]) / s, 0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s
    elif m[1, 1] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        w, x, y, z = (m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s
    else:
        s = 2.0 * math.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        w, x, y, z = (m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s
    norm = math.sqrt(w * w + x * x + y * y + z * z)
    sign = 1.0 if w >= 0 else -1.0
    return (sign * w / norm, sign * x / norm, sign * y / norm, sign * z / norm)


def quaternion_to_matrix(q: tuple[float, float, float, float]) -> Matrix:
    """Rotation matrix of a quaternion ``(w, x, y, z)`` (normalised first)."""
    import numpy as np

    w, x, y, z = q
    n = math.sqrt(w * w + x * x + y * y + z * z) or 1.0
    w, x, y, z = w / n, x / n, y / n, z / n
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def axis_angle_matrix(axis: Vec3, angle: float) -> Matrix:
    """Rotation by *angle* (radians) about the unit *axis* (Rodrigues)."""
    import numpy as np

    a = np.asarray(axis, dtype=float)
    n = float(np.linalg.norm(a))
    if n == 0.0:
        return np.eye(3)
    x, y, z = a / n
    c, s = math.cos(angle), math.sin(angle)
    t = 1.0 - c
    return np.array(
        [
            [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
        ]
    )


def homogeneous(rotation: Matrix, translation: Vec3 | Matrix) -> Matrix:
    """4×4 homogeneous transform from a rotation and a translation."""
    import numpy as np

    out = np.eye(4)
    out[:3, :3] = rotation
    out[:3, 3] = translation
    return out


@dataclass(frozen=True)
class Pose:
    """Translation (m) and fixed-axis roll-pitch-yaw (rad) of a child frame in its parent."""

    xyz: Vec3 = ZERO3
    rpy: Vec3 = ZERO3

    @property
    def rotation(self) -> Matrix:
        return rpy_to_matrix(self.rpy)

    @property
    def matrix(self) -> Matrix:
        """4×4 transform taking child-frame coordinates to parent-frame coordinates."""
        return homogeneous(self.rotation, self.xyz)

    @property
    def quaternion(self) -> tuple[float, float, float, float]:
        return matrix_to_quaternion(self.rotation)

    @property
    def is_identity(self) -> bool:
        return self.xyz == ZERO3 and self.rpy == ZERO3

    @classmethod
    def from_matrix(cls, transform: Matrix) -> Pose:
        t = transform[:3, 3]
        return cls((float(t[0]), float(t[1]), float(t[2])), matrix_to_rpy(transform[:3, :3]))

    def compose(self, other: Pose) -> Pose:
        """``self ∘ other``: *other* expressed in this pose's parent frame."""
        return Pose.from_matrix(self.matrix @ other.matrix)

    def inverse(self) -> Pose:
        import numpy as np

        return Pose.from_matrix(np.linalg.inv(self.matrix))


IDENTITY = Pose()


def planar_directions(axis: tuple[float, float, float]) -> tuple[npt.NDArray[Any], npt.NDArray[Any]]:
    """Two in-plane unit directions e1, e2 with e1 × e2 = axis (as in the tree view's FK)."""
    import numpy as np

    unit = np.asarray(axis, dtype=float)
    helper = np.array([1.0, 0.0, 0.0]) if abs(unit[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(unit, helper)
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(unit, e1)
