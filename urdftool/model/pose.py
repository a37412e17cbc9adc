"""Rigid transforms in URDF's convention.

A :class:`Pose` is a translation ``xyz`` (metres) and fixed-axis roll-pitch-yaw
``rpy`` (radians): the rotation is ``Rz(yaw) @ Ry(pitch) @ Rx(roll)``, applied
to points expressed in the child frame to express them in the parent frame.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

from urdftool.records import record

# NumPy is imported inside the functions: reading and structurally checking a
# robot must not pay its import time (a CLI cold start is dominated by it).
if TYPE_CHECKING:
    import numpy.typing as npt

    Matrix = npt.NDArray[Any]
else:
    Matrix = Any

Vec3 = tuple[float, float, float]

ZERO3: Vec3 = (0.0, 0.0, 0.0)


def finite(value: float) -> float:
    """*value* when finite, else 0.0.

    The readers never put NaN or infinity into a model (they report the value as
    ``invalid-number`` and treat it as unwritten); this keeps pose math total for
    models built in code and for arithmetic that overflows.
    """
    return value if math.isfinite(value) else 0.0


def finite3(values: Vec3) -> Vec3:
    return (finite(values[0]), finite(values[1]), finite(values[2]))


def vector_norm(values: Vec3 | Matrix) -> float:
    """``float(numpy.linalg.norm(values))``, the same number, for the hot paths.

    NumPy's norm of a vector (or the Frobenius norm of a matrix) is the square root of the
    array's dot product with itself; this computes exactly that, without the function's
    dispatch, which costs more than the arithmetic on a 3-vector (tens of thousands of calls a
    check: shapes' sizes, joint axes, centres of mass).
    """
    import numpy as np

    if type(values) is np.ndarray and values.ndim == 1 and values.dtype == np.float64:
        return math.sqrt(values.dot(values))  # the common case, without a conversion
    array = np.asarray(values)
    if not issubclass(array.dtype.type, (np.inexact, np.object_)):
        array = array.astype(float)
    array = array.ravel(order="K")
    return math.sqrt(array.dot(array))


def unrotated(rpy: Vec3) -> bool:
    """Whether ``rpy_to_matrix(rpy)`` holds only ones and zeros: every angle +0.

    Its products with a vector or a tensor give back the same numbers, with two exceptions: a
    sum of zeros is +0 unless every term is -0 (an entry that is -0 may come back +0), and
    0 × ∞ is NaN. :func:`identity_exact` tells when neither can happen; then the products can
    be skipped, and the numbers are the same to the bit. (-0 angles give a matrix with other
    signs of zero, so they do not count.)
    """
    roll, pitch, yaw = rpy
    return (
        roll == 0.0 and pitch == 0.0 and yaw == 0.0
        and math.copysign(1.0, roll) + math.copysign(1.0, pitch) + math.copysign(1.0, yaw) == 3.0
    )


def identity_exact(values: Iterable[float]) -> bool:
    """Whether every number is finite and none is -0 (see :func:`unrotated`)."""
    values = tuple(values)
    if not all(map(math.isfinite, values)):
        return False
    return 0.0 not in values or all([math.copysign(1.0, v) > 0.0 for v in values if v == 0.0])


def rotate_tensor(tensor: Matrix, rpy: Vec3, inverse: bool = False) -> Matrix:
    """``R @ tensor @ R.T`` (``R.T @ tensor @ R`` when *inverse*), R = ``rpy_to_matrix(rpy)``:
    a tensor (kg·m²) written in a frame at *rpy*, expressed in its parent frame (or back).

    A frame at ``rpy="0 0 0"`` (most inertial frames) returns a copy without the products,
    when :func:`unrotated` says that gives the same numbers.
    """
    if unrotated(rpy) and identity_exact(tensor.ravel().tolist()):
        copied: Matrix = tensor.copy()
        return copied
    rotation = rpy_to_matrix(rpy)
    rotated: Matrix = rotation.T @ tensor @ rotation if inverse else rotation @ tensor @ rotation.T
    return rotated


def rpy_to_matrix(rpy: Vec3) -> Matrix:
    """3×3 rotation matrix for fixed-axis roll, pitch, yaw (radians); non-finite angles count as 0."""
    import numpy as np

    r, p, y = finite3(rpy)
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
    import numpy as np

    # On Python floats: the same doubles as NumPy's scalars (so the same angles), without a
    # NumPy scalar per element read; a robot's poses are composed thousands of times a check.
    rows = np.asarray(rotation, dtype=float).tolist()
    if not all(map(math.isfinite, (*rows[0], *rows[1], *rows[2]))):
        return ZERO3
    (r00, r01, _), (r10, r11, _), (r20, r21, r22) = rows
    pitch = math.atan2(-r20, math.hypot(r00, r10))
    if abs(abs(pitch) - math.pi / 2) < 1e-9:
        # Gimbal lock: only roll - yaw (or roll + yaw) is defined; put it all in yaw.
        yaw = math.atan2(-r01, r11)
        return (0.0, pitch, yaw)
    roll = math.atan2(r21, r22)
    yaw = math.atan2(r10, r00)
    return (roll, pitch, yaw)


def matrix_to_quaternion(rotation: Matrix) -> tuple[float, float, float, float]:
    """Unit quaternion ``(w, x, y, z)`` with ``w >= 0`` for a rotation matrix."""
    import numpy as np

    m = np.asarray(rotation, dtype=float)
    if not np.all(np.isfinite(m)):
        return (1.0, 0.0, 0.0, 0.0)
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
    if not norm > 0.0:
        return (1.0, 0.0, 0.0, 0.0)
    sign = 1.0 if w >= 0 else -1.0
    return (sign * w / norm, sign * x / norm, sign * y / norm, sign * z / norm)


def quaternion_to_matrix(q: tuple[float, float, float, float]) -> Matrix:
    """Rotation matrix of a quaternion ``(w, x, y, z)`` (normalised first)."""
    import numpy as np

    w, x, y, z = (finite(v) for v in q)
    n = math.sqrt(w * w + x * x + y * y + z * z)
    if not (n > 0.0 and math.isfinite(n)):
        return np.eye(3)
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

    a = np.asarray(finite3(axis), dtype=float)
    n = vector_norm(a)
    if not (n > 0.0 and math.isfinite(n)):
        return np.eye(3)
    x, y, z = (a / n).tolist()  # Python floats: the same doubles, cheaper arithmetic
    angle = finite(angle)
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

    out = np.empty((4, 4))  # every entry written below: the numbers of an identity filled in
    out[:3, :3] = rotation
    out[:3, 3] = translation
    out[3] = (0.0, 0.0, 0.0, 1.0)
    return out


@record
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
        """The pose of a 4×4 transform; non-finite entries (overflow) count as 0."""
        t = transform[:3, 3]
        xyz = finite3((float(t[0]), float(t[1]), float(t[2])))
        return cls(xyz, matrix_to_rpy(transform[:3, :3]))

    def compose(self, other: Pose) -> Pose:
        """``self ∘ other``: *other* expressed in this pose's parent frame."""
        import numpy as np

        with np.errstate(all="ignore"):  # an overflow is clamped by from_matrix, not warned about
            return Pose.from_matrix(self.matrix @ other.matrix)

    def inverse(self) -> Pose:
        """The inverse transform (rotation transposed; no general matrix inversion to fail)."""
        import numpy as np

        out = np.eye(4)
        rotation = self.rotation.T
        out[:3, :3] = rotation
        with np.errstate(all="ignore"):
            out[:3, 3] = -rotation @ np.asarray(finite3(self.xyz), dtype=float)
        return Pose.from_matrix(out)


IDENTITY = Pose()


def planar_directions(axis: tuple[float, float, float]) -> tuple[npt.NDArray[Any], npt.NDArray[Any]]:
    """Two in-plane unit directions e1, e2 with e1 × e2 = axis (as in the tree view's FK)."""
    import numpy as np

    unit = np.asarray(axis, dtype=float)
    helper = np.array([1.0, 0.0, 0.0]) if abs(unit[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(unit, helper)
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(unit, e1)
