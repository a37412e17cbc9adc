"""Mass properties and the inertia rules on small robots written here.

Shape formulas and compositions are checked against trimesh's mass properties
of the same solids (an independent computation); rule behaviour is checked on
robots built in the test, so each case shows one decision.
"""

from __future__ import annotations

import dataclasses
import math
import random
from pathlib import Path

import numpy as np
import pytest

from tests.conftest import SEEDS
from urdftool.model import (
    Box,
    Capsule,
    Collision,
    Cylinder,
    Inertial,
    Joint,
    JointType,
    KinematicTree,
    Link,
    Pose,
    Robot,
    Sphere,
)
from urdftool.model.pose import rpy_to_matrix
from urdftool.physics.bodies import mass_role, rigid_bodies
from urdftool.physics.inertia import MIN_MOMENT, assess, clearly_valid
from urdftool.physics.massprops import combine, place, rotate_into, shape_properties
from urdftool.pipeline.check import CheckOptions, check_file, run_rules
from urdftool.rules import Selection
from urdftool.rules.inertia_geometry import INERTIA_FACTOR

ROOT = Path(__file__).resolve().parent.parent


def _trimesh_solid(geometry: object):  # type: ignore[no-untyped-def]
    import trimesh

    if isinstance(geometry, Box):
        return trimesh.creation.box(extents=geometry.size)
    if isinstance(geometry, Cylinder):
        return trimesh.creation.cylinder(
            radius=geometry.radius, height=geometry.length, sections=256
        )
    if isinstance(geometry, Sphere):
        return trimesh.creation.icosphere(subdivisions=6, radius=geometry.radius)
    if isinstance(geometry, Capsule):
        return trimesh.creation.capsule(
            radius=geometry.radius, height=geometry.length, count=[128, 128]
        )
    raise AssertionError(geometry)


SHAPES = [Box((0.4, 0.3, 0.1)), Cylinder(0.08, 0.04), Sphere(0.05), Capsule(0.03, 0.2)]


@pytest.mark.parametrize("shape", SHAPES, ids=lambda s: s.kind)
def test_shape_formulas_match_trimesh(shape: object) -> None:
    solid = shape_properties(shape)  # type: ignore[arg-type]
    mesh = _trimesh_solid(shape)
    assert solid is not None
    assert solid.volume == pytest.approx(mesh.volume, rel=2e-3)
    np.testing.assert_allclose(solid.inertia, mesh.moment_inertia, rtol=3e-3, atol=1e-12)


def test_composition_with_origins_matches_trimesh() -> None:
    import trimesh

    parts = [
        (Cylinder(0.02, 0.3), Pose((0.0, 0.0, 0.15), (0.3, 0.0, 0.0))),
        (Box((0.1, 0.05, 0.08)), Pose((0.05, 0.0, 0.35), (0.0, 0.4, 1.0))),
    ]
    solid = combine(place(shape_properties(g), pose) for g, pose in parts)  # type: ignore[arg-type]
    meshes = []
    for geometry, pose in parts:
        mesh = _trimesh_solid(geometry)
        mesh.apply_transform(pose.matrix)
        meshes.append(mesh)
    union = trimesh.util.concatenate(meshes)
    assert solid is not None
    np.testing.assert_allclose(solid.center, union.center_mass, atol=1e-4)
    np.testing.assert_allclose(solid.inertia, union.moment_inertia, rtol=3e-3, atol=1e-9)


def test_rotation_into_inertial_frame_turns_the_spin_axis() -> None:
    wheel = place(shape_properties(Cylinder(0.08, 0.04)), Pose(rpy=(math.pi / 2, 0.0, 0.0)))  # type: ignore[arg-type]
    in_link = wheel.inertia_for_mass(2.0)
    spin = 2.0 * 0.08**2 / 2
    assert in_link[1][1] == pytest.approx(spin)  # the axle is y in the link frame
    in_inertial = rotate_into(in_link, Pose(rpy=(math.pi / 2, 0.0, 0.0)))
    assert in_inertial[2][2] == pytest.approx(spin)  # and z in the rolled inertial frame


