"""The inertia rules' arithmetic in plain floats agrees with NumPy's to rounding.

Since the eleventh pass (docs/scale.md) the check places shapes, rotates tensors and composes
welded links' poses on tuples of floats (:mod:`urdftool.physics.vec3`); the exporters keep
NumPy. A finding's ``data`` may then move in its last digit or two, never more: each function is
held here to the NumPy computation it replaces, on random finite inputs, at a relative tolerance
of 1e-12 (of the largest number involved).
"""

from __future__ import annotations

import math
import random

import numpy as np

from urdftool.backends.meshes import MeshFacts, scaled_info
from urdftool.model.pose import Pose, matrix_to_rpy, rotate_tensor, rpy_to_matrix
from urdftool.physics import vec3
from urdftool.physics.inertia import shift_to_point
from urdftool.physics.massprops import SolidProperties, _scaled_mesh, combine, place

N = 5_000


def _close(got: object, expected: object) -> bool:
    a, b = np.asarray(got, dtype=float), np.asarray(expected, dtype=float)
    scale = max(float(np.abs(b).max()), 1e-300)
    return a.shape == b.shape and bool(np.all(np.abs(a - b) <= 1e-12 * scale))


def _number(rng: random.Random) -> float:
    return rng.choice([0.0, -0.0, 1.0, -1.0, rng.uniform(-1, 1), rng.uniform(-1e-4, 1e-4),
                       rng.uniform(-5, 5)])


def _angles(rng: random.Random) -> tuple[float, float, float]:
    roll, pitch, yaw = (rng.choice([0.0, -0.0, rng.uniform(-3, 3), math.pi / 2]) for _ in range(3))
    return roll, pitch, yaw


def _tensor(rng: random.Random) -> vec3.Tensor3:
    rows = [[_number(rng) for _ in range(3)] for _ in range(3)]
    return tuple(tuple(row) for row in rows)  # type: ignore[return-value]


def _solid(rng: random.Random) -> SolidProperties:
    center = tuple(_number(rng) for _ in range(3))
    half = tuple(abs(_number(rng)) for _ in range(3))
    return SolidProperties(
        rng.uniform(0.1, 2.0), center, _tensor(rng), tuple(-h for h in half), half, "s"  # type: ignore[arg-type]
    )


def test_rotation_is_rpy_to_matrix() -> None:
    rng = random.Random(0)
    for _ in range(N):
        rpy = _angles(rng)
        assert vec3.rotation(rpy) == tuple(tuple(row) for row in rpy_to_matrix(rpy).tolist())


def test_place_is_numpys_products_with_the_rotation() -> None:
    rng = random.Random(1)
    for _ in range(N):
        solid = _solid(rng)
        origin = Pose(tuple(_number(rng) for _ in range(3)), _angles(rng))  # type: ignore[arg-type]
        placed = place(solid, origin)
        rotation = rpy_to_matrix(origin.rpy)
        corners = np.array([[x, y, z] for x in (solid.bounds_min[0], solid.bounds_max[0])
                            for y in (solid.bounds_min[1], solid.bounds_max[1])
                            for z in (solid.bounds_min[2], solid.bounds_max[2])])
        corners = corners @ rotation.T + np.asarray(origin.xyz)
        assert _close(placed.center, rotation @ np.asarray(solid.center) + np.asarray(origin.xyz))
        assert _close(placed.inertia, rotation @ np.asarray(solid.inertia) @ rotation.T)
        assert _close(placed.bounds_min, corners.min(axis=0))
        assert _close(placed.bounds_max, corners.max(axis=0))


def test_rotate_tensor_and_shift_are_numpys() -> None:
    rng = random.Random(2)
    for _ in range(N):
        tensor, rpy = _tensor(rng), _angles(rng)
        inverse = rng.random() < 0.5
        got = vec3.rotate_tensor(tensor, rpy, inverse)
        assert _close(got, rotate_tensor(np.array(tensor), rpy, inverse))
        offset, mass = tuple(_number(rng) for _ in range(3)), rng.uniform(0, 3)
        expected = shift_to_point(np.array(tensor), mass, offset)  # type: ignore[arg-type]
        assert _close(vec3.shift_to_point(tensor, mass, offset), expected)  # type: ignore[arg-type]


def test_combined_solids_are_the_sums_of_numpys() -> None:
    rng = random.Random(3)
    for _ in range(N // 5):
        parts = [_solid(rng) for _ in range(rng.randint(2, 4))]
        got = combine(parts)
        assert got is not None
        volume = sum(p.volume for p in parts)
        center = sum((p.volume * np.asarray(p.center) for p in parts), np.zeros(3)) / volume
        inertia = sum((shift_to_point(np.asarray(p.inertia), p.volume, np.asarray(p.center) - center)
                       for p in parts), np.zeros((3, 3)))
        assert _close(got.center, center)
        assert _close(got.inertia, inertia)


def test_compose_is_pose_compose() -> None:
    rng = random.Random(4)
    for _ in range(N):
        parent = Pose(tuple(_number(rng) for _ in range(3)), _angles(rng))  # type: ignore[arg-type]
        child = Pose(tuple(_number(rng) for _ in range(3)), _angles(rng))  # type: ignore[arg-type]
        got, expected = vec3.compose(parent, child), parent.compose(child)
        assert _close(got.xyz, expected.xyz)
        assert _close(rpy_to_matrix(got.rpy), rpy_to_matrix(expected.rpy))


def test_angles_are_matrix_to_rpy_on_the_same_doubles() -> None:
    rng = random.Random(5)
    for _ in range(N):
        turn = vec3.product(vec3.rotation(_angles(rng)), vec3.rotation(_angles(rng)))
        assert vec3._angles(turn) == matrix_to_rpy(np.array(turn))


def test_scaled_mesh_is_scaled_info() -> None:
    rng = random.Random(6)
    for _ in range(N // 5):
        second = _tensor(rng)
        second = tuple(tuple((a + b) / 2 for a, b in zip(row, col, strict=True))  # type: ignore[assignment]
                       for row, col in zip(second, vec3.transpose(second), strict=True))  # symmetric
        lo = tuple(-abs(_number(rng)) for _ in range(3))
        hi = tuple(abs(_number(rng)) for _ in range(3))
        center = tuple(_number(rng) for _ in range(3))
        facts = MeshFacts(8, 12, rng.random() < 0.5, rng.uniform(0.1, 2), center, second, lo, hi)  # type: ignore[arg-type]
        scale = rng.choice([(1.0, 1.0, 1.0), (0.001, 0.001, 0.001), (-1.0, 1.0, 2.0)])
        got, info = _scaled_mesh(facts, scale, "m"), scaled_info("m.stl", facts, scale)
        assert got is not None
        assert got.volume == info.volume
        assert got.approximate == (not info.watertight)
        assert _close(got.inertia, info.inertia_unit_density)
        assert _close(got.center, info.center_mass)
        assert _close((got.bounds_min, got.bounds_max), (info.bounds_min, info.bounds_max))
