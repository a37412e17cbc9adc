"""Inertia tensors: principal moments, physical validity, and the inertia of shapes.

All tensors are 3×3 in kg·m², about the centre of mass. A tensor is physically
valid when it is symmetric positive definite and its principal moments satisfy
the triangle inequalities (A + B ≥ C for every ordering), which is what every
real mass distribution obeys and what MuJoCo's compiler enforces.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
else:
    # NumPy is imported on first use: a structural check must not pay for it.
    from urdftool.lazy import numpy as np

from urdftool.model.pose import Matrix, Vec3
from urdftool.model.robot import Inertia3
from urdftool.physics.vec3 import Tensor3
from urdftool.records import record

#: Relative tolerance (to the trace) within which the triangle inequality counts as met; absorbs
#: rounding in tensors written with a few digits (a flat plate's A + B = C).
RELATIVE_TOLERANCE = 1e-6

#: The fraction of the trace below which a principal moment counts as zero. Real bodies go far
#: below 1e-6: a 1 m rod of 1 mm diameter has 1.5e-6, a wire less, and every engine takes them
#: (MuJoCo's floor is absolute, :data:`MIN_MOMENT`). 1e-9 still reads a rank-deficient tensor as
#: singular, whose smallest moment is the eigenvalue routine's rounding (about 1e-16 of the trace).
ZERO_MOMENT = 1e-9

#: The smallest principal moment (kg·m²) MuJoCo accepts in a full tensor
#: (``mjEPS``); below it, a tensor is numerically zero in any engine.
MIN_MOMENT = 1e-14


def principal_moments(tensor: Matrix | Tensor3) -> tuple[Matrix, Matrix]:
    """Eigenvalues (ascending) and eigenvectors (columns) of the symmetric part of *tensor*."""
    matrix = np.asarray(tensor, dtype=float)
    sym = 0.5 * (matrix + matrix.T)
    values, vectors = np.linalg.eigh(sym)
    return values, vectors


def principal_moments_many(tensors: Sequence[Inertia3 | Matrix]) -> list[tuple[float, float, float]]:
    """:func:`principal_moments`' eigenvalues (ascending, kg·m²) of each tensor, in one call.

    The same numbers as one call per tensor: NumPy's ``eigh`` of a stack runs the same
    LAPACK routine on each matrix, and the symmetric part is the same elementwise sum. One
    call instead of a call per link saves NumPy's overhead per call (a tenth of the inertia
    rules' time). Raises :class:`numpy.linalg.LinAlgError` when any tensor fails.
    """
    if not tensors:
        return []
    stack = np.array(tensors, dtype=float)
    values = np.linalg.eigh(0.5 * (stack + stack.transpose(0, 2, 1)))[0].tolist()
    return [(v[0], v[1], v[2]) for v in values]


@record
class InertiaVerdict:
    """What is wrong with a tensor, if anything."""

    moments: tuple[float, float, float]
    positive_definite: bool
    #: ``None`` when the triangle inequalities hold, else the violated one as (a, b, c): a + b < c
    triangle_violation: tuple[float, float, float] | None

    @property
    def valid(self) -> bool:
        return self.positive_definite and self.triangle_violation is None


def assess(
    tensor: Matrix | Tensor3, rel_tol: float = RELATIVE_TOLERANCE, abs_tol: float = 0.0
) -> InertiaVerdict:
    """Positive-definiteness and triangle inequalities, with a tolerance relative to the trace.

    A principal moment counts as positive when it exceeds both :data:`ZERO_MOMENT`
    times the trace and ``abs_tol`` (kg·m²; :data:`MIN_MOMENT` is MuJoCo's floor); the triangle
    inequality holds within ``rel_tol`` of the trace.
    """
    values, _ = principal_moments(tensor)
    return judge_moments((float(values[0]), float(values[1]), float(values[2])), rel_tol, abs_tol)


def judge_moments(
    moments: tuple[float, float, float], rel_tol: float = RELATIVE_TOLERANCE, abs_tol: float = 0.0
) -> InertiaVerdict:
    """:func:`assess` on principal moments (kg·m², ascending) already computed: a check that
    judges one tensor against several tolerances decomposes it once."""
    a, b, c = moments
    scale = max(abs(a) + abs(b) + abs(c), 1e-300)
    tol = rel_tol * scale
    positive = a > ZERO_MOMENT * scale and a > abs_tol
    violation = None
    if a + b < c - tol:  # c is the largest, so this is the only inequality that can fail
        violation = (a, b, c)
    return InertiaVerdict((a, b, c), positive, violation)


#: How far above zero, against the size of the numbers that make it, a leading minor must be for
#: :func:`clearly_valid` to count it positive: rounding moves a minor by about 1e-15 of its size,
#: and the eigenvalue routine each moment by about 1e-15 of the tensor.
ROOM = 1e-9


def clearly_valid(tensor: Inertia3, rel_tol: float = RELATIVE_TOLERANCE, abs_tol: float = 0.0) -> bool:
    """True when :func:`assess` would find *tensor* (a symmetric tensor as written, kg·m²) valid,
    told without its eigenvalues; False when it is invalid or too close to a limit to tell
    without them (then ask :func:`assess`).

    Sylvester's criterion, on two matrices: the tensor less its floor (:data:`ZERO_MOMENT` of the
    trace, or ``abs_tol``) is positive definite when every principal moment is above the floor; and
    ``trace/2 − I``, the second moments of the mass (∫x² dm ...), is positive definite when the
    largest moment is below half the trace, that is below the sum of the two others (the
    triangle inequality). Both are asked with ROOM to spare, so that no rounding of the minors
    or of the eigenvalues could make :func:`assess` say otherwise. Most tensors of real robots
    are clear (951 of example-robot-data's 966 valid ones); a flat plate's A + B = C is not.
    """
    (xx, xy, xz), (yx, yy, yz), (zx, zy, zz) = tensor
    if xy != yx or xz != zx or yz != zy:
        return False  # assess judges the symmetric part
    size = abs(xx) + abs(yy) + abs(zz) + abs(xy) + abs(xz) + abs(yz)
    if not 1e-90 < size < 1e90:  # (also NaN and infinities) where the minors' cubes stay normal
        return False
    trace = xx + yy + zz
    room = ROOM * size
    floor = max(ZERO_MOMENT * (trace + room), abs_tol) + room
    half = trace / 2 - room
    return _clearly_positive_definite(xx - floor, xy, xz, yy - floor, yz, zz - floor, size) and (
        _clearly_positive_definite(half - xx, -xy, -xz, half - yy, -yz, half - zz, size)
    )


def _clearly_positive_definite(xx: float, xy: float, xz: float, yy: float, yz: float, zz: float,
                               size: float) -> bool:
    """Whether the symmetric matrix of these entries is positive definite, each of its leading
    minors above ROOM times its size (*size*: the sum of the entries' magnitudes, about)."""
    if not xx > ROOM * size:
        return False
    minor = xx * yy - xy * xy
    if not minor > ROOM * size * size:
        return False
    det = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz)
    return det > ROOM * size * size * size


def box_moments(mass: float, size: tuple[float, float, float]) -> Vec3:
    """Principal moments (kg·m², about x, y, z) of a solid box with full edge lengths *size* (m),
    about its centre, box frame."""
    x, y, z = size
    return (mass * (y * y + z * z) / 12, mass * (x * x + z * z) / 12, mass * (x * x + y * y) / 12)


def cylinder_moments(mass: float, radius: float, length: float) -> Vec3:
    """Solid cylinder along local z about its centre."""
    side = mass * (3 * radius * radius + length * length) / 12
    return (side, side, mass * radius * radius / 2)


def sphere_moments(mass: float, radius: float) -> Vec3:
    moment = (2.0 / 5.0) * mass * radius * radius
    return (moment, moment, moment)


def ellipsoid_moments(mass: float, radii: tuple[float, float, float]) -> Vec3:
    a, b, c = radii
    return (mass * (b * b + c * c) / 5, mass * (a * a + c * c) / 5, mass * (a * a + b * b) / 5)


def capsule_moments(mass: float, radius: float, length: float) -> Vec3:
    """Solid capsule along local z: a cylinder of *length* with two hemispherical caps."""
    r, h = radius, length
    v_cyl = math.pi * r * r * h
    v_caps = 4.0 / 3.0 * math.pi * r**3
    rho = mass / (v_cyl + v_caps)
    m_cyl, m_caps = rho * v_cyl, rho * v_caps
    izz = m_cyl * r * r / 2 + m_caps * 2 * r * r / 5
    # Each hemisphere: own moment about its centroid, shifted to the capsule centre
    # (centroid 3r/8 from the flat face, flat face at h/2).
    ixx_cyl = m_cyl * (3 * r * r + h * h) / 12
    ixx_caps = m_caps * (2 * r * r / 5 + h * h / 4 + 3 * h * r / 8)
    return (ixx_cyl + ixx_caps, ixx_cyl + ixx_caps, izz)


def shift_to_point(tensor: Matrix, mass: float, offset: Matrix) -> Matrix:
    """Parallel-axis theorem: a tensor about the centre of mass, moved to a point *offset* away."""
    d = np.asarray(offset, dtype=float)
    return tensor + mass * (float(d @ d) * np.eye(3) - np.outer(d, d))
