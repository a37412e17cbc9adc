"""``convert --collision primitives`` fits capsules: rods become capsules, other shapes do not.

The rod is a tessellated capsule written by the test itself (tilted and moved
off the origin, under a collision ``<origin>`` of its own); MuJoCo and PyBullet
load the converted files and the capsule they see is compared with the mesh.
The real case is example-robot-data's Panda: its elbow links 3 and 4 are
capsules within 50 % of their volume (boxes and cylinders are over 75 % off),
its other links are not; at the default 15 % no link is.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from tests.conftest import ERD
from urdftool.backends.collision_shapes import simplify
from urdftool.backends.mesh_shape import shape_facts
from urdftool.cli import main

trimesh = pytest.importorskip("trimesh")

PANDA = ERD / "panda_description" if ERD else None
needs_panda = pytest.mark.skipif(PANDA is None or not PANDA.is_dir(),
                                 reason="example-robot-data not installed")
RADIUS, LENGTH = 0.03, 0.2
#: the rod's pose in its mesh file, and the collision origin it is placed at
MESH_POSE = trimesh.transformations.euler_matrix(0.3, -0.5, 0.2)
MESH_POSE[:3, 3] = (0.01, -0.02, 0.1)
ORIGIN = trimesh.transformations.euler_matrix(0.0, 0.4, 0.0)
ORIGIN[:3, 3] = (0.1, 0.0, 0.05)

URDF = """<?xml version="1.0"?>
<robot name="rod">
  <link name="base">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <visual><geometry><mesh filename="{mesh}"/></geometry></visual>
    <collision name="shell">
      <origin xyz="0.1 0 0.05" rpy="0 0.4 0"/>
      <geometry><mesh filename="{mesh}"/></geometry>
    </collision>
  </link>
</robot>
"""


@pytest.fixture(autouse=True)
def own_cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("URDFTOOL_CACHE_DIR", str(tmp_path / "cache"))


def write_shape(folder: Path, name: str, mesh: Any) -> Path:
    path = folder / name
    mesh.export(path)
    return path


def rod(folder: Path) -> Path:
    """A URDF whose collision mesh is a capsule (r 3 cm, 20 cm between its cap centres)."""
    mesh = trimesh.creation.capsule(height=LENGTH, radius=RADIUS, count=[32, 32])
    mesh.apply_transform(MESH_POSE)
    write_shape(folder, "rod.stl", mesh)
    source = folder / "rod.urdf"
    source.write_text(URDF.format(mesh="rod.stl"), encoding="utf-8")
    return source


def true_ends() -> np.ndarray:
    """The centres of the rod's end caps in the link frame."""
    ends = np.array([[0.0, 0.0, -LENGTH / 2, 1.0], [0.0, 0.0, LENGTH / 2, 1.0]])
    return np.asarray((ORIGIN @ MESH_POSE @ ends.T).T[:, :3])


def same_ends(found: np.ndarray, tol: float = 2e-3) -> bool:
    """The two points *found* are the rod's cap centres, in either order (within *tol* m)."""
    want = true_ends()
    return bool(min(np.abs(found - want).max(), np.abs(found[::-1] - want).max()) < tol)


def convert(source: Path, out: Path, *args: str) -> str:
    result = CliRunner().invoke(main, ["convert", str(source), "-o", str(out), "--collision", "primitives",
                                       *args])
    assert result.exit_code == 0, result.output
    return result.output


def capsule_volume(radius: float, length: float) -> float:
    return float(np.pi * radius**2 * length + 4 / 3 * np.pi * radius**3)


# -- fitting ---------------------------------------------------------------------


def test_a_capsule_mesh_becomes_a_capsule(tmp_path: Path) -> None:
    path = write_shape(tmp_path, "rod.stl", trimesh.creation.capsule(height=LENGTH, radius=RADIUS))
    result = simplify(str(path), "primitives")
    assert result.primitive is not None and result.primitive.kind == "capsule"
    radius, length = result.primitive.size
    assert radius == pytest.approx(RADIUS, rel=0.01) and length == pytest.approx(LENGTH, rel=0.01)
    assert 0 <= result.volume_error < 0.03
    assert result.volume == pytest.approx(capsule_volume(radius, length))


@pytest.mark.parametrize(("shape", "kind"), [
    (lambda: trimesh.creation.cylinder(radius=RADIUS, height=LENGTH, sections=64), "cylinder"),
    (lambda: trimesh.creation.box((0.05, 0.1, 0.2)), "box"),
    (lambda: trimesh.creation.icosphere(subdivisions=3, radius=0.05), "sphere"),
])
def test_other_shapes_do_not_become_capsules(tmp_path: Path, shape: Any, kind: str) -> None:
    path = write_shape(tmp_path, f"{kind}.stl", shape())
    result = simplify(str(path), "primitives")
    assert result.primitive is not None and result.primitive.kind == kind