def test_assess_absolute_floor_is_optional() -> None:
    tiny = np.diag([4.9e-21, 3.6e-20, 5.4e-20])
    assert assess(tiny).positive_definite  # relative test alone: fine
    assert not assess(tiny, abs_tol=MIN_MOMENT).positive_definite


def _tensors(rng: random.Random, count: int) -> list[tuple[tuple[float, float, float], ...]]:
    """Symmetric tensors of bodies and of no body, rotated at random: rods, plates and discs at
    the triangle's limit, placeholders, moments off by a little or a lot, tiny and huge
    scales, products with the wrong sign, zeros, NaN and infinities."""
    out = []
    for _ in range(count):
        kind = rng.random()
        a, b = rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0)
        if kind < 0.2:
            moments = [a, a + b * 10 ** -rng.randint(0, 14), a + b]  # near the triangle's limit
        elif kind < 0.3:
            moments = [10 ** -rng.randint(5, 18), a, a]  # a rod
        elif kind < 0.4:
            moments = [a, a, a * rng.choice([1.0, 0.5, 0.1])]  # placeholders, and off by a lot
        else:
            moments = [rng.uniform(-0.1, 1.0) for _ in range(3)]
        scale = 10.0 ** rng.randint(-100, 100) if rng.random() < 0.3 else 10.0 ** rng.randint(-9, 3)
        turn = rpy_to_matrix(tuple(rng.uniform(-math.pi, math.pi) for _ in range(3)))
        tensor = turn @ np.diag([m * scale for m in moments]) @ turn.T
        if rng.random() < 0.3:
            tensor = np.diag(np.diag(tensor))
        tensor = 0.5 * (tensor + tensor.T)
        if rng.random() < 0.05:
            tensor[0, 1] = tensor[1, 0] = -tensor[0, 1]
        if rng.random() < 0.02:
            tensor[rng.randrange(3), rng.randrange(3)] = rng.choice([0.0, -0.0, math.nan, math.inf])
        out.append(tuple(tuple(row) for row in tensor.tolist()))
    return out


@pytest.mark.parametrize("abs_tol", [0.0, MIN_MOMENT])
def test_a_clearly_valid_tensor_is_one_assess_finds_valid(abs_tol: float) -> None:
    """The test without eigenvalues never calls valid a tensor the eigenvalues call invalid, and
    tells most valid tensors (the others are the triangle's limits, or too close to a floor)."""
    valid = clear = 0
    for tensor in _tensors(random.Random(5), 20_000):
        try:
            verdict = assess(np.array(tensor), abs_tol=abs_tol).valid
        except np.linalg.LinAlgError:  # no eigenvalues to be found: nothing is clear either
            verdict = False
        if clearly_valid(tensor, abs_tol=abs_tol):  # type: ignore[arg-type]
            assert verdict, tensor
            clear += 1
        valid += verdict
    assert clear > 0.6 * valid


# -- robots built here ---------------------------------------------------------------


def _inertial(
    mass: float,
    diag: tuple[float, float, float],
    rpy: tuple[float, float, float] = (0, 0, 0),
    xyz: tuple[float, float, float] = (0, 0, 0),
) -> Inertial:
    return Inertial(mass, Inertial.tensor(diag[0], 0, 0, diag[1], 0, diag[2]), Pose(xyz, rpy))


def _robot(*links: Link, joints: tuple[Joint, ...] = ()) -> Robot:
    return Robot("r", links=links, joints=joints, path="built-in-test.urdf")


def _joint(name: str, parent: str, child: str, kind: JointType = JointType.REVOLUTE) -> Joint:
    return Joint(name, kind, parent, child, axis=(0.0, 0.0, 1.0))


def _codes(robot: Robot, select: str) -> list[tuple[str, str, str]]:
    found = run_rules(robot, Selection.of((select,), ()))
    return [(d.code, d.severity.value, d.element or "") for d in found]


BOX = (Collision(Box((0.1, 0.1, 0.1))),)


