"""3-vectors, rotations and 3×3 tensors as tuples of Python floats, for the check's per-link work.

The inertia rules place every shape of every link, rotate tensors into inertial frames and
compose welded links' poses: a few dozen multiplications each. On 3-vectors and 3×3 matrices a
NumPy call costs about 1 µs whatever it computes, a float operation about 30 ns, so the check
does this arithmetic here. The numbers are the same products and sums as NumPy's, in an order
that may differ in the last bit (BLAS may fuse a multiply and an add): a finding's ``data`` is a
measurement, and its last digit or two may move (docs/scale.md, "Eleventh pass").

The exporters and the dynamics pass keep NumPy (:mod:`urdftool.model.pose`): what they write
must not change by one bit.

Conventions: a tensor is its three rows; a rotation ``R`` maps child-frame coordinates to the
parent frame (``R @ v``), as :func:`urdftool.model.pose.rpy_to_matrix`.
"""

from __future__ import annotations

import math

from urdftool.model.pose import ZERO3, Pose, Vec3, finite3, unrotated

#: A 3×3 matrix as its rows: an inertia tensor (kg·m²) or a rotation.
Tensor3 = tuple[Vec3, Vec3, Vec3]

ZERO_TENSOR: Tensor3 = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))


def rotation(rpy: Vec3) -> Tensor3:
    """:func:`~urdftool.model.pose.rpy_to_matrix` of *rpy* (radians), as rows of floats."""
    r, p, y = finite3(rpy)
    cr, sr = math.cos(r), math.sin(r)
    cp, sp = math.cos(p), math.sin(p)
    cy, sy = math.cos(y), math.sin(y)
    return (
        (cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr),
        (sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr),
        (-sp, cp * sr, cp * cr),
    )


def apply(rotation: Tensor3, vector: Vec3) -> Vec3:
    """``rotation @ vector``."""
    (a, b, c), (d, e, f), (g, h, i) = rotation
    x, y, z = vector
    return (a * x + b * y + c * z, d * x + e * y + f * z, g * x + h * y + i * z)


def add(a: Vec3, b: Vec3) -> Vec3:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a: Vec3, b: Vec3) -> Vec3:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def norm(v: Vec3) -> float:
    """Euclidean length of *v*."""
    return math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])


def transpose(m: Tensor3) -> Tensor3:
    (a, b, c), (d, e, f), (g, h, i) = m
    return ((a, d, g), (b, e, h), (c, f, i))


def product(m: Tensor3, n: Tensor3) -> Tensor3:
    """``m @ n``."""
    (a, b, c), (d, e, f), (g, h, i) = m
    (p, q, r), (s, t, u), (v, w, x) = n
    return (
        (a * p + b * s + c * v, a * q + b * t + c * w, a * r + b * u + c * x),
        (d * p + e * s + f * v, d * q + e * t + f * w, d * r + e * u + f * x),
        (g * p + h * s + i * v, g * q + h * t + i * w, g * r + h * u + i * x),
    )


def scaled(m: Tensor3, factor: float) -> Tensor3:
    """Every entry of *m* times *factor*."""
    (a, b, c), (d, e, f), (g, h, i) = m
    return ((a * factor, b * factor, c * factor), (d * factor, e * factor, f * factor),
            (g * factor, h * factor, i * factor))


def added(m: Tensor3, n: Tensor3) -> Tensor3:
    (a, b, c), (d, e, f), (g, h, i) = m
    (p, q, r), (s, t, u), (v, w, x) = n
    return ((a + p, b + q, c + r), (d + s, e + t, f + u), (g + v, h + w, i + x))


def trace(m: Tensor3) -> float:
    return m[0][0] + m[1][1] + m[2][2]


def rotate_tensor(tensor: Tensor3, rpy: Vec3, inverse: bool = False) -> Tensor3:
    """``R @ tensor @ R.T`` (``R.T @ tensor @ R`` when *inverse*), R = :func:`rotation` of *rpy*:
    :func:`urdftool.model.pose.rotate_tensor` in floats. A frame at ``rpy="0 0 0"`` (most
    inertial frames, most shapes) gives back *tensor* itself: the identity's products would
    give back the same numbers."""
    if unrotated(rpy):
        return tensor
    turn = rotation(rpy)
    if inverse:
        return product(product(transpose(turn), tensor), turn)
    return product(product(turn, tensor), transpose(turn))


def shift_to_point(tensor: Tensor3, mass: float, offset: Vec3) -> Tensor3:
    """:func:`urdftool.physics.inertia.shift_to_point` in floats: the parallel-axis theorem,
    a tensor (kg·m²) about the centre of mass moved to a point *offset* (m) away."""
    x, y, z = offset
    square = x * x + y * y + z * z
    xy, xz, yz = 0.0 - x * y, 0.0 - x * z, 0.0 - y * z  # as NumPy's d·d·E − d dᵀ writes them
    (a, b, c), (d, e, f), (g, h, i) = tensor
    return (
        (a + mass * (square - x * x), b + mass * xy, c + mass * xz),
        (d + mass * xy, e + mass * (square - y * y), f + mass * yz),
        (g + mass * xz, h + mass * yz, i + mass * (square - z * z)),
    )


def compose(parent: Pose, child: Pose) -> Pose:
    """:meth:`Pose.compose <urdftool.model.pose.Pose.compose>` in floats: *child* (a pose in
    *parent*'s frame) expressed in *parent*'s own parent frame. A non-finite result (overflow)
    counts as 0, as there."""
    if unrotated(parent.rpy):  # a head's own frame, most welded chains: no products to make
        xyz = finite3(add(child.xyz, parent.xyz))
        return Pose(xyz, parent.rpy if unrotated(child.rpy) else _angles(rotation(child.rpy)))
    turn = rotation(parent.rpy)
    xyz = finite3(add(apply(turn, child.xyz), parent.xyz))
    if unrotated(child.rpy):
        return Pose(xyz, _angles(turn))
    return Pose(xyz, _angles(product(turn, rotation(child.rpy))))


def _angles(turn: Tensor3) -> Vec3:
    """:func:`~urdftool.model.pose.matrix_to_rpy` of a rotation given as rows of floats."""
    (r00, r01, _), (r10, r11, _), (r20, r21, r22) = turn
    if not all(map(math.isfinite, (*turn[0], *turn[1], *turn[2]))):
        return ZERO3
    # the same formula as matrix_to_rpy, without converting the rows to an array and back
    pitch = math.atan2(-r20, math.hypot(r00, r10))
    if abs(abs(pitch) - math.pi / 2) < 1e-9:  # gimbal lock: all of roll - yaw in yaw
        return (0.0, pitch, math.atan2(-r01, r11))
    return (math.atan2(r21, r22), pitch, math.atan2(r10, r00))
