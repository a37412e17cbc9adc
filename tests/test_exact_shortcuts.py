"""Shortcuts the default check takes on 3-vectors and 3×3 tensors give NumPy's numbers to the bit.

A finding carries numbers in its ``data`` (``--format json``); a faster way to compute one must not
move its last digit, nor the sign of a zero (docs/scale.md, "Ninth pass"). Each shortcut is held
here to the products it replaces, on random inputs rich in ±0, tiny, huge and non-finite numbers.
(The inertia rules' shapes are placed in plain floats since the eleventh pass: their agreement
with NumPy, to rounding, is tested in ``tests/test_vec3.py``.)
"""

from __future__ import annotations

import math
import random

import numpy as np

from urdftool.backends.meshes import MeshFacts, scaled_info
from urdftool.model.pose import (
    axis_angle_matrix,
    finite,
    finite3,
    homogeneous,
    matrix_to_rpy,
    rotate_tensor,
    rpy_to_matrix,
    vector_norm,
)

N = 20_000


def _same(a: object, b: object) -> bool:
    """Equal numbers with equal signs (so +0 is not -0); any NaN matches any NaN."""
    pairs = zip(np.ravel(a).tolist(), np.ravel(b).tolist(), strict=True)
    sign = math.copysign
    nan = math.isnan
    return all((nan(x) and nan(y)) or (x == y and sign(1.0, x) == sign(1.0, y)) for x, y in pairs)


def _number(rng: random.Random, finite_only: bool) -> float:
    choices = [0.0, -0.0, 1.0, -1.0, 1e-300, -1e-300]
    choices += [rng.uniform(-1, 1), rng.uniform(-1e-4, 1e-4), rng.uniform(-5, 5)]
    if not finite_only:
        choices += [math.inf, -math.inf, math.nan]
    return rng.choice(choices)


def _angles(rng: random.Random) -> tuple[float, float, float]:
    roll, pitch, yaw = (rng.choice([0.0, 0.0, -0.0, rng.uniform(-3, 3)]) for _ in range(3))
    return roll, pitch, yaw


def test_rotate_tensor_is_the_products_with_the_rotation() -> None:
    rng = random.Random(1)
    for _ in range(N):
        finite_only = rng.random() < 0.8
        tensor = np.array([[_number(rng, finite_only) for _ in range(3)] for _ in range(3)])
        rpy = _angles(rng)
        rotation = rpy_to_matrix(rpy)
        with np.errstate(all="ignore"):
            assert _same(rotate_tensor(tensor, rpy), rotation @ tensor @ rotation.T)
            assert _same(rotate_tensor(tensor, rpy, inverse=True), rotation.T @ tensor @ rotation)


def test_vector_norm_is_numpys() -> None:
    rng = random.Random(2)
    for _ in range(N):
        values = [_number(rng, rng.random() < 0.8) for _ in range(rng.choice([1, 3, 3, 4]))]
        argument: object = tuple(values) if rng.random() < 0.3 else np.array(values)
        with np.errstate(all="ignore"):
            got = vector_norm(argument)  # type: ignore[arg-type]
            assert type(got) is float
            assert _same(got, float(np.linalg.norm(argument)))  # type: ignore[arg-type]
    assert vector_norm((3, 4)) == 5.0  # integers, as NumPy converts them


def test_matrix_to_rpy_reads_the_same_doubles() -> None:
    rng = random.Random(3)
    for _ in range(N):
        matrix = rpy_to_matrix(_angles(rng)) @ rpy_to_matrix(_angles(rng))
        if rng.random() < 0.05:
            matrix[rng.randrange(3), rng.randrange(3)] = rng.choice([math.inf, math.nan])
        r = matrix
        if not np.all(np.isfinite(r)):
            expected: tuple[float, float, float] = (0.0, 0.0, 0.0)
        else:
            pitch = math.atan2(-r[2, 0], math.hypot(r[0, 0], r[1, 0]))
            if abs(abs(pitch) - math.pi / 2) < 1e-9:
                expected = (0.0, pitch, math.atan2(-r[0, 1], r[1, 1]))
            else:
                expected = (math.atan2(r[2, 1], r[2, 2]), pitch, math.atan2(r[1, 0], r[0, 0]))
        assert _same(matrix_to_rpy(matrix), expected)


def test_axis_angle_matrix_on_floats_is_on_numpy_scalars() -> None:
    rng = random.Random(4)
    for _ in range(N):
        axis = (_number(rng, False), _number(rng, False), _number(rng, False))
        angle = rng.choice([0.0, -0.0, math.pi, rng.uniform(-7, 7)])
        a = np.asarray(finite3(axis), dtype=float)
        n = float(np.linalg.norm(a))
        if not (n > 0.0 and math.isfinite(n)):
            expected = np.eye(3)
        else:
            x, y, z = a / n  # NumPy scalars, as before
            c, s = math.cos(finite(angle)), math.sin(finite(angle))
            t = 1.0 - c
            expected = np.array([[t * x * x + c, t * x * y - s * z, t * x * z + s * y],
                                 [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
                                 [t * x * z - s * y, t * y * z + s * x, t * z * z + c]])
        assert _same(axis_angle_matrix(axis, angle), expected)


def test_homogeneous_is_an_identity_filled_in() -> None:
    rng = random.Random(5)
    for _ in range(2_000):
        rotation = np.array([[_number(rng, False) for _ in range(3)] for _ in range(3)])
        translation = tuple(_number(rng, False) for _ in range(3))
        expected = np.eye(4)
        expected[:3, :3] = rotation
        expected[:3, 3] = translation
        assert _same(homogeneous(rotation, translation), expected)


def test_unscaled_mesh_facts_are_the_scaled_formula_at_scale_one() -> None:
    second_moment = ((1.0, -0.0, 0.2), (-0.0, 2.0, 0.0), (0.2, 0.0, 3.0))
    facts = MeshFacts(8, 12, True, 0.5, (0.1, -0.0, 2.0), second_moment, (-1.0, -0.0, 0.0), (1.0, 0.5, 2.0))
    s = np.ones(3)
    second = 1.0 * (s[:, None] * np.asarray(facts.second_moment, dtype=float) * s[None, :])
    ends = np.array([np.asarray(facts.bounds_min) * s, np.asarray(facts.bounds_max) * s])
    info = scaled_info("m.stl", facts, (1.0, 1.0, 1.0))
    assert _same(info.inertia_unit_density, np.trace(second) * np.eye(3) - second)
    assert _same(info.center_mass, np.asarray(facts.center_mass) * s)
    assert _same((info.bounds_min, info.bounds_max), (ends.min(axis=0), ends.max(axis=0)))
    assert info.volume == facts.volume * 1.0