def test_massless_link_on_a_joint_is_an_error_and_welded_collider_a_warning() -> None:
    robot = _robot(
        Link("base", _inertial(2.0, (0.01, 0.01, 0.01)), collisions=BOX),
        Link("finger", _inertial(0.0, (0, 0, 0)), collisions=BOX),
        Link("sensor", _inertial(0.0, (0, 0, 0)), collisions=BOX),
        Link("optical_frame", _inertial(0.0, (0, 0, 0))),
        joints=(
            _joint("j", "base", "finger"),
            _joint("s", "base", "sensor", JointType.FIXED),
            _joint("o", "sensor", "optical_frame", JointType.FIXED),
        ),
    )
    found = _codes(robot, "I002")
    assert ("I002", "error", "link[finger]/inertial/mass") in found
    assert ("I002", "warning", "link[sensor]/inertial/mass") in found
    assert len(found) == 2  # the massless root-body frame is fine


def test_moving_massless_link_carried_by_a_welded_child_is_fine() -> None:
    robot = _robot(
        Link("base", _inertial(2.0, (0.01, 0.01, 0.01))),
        Link("bracket", None),
        Link("motor", _inertial(0.5, (1e-4, 1e-4, 1e-4))),
        joints=(_joint("j", "base", "bracket"), _joint("w", "bracket", "motor", JointType.FIXED)),
    )
    assert _codes(robot, "I001") == []
    bodies = {b.head: b for b in rigid_bodies(KinematicTree.of(robot))}
    assert bodies["bracket"].mass == pytest.approx(0.5)
    assert mass_role(robot.links[1], bodies["bracket"]) is None


def test_point_mass_is_an_error_only_where_nothing_gives_the_body_inertia() -> None:
    robot = _robot(
        Link("base", _inertial(2.0, (0.01, 0.01, 0.01))),
        Link("arm", _inertial(1.0, (0, 0, 0))),
        Link("tool", _inertial(0.1, (0, 0, 0))),
        joints=(_joint("j", "base", "arm"), _joint("t", "arm", "tool", JointType.FIXED)),
    )
    assert _codes(robot, "I004") == [("I004", "error", "link[arm]/inertial/inertia")]
    # give the arm inertia: the welded point-mass tool is then carried
    arm = dataclasses.replace(robot.links[1], inertial=_inertial(1.0, (0.01, 0.01, 0.002)))
    assert (
        _codes(dataclasses.replace(robot, links=(robot.links[0], arm, robot.links[2])), "I004")
        == []
    )


def test_triangle_violation_found_through_products_of_inertia() -> None:
    tensor = Inertial.tensor(3e-6, 2.5e-6, 0, 3e-6, 0, 1e-6)  # moments 5e-7, 1e-6, 5.5e-6
    robot = _robot(Link("finger", Inertial(0.02, tensor)))
    found = run_rules(robot, Selection.of(("I005",), ()))
    assert [d.code for d in found] == ["I005"]
    a, b, c = found[0].data["moments"]
    assert a + b < c


def _box_link(
    mass: float,
    size: tuple[float, float, float],
    rpy: tuple[float, float, float],
    scale: float = 1.0,
) -> Link:
    """A box link whose inertia is written, exactly, in an inertial frame rotated by *rpy*."""
    x, y, z = size
    in_box = np.diag([y * y + z * z, x * x + z * z, x * x + y * y]) * mass / 12 * scale
    frame = Pose(rpy=rpy)
    declared = frame.rotation.T @ in_box @ frame.rotation
    t = declared
    inertial = Inertial(
        mass, Inertial.tensor(t[0, 0], t[0, 1], t[0, 2], t[1, 1], t[1, 2], t[2, 2]), frame
    )
    return Link("body", inertial, collisions=(Collision(Box(size)),))


@pytest.mark.parametrize("rpy", [(0, 0, 0), (0.3, -1.1, 2.0), (math.pi / 2, 0, math.pi / 2)])
def test_exact_inertia_in_any_inertial_frame_is_quiet(rpy: tuple[float, float, float]) -> None:
    assert _codes(_robot(_box_link(3.0, (0.4, 0.2, 0.1), rpy)), "I006") == []