def test_a_capsule_beyond_the_tolerance_falls_back_to_the_hull(tmp_path: Path) -> None:
    # an L of two rods: the enclosing capsule is more than twice its volume
    one = trimesh.creation.capsule(height=LENGTH, radius=RADIUS)
    other = one.copy()
    other.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, (0, 1, 0)))
    other.apply_translation((LENGTH / 2, 0, LENGTH / 2))
    path = write_shape(tmp_path, "ell.stl", trimesh.boolean.union([one, other], engine="manifold"))
    result = simplify(str(path), "primitives")
    assert result.mode == "hull" and "capsule" in result.note


def test_a_mesh_with_no_hull_is_kept_with_a_warning(tmp_path: Path) -> None:
    # two triangles on three distinct points: qhull has no hull to give
    sliver = trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 1e-9, 0]], [[0, 1, 3], [1, 2, 3]])
    write_shape(tmp_path, "sliver.stl", sliver)
    source = tmp_path / "sliver.urdf"
    source.write_text(URDF.format(mesh="sliver.stl"), encoding="utf-8")
    output = convert(source, tmp_path / "out.urdf")
    assert "kept as it is (no convex hull" in output
    assert ET.parse(tmp_path / "out.urdf").getroot().find("link/collision/geometry/mesh") is not None


# -- writers, read back by the engines ---------------------------------------------


def test_mjcf_capsule_in_mujoco(tmp_path: Path) -> None:
    mujoco = pytest.importorskip("mujoco")
    output = convert(rod(tmp_path), tmp_path / "rod.xml")
    assert "became a capsule; volume error +" in output
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "rod.xml"))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    capsules = [g for g in range(model.ngeom) if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_CAPSULE]
    assert len(capsules) == 1
    geom = capsules[0]
    radius, half = (float(v) for v in model.geom_size[geom][:2])
    assert radius == pytest.approx(RADIUS, rel=0.01) and 2 * half == pytest.approx(LENGTH, rel=0.01)
    axis = data.geom_xmat[geom].reshape(3, 3)[:, 2]
    ends = np.array([data.geom_xpos[geom] - half * axis, data.geom_xpos[geom] + half * axis])
    assert same_ends(ends)
    mesh_volume = capsule_volume(RADIUS, LENGTH)
    assert abs(capsule_volume(radius, 2 * half) - mesh_volume) / mesh_volume < 0.15


def test_pybullet_reads_the_capsule_element(tmp_path: Path) -> None:
    pybullet = pytest.importorskip("pybullet")
    convert(rod(tmp_path), tmp_path / "rod_pb.urdf", "--to", "pybullet")
    written = ET.parse(tmp_path / "rod_pb.urdf").getroot()
    assert len(written.findall("link/collision/geometry/capsule")) == 1
    client = pybullet.connect(pybullet.DIRECT)
    try:
        body = pybullet.loadURDF(str(tmp_path / "rod_pb.urdf"), physicsClientId=client)
        shapes = pybullet.getCollisionShapeData(body, -1, physicsClientId=client)
    finally:
        pybullet.disconnect(client)
    assert [s[2] for s in shapes] == [pybullet.GEOM_CAPSULE]
    length, radius = shapes[0][3][:2]
    assert radius == pytest.approx(RADIUS, rel=0.01) and length == pytest.approx(LENGTH, rel=0.01)
    position, orientation = np.array(shapes[0][5]), shapes[0][6]
    axis = np.array(pybullet.getMatrixFromQuaternion(orientation)).reshape(3, 3)[:, 2]
    assert same_ends(np.array([position - length / 2 * axis, position + length / 2 * axis]))


def test_plain_urdf_gets_a_cylinder_and_two_spheres(tmp_path: Path) -> None:
    pybullet = pytest.importorskip("pybullet")
    output = convert(rod(tmp_path), tmp_path / "out.urdf")
    assert "became a capsule (written as a cylinder and two spheres" in output
    written = ET.parse(tmp_path / "out.urdf").getroot()
    assert not written.findall(".//capsule")
    names = [c.get("name") for c in written.iter("collision")]
    assert names == ["shell_cylinder", "shell_end0", "shell_end1"]
    assert written.find("link/visual/geometry/mesh") is not None  # the visual keeps its mesh
    client = pybullet.connect(pybullet.DIRECT)
    try:
        body = pybullet.loadURDF(str(tmp_path / "out.urdf"), physicsClientId=client)
        shapes = pybullet.getCollisionShapeData(body, -1, physicsClientId=client)
    finally:
        pybullet.disconnect(client)
    spheres = [s for s in shapes if s[2] == pybullet.GEOM_SPHERE]
    assert len(shapes) == 3 and len(spheres) == 2
    assert all(s[3][0] == pytest.approx(RADIUS, rel=0.01) for s in spheres)
    assert same_ends(np.array([s[5] for s in spheres]))


def test_sdf_gets_a_cylinder_and_two_spheres(tmp_path: Path) -> None:
    convert(rod(tmp_path), tmp_path / "out.sdf")
    written = ET.parse(tmp_path / "out.sdf").getroot()
    kinds = [g[0].tag for g in written.iter("geometry") if g[0].tag != "mesh"]
    assert sorted(kinds) == ["cylinder", "sphere", "sphere"]


def test_output_is_deterministic(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    source = rod(tmp_path)
    convert(source, tmp_path / "first.xml")
    convert(source, tmp_path / "cached.xml")  # from the collision cache
    monkeypatch.setenv("URDFTOOL_CACHE_DIR", str(tmp_path / "fresh-cache"))
    convert(source, tmp_path / "fresh.xml")
    first = (tmp_path / "first.xml").read_bytes()
    assert b'type="capsule"' in first
    assert first == (tmp_path / "cached.xml").read_bytes() == (tmp_path / "fresh.xml").read_bytes()


# -- a real robot ------------------------------------------------------------------


def inside(vertices: np.ndarray, centre: np.ndarray, axis: np.ndarray, radius: float, half: float) -> bool:
    """Every vertex within the capsule (0.1 mm slack for the file's single precision)."""
    along = np.clip((vertices - centre) @ axis, -half, half)
    return bool((np.linalg.norm(vertices - centre - along[:, None] * axis, axis=1) <= radius + 1e-4).all())


@pytest.mark.slow
@needs_panda
def test_panda_elbow_links_become_capsules_in_mujoco(tmp_path: Path) -> None:
    mujoco = pytest.importorskip("mujoco")
    assert PANDA is not None
    convert(PANDA / "urdf" / "panda.urdf", tmp_path / "panda.xml", "--collision-tolerance", "0.5")
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "panda.xml"))
    capsules = {mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, model.geom_bodyid[g]): g
                for g in range(model.ngeom) if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_CAPSULE}
    assert sorted(capsules) == ["panda_link3", "panda_link4"]
    for link, geom in capsules.items():
        mesh = PANDA / "meshes" / "collision" / f"{link.removeprefix('panda_')}.stl"
        radius, half = (float(v) for v in model.geom_size[geom][:2])
        rotation = np.zeros(9)
        mujoco.mju_quat2Mat(rotation, model.geom_quat[geom])
        vertices = np.asarray(trimesh.load(mesh, force="mesh").vertices)  # the link frame is the body's
        assert inside(vertices, np.asarray(model.geom_pos[geom]), rotation.reshape(3, 3)[:, 2], radius, half)
        mesh_volume = shape_facts(str(mesh)).solid_volume
        assert 0.3 < (capsule_volume(radius, 2 * half) - mesh_volume) / mesh_volume < 0.5


@pytest.mark.slow
@needs_panda
def test_panda_elbow_capsules_in_pybullet(tmp_path: Path) -> None:
    pybullet = pytest.importorskip("pybullet")
    assert PANDA is not None
    convert(PANDA / "urdf" / "panda.urdf", tmp_path / "panda_pb.urdf", "--to", "pybullet",
            "--collision-tolerance", "0.5")
    client = pybullet.connect(pybullet.DIRECT)
    try:
        body = pybullet.loadURDF(str(tmp_path / "panda_pb.urdf"), physicsClientId=client)
        found = []
        for index in range(pybullet.getNumJoints(body, physicsClientId=client)):
            link = pybullet.getJointInfo(body, index, physicsClientId=client)[12].decode()
            shapes = pybullet.getCollisionShapeData(body, index, physicsClientId=client)
            # shapes are placed in the link's inertial frame
            inertial = pybullet.getDynamicsInfo(body, index, physicsClientId=client)[3:5]
            found.extend((link, shape, inertial) for shape in shapes if shape[2] == pybullet.GEOM_CAPSULE)
    finally:
        pybullet.disconnect(client)
    assert sorted(link for link, _, _ in found) == ["panda_link3", "panda_link4"]
    for link, shape, (offset, turn) in found:
        length, radius = shape[3][:2]
        inertial = np.eye(4)
        inertial[:3, :3] = np.array(pybullet.getMatrixFromQuaternion(turn)).reshape(3, 3)
        inertial[:3, 3] = offset
        local = np.eye(4)
        local[:3, :3] = np.array(pybullet.getMatrixFromQuaternion(shape[6])).reshape(3, 3)
        local[:3, 3] = shape[5]
        placed = inertial @ local
        mesh = trimesh.load(PANDA / "meshes" / "collision" / f"{link.removeprefix('panda_')}.stl",
                            force="mesh")
        assert inside(np.asarray(mesh.vertices), placed[:3, 3], placed[:3, 2], radius, length / 2)


@needs_panda
def test_panda_links_are_no_capsules_at_the_default_tolerance() -> None:
    assert PANDA is not None
    for name in ("link3", "link4"):
        result = simplify(str(PANDA / "meshes" / "collision" / f"{name}.stl"), "primitives")
        assert result.mode == "hull" and "capsule within 15%" in result.note
    finger = simplify(str(PANDA / "meshes" / "collision" / "finger.stl"), "primitives", tolerance=0.5)
    assert finger.primitive is not None and finger.primitive.kind == "box"  # a capsule would be 133 % off