@pytest.mark.parametrize("scale", [10.0, 0.1, INERTIA_FACTOR * 1.01, 1 / (INERTIA_FACTOR * 1.01)])
def test_scaled_inertia_is_reported_with_the_computed_tensor(scale: float) -> None:
    robot = _robot(_box_link(3.0, (0.4, 0.2, 0.1), (0.3, -1.1, 2.0), scale))
    found = run_rules(robot, Selection.of(("I006",), ()))
    assert [d.code for d in found] == ["I006"]
    assert found[0].data["ratio"] == pytest.approx(scale, rel=1e-6)
    computed = np.array(found[0].data["computed"])
    assert np.trace(computed) * scale == pytest.approx(
        np.trace(robot.links[0].inertial.inertia_matrix)
    )
    assert "ixx=" in (found[0].help or "")


def test_example_message_reads_in_the_robots_terms() -> None:
    link = Link("lidar", _inertial(1e-5, (1e-6, 1e-6, 1e-6)), collisions=BOX)
    found = run_rules(_robot(link), Selection.of(("I006",), ()))
    assert found[0].message == (
        "link 'lidar': declared inertia is 60× the 0.1 m box at 1e-05 kg (ixx=iyy=izz=1.67e-08)"
    )


def _seed_findings(path: Path, code: str) -> list:  # type: ignore[type-arg]
    options = CheckOptions(select=(code,), package_paths=(str(SEEDS),))
    return [d for r in check_file(str(path), options) for d in r.diagnostics]


def test_m_robot_sensors_are_reported_and_its_rotated_wheels_are_not(seeds: Path) -> None:
    path = seeds / "hyundai_ngv" / "m_robot_description" / "urdf" / "m_robot.xacro"
    zero = {d.element.split("]")[0][5:] for d in _seed_findings(path, "zero-mass")}
    assert zero == {"camera", "laser_frame"}
    mismatched = {d.element for d in _seed_findings(path, "inertia-geometry-mismatch")}
    assert not any("wheel" in e for e in mismatched), mismatched


def test_diffbot_wheels_are_quiet_and_its_massless_lidar_is_reported() -> None:
    path = ROOT / "urdftool" / "examples" / "diffbot" / "urdf" / "diffbot.urdf.xacro"
    assert _seed_findings(path, "I006") == []
    assert [d.element for d in _seed_findings(path, "I002")] == ["link[lidar]/inertial/mass"]


def test_placeholder_wheel_inertia_of_my_robot_is_reported(seeds: Path) -> None:
    path = seeds / "go_chase_it" / "my_robot" / "urdf" / "my_robot.xacro"
    found = {d.element: d for d in _seed_findings(path, "I006")}
    wheel = found["link[left_wheel]/inertial/inertia"]
    assert wheel.data["ratio"] == pytest.approx(5.75, rel=0.01)
    # the hokuyo's placeholder is 60x its 0.1 m box, but it is welded to the chassis, whose
    # inertia it changes by far less than 3x: nothing any consumer computes depends on it
    assert "link[hokuyo]/inertial/inertia" not in found


def test_geometry_tensor_data_has_no_rounding_residue() -> None:
    """I006's ``computed`` tensor in ``data``: the products of a wheel's cylinder turned about x
    are zero, not residues of the rotation (1e-26 beside moments of 1e-2, digits that moved with
    the order of the operations between versions)."""
    path = SEEDS / "go_chase_it" / "my_robot" / "urdf" / "my_robot.xacro"
    [report] = check_file(str(path), CheckOptions(select=("I006",)))
    wheels = [d for d in report.diagnostics if "wheel" in d.message]
    assert len(wheels) == 2
    for finding in wheels:
        computed = (finding.data or {})["computed"]
        assert [computed[0][1], computed[0][2], computed[1][2], computed[1][0], computed[2][0],
                computed[2][1]] == [0.0] * 6
        assert computed[2][2] == pytest.approx(0.025050025)
