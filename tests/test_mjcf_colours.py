"""MJCF visual colours from COLLADA materials (docs/mjcf.md, "Meshes"): a multi-material visual
mesh is one geom per colour with a ``<material>``, the URDF colour fills the triangles without a
material of their own, collision geometry is the whole mesh; the split is cached on disk."""

from __future__ import annotations

import shutil
from pathlib import Path

import mujoco
import numpy as np
import pytest
import trimesh
from lxml import etree

from tests.conftest import ERD, FIXTURES
from urdftool.backends import mesh_cache
from urdftool.backends.meshes import load_trimesh
from urdftool.export import ExportOptions, mjcf_assets
from urdftool.export.mjcf import export
from urdftool.export.mjcf_verify import verify
from urdftool.parse import read
from urdftool.pipeline.check import CheckOptions
from urdftool.pipeline.load import load_one

TWO_COLOURS = FIXTURES / "robots" / "two_colours.dae"
INERTIAL = ('<inertial><mass value="1"/>'
            '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>')


def _robot(tmp_path: Path):  # type: ignore[no-untyped-def]
    shutil.copy(TWO_COLOURS, tmp_path / "part.dae")
    shutil.copy(FIXTURES / "rules" / "C004" / "good_mesh.dae", tmp_path / "plain.dae")
    (tmp_path / "robot.urdf").write_text(
        '<robot name="colours"><material name="blue"><color rgba="0 0 1 1"/></material>'
        f'<link name="base">{INERTIAL}'
        '<visual><geometry><mesh filename="part.dae"/></geometry><material name="blue"/></visual>'
        '<visual><geometry><mesh filename="plain.dae"/></geometry><material name="blue"/></visual>'
        '<visual><geometry><box size="0.1 0.1 0.1"/></geometry><material name="blue"/></visual>'
        '<collision><geometry><mesh filename="part.dae"/></geometry></collision></link></robot>')
    robot = read(tmp_path / "robot.urdf")[0].robot
    assert robot is not None
    return robot


def _export(robot, out: Path, **options) -> etree._Element:  # type: ignore[no-untyped-def]
    result = export(robot, out, ExportOptions(**options))
    for name, data in result.files.items():
        (out.parent / name).parent.mkdir(parents=True, exist_ok=True)
        (out.parent / name).write_bytes(data)
    return etree.parse(str(out)).getroot()


@pytest.fixture
def fresh_cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """An empty disk cache and empty in-process caches, so a test sees its own conversions."""
    monkeypatch.setenv("URDFTOOL_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("URDFTOOL_NO_CACHE", raising=False)
    mjcf_assets._parts_cached.cache_clear()
    mjcf_assets._convert_cached.cache_clear()
    yield tmp_path / "cache"
    mjcf_assets._parts_cached.cache_clear()
    mjcf_assets._convert_cached.cache_clear()


def test_multi_material_visual_is_one_geom_per_colour(tmp_path: Path, fresh_cache: Path) -> None:
    out = tmp_path / "out" / "robot.xml"
    root = _export(_robot(tmp_path), out)
    visual = root.findall(".//geom[@class='visual']")
    collision = root.findall(".//geom[@class='collision']")
    # part.dae: no material (with the green triangle, too small for a mesh), grey, red (sorted);
    # plain.dae: its one colour; the box: URDF blue
    assert [g.get("material") for g in visual] == [
        None, "rgba_33333380", "rgba_ff0000ff", "rgba_000000ff", None]
    assert visual[0].get("rgba") == "0 0 1 1" and visual[4].get("rgba") == "0 0 1 1"
    assert all(g.get("rgba") is None for g in visual[1:4])  # the mesh's own colour wins
    materials = {m.get("name"): m.get("rgba") for m in root.findall("asset/material")}
    assert materials == {"rgba_33333380": "0.2 0.2 0.2 0.502", "rgba_ff0000ff": "1 0 0 1",
                         "rgba_000000ff": "0 0 0 1"}
    assert len(collision) == 1 and collision[0].get("mesh") not in {g.get("mesh") for g in visual}

    model = mujoco.MjModel.from_xml_path(str(out))
    faces = {model.mesh(i).name: int(model.mesh_facenum[i]) for i in range(model.nmesh)}
    whole = load_trimesh(str(TWO_COLOURS))
    assert sum(faces[g.get("mesh")] for g in visual[:3]) == len(whole.faces) == 9
    assert [faces[g.get("mesh")] for g in visual[:3]] == [5, 2, 2]
    assert faces[collision[0].get("mesh")] == 9
    # the parts together are the whole mesh, in place and in metres (unit 0.5, node offsets)
    files = {m.get("name"): out.parent / m.get("file") for m in root.findall("asset/mesh")}
    points = np.concatenate([trimesh.load(files[g.get("mesh")], force="mesh").vertices for g in visual[:3]])
    assert points.min(axis=0) == pytest.approx(whole.bounds[0], abs=1e-7)
    assert points.max(axis=0) == pytest.approx(whole.bounds[1], abs=1e-7)
    assert tuple(model.mat_rgba[model.material("rgba_ff0000ff").id]) == pytest.approx((1, 0, 0, 1))


def test_colour_split_is_cached_on_disk(tmp_path: Path, fresh_cache: Path,
                                        monkeypatch: pytest.MonkeyPatch) -> None:
    robot = _robot(tmp_path)
    first = export(robot, tmp_path / "a" / "robot.xml", ExportOptions()).files
    assert list((fresh_cache).rglob(f"converted/{mjcf_assets.PARTS_KIND}/*/*"))
    mjcf_assets._parts_cached.cache_clear()

    def refuse(path: str) -> None:
        raise AssertionError(f"{path} read again instead of the cached split")

    monkeypatch.setattr(mjcf_assets, "coloured_parts", refuse)
    second = export(robot, tmp_path / "a" / "robot.xml", ExportOptions()).files
    assert second == first


def test_damaged_cache_entry_is_computed_again(tmp_path: Path, fresh_cache: Path) -> None:
    robot = _robot(tmp_path)
    first = export(robot, tmp_path / "a" / "robot.xml", ExportOptions()).files
    for entry in fresh_cache.rglob(f"converted/{mjcf_assets.PARTS_KIND}/*/*"):
        entry.write_bytes(entry.read_bytes()[:-7])
    mjcf_assets._parts_cached.cache_clear()
    assert export(robot, tmp_path / "a" / "robot.xml", ExportOptions()).files == first


def _dae_colours(path: str) -> set[tuple[float, ...]]:
    """The diffuse colours trimesh reads from a COLLADA file, as 0..1 floats."""
    scene = trimesh.load(path, force="scene")
    return {tuple(float(c) / 255 for c in g.visual.material.baseColorFactor)
            for g in scene.geometry.values() if getattr(g.visual, "material", None) is not None}


def test_panda_visual_colours_come_from_its_dae_materials(tmp_path: Path) -> None:
    assert ERD is not None
    loaded = load_one(str(ERD / "panda_description" / "urdf" / "panda.urdf"), CheckOptions())
    robot = loaded.robot
    assert robot is not None
    outs = [tmp_path / run / "robot.xml" for run in ("a", "b")]
    for out in outs:
        _export(robot, out, scene=True, actuators="auto")
    files = sorted(p.relative_to(outs[0].parent) for p in outs[0].parent.rglob("*") if p.is_file())
    assert files == sorted(p.relative_to(outs[1].parent) for p in outs[1].parent.rglob("*") if p.is_file())
    assert all((outs[0].parent / f).read_bytes() == (outs[1].parent / f).read_bytes() for f in files)

    model = mujoco.MjModel.from_xml_path(str(outs[0]))
    split = 0
    for link in robot.links:
        if not link.visuals or link.visuals[0].geometry is None:
            continue
        resolved = getattr(link.visuals[0].geometry, "resolved", None)
        if not resolved or not resolved.endswith(".dae"):
            continue
        body = model.body(link.name).id
        geoms = [i for i in range(model.ngeom)
                 if model.geom_bodyid[i] == body and model.geom_group[i] == 2]
        got = {tuple(float(c) for c in model.mat_rgba[model.geom_matid[i]]) for i in geoms}
        assert all(model.geom_matid[i] >= 0 for i in geoms), link.name
        expected = _dae_colours(resolved)
        assert len(got) == len(expected) == len(geoms), link.name
        for colour in expected:
            assert any(np.allclose(colour, g, atol=1e-4) for g in got), (link.name, colour)
        split += len(geoms) > 1
    assert split >= 6  # link0, link3 … link7, hand: several materials each
    verdict = verify(robot, outs[0], ExportOptions(scene=True, actuators="auto"))
    assert verdict.ok, verdict.rows


def test_cache_entry_packs_and_unpacks() -> None:
    parts = ((None, b"abc", ".stl"), ((1, 2, 3, 255), b"", ".obj"), ((9, 9, 9, 9), b"xyz\n", ".stl"))
    assert mjcf_assets._unpack_parts(mjcf_assets._pack_parts(parts)) == parts
    assert mjcf_assets._unpack_parts(mjcf_assets._pack_parts(())) == ()
    assert mesh_cache.SCHEMA == 5  # a new kind of entry was not a new meaning for the old ones (5: comments)


def test_obj_visual_split_by_its_mtl_colours(tmp_path: Path, fresh_cache: Path) -> None:
    """An OBJ's ``.mtl`` materials colour its parts, as Assimp shows them in RViz and as obj2mjcf
    splits them for MuJoCo (which reads no ``.mtl``); an OBJ without one keeps the URDF colour."""
    for suffix in (".obj", ".mtl"):
        shutil.copy(FIXTURES / "robots" / f"two_colours{suffix}", tmp_path / f"two_colours{suffix}")
    lines = (FIXTURES / "robots" / "two_colours.obj").read_text().splitlines()
    (tmp_path / "plain.obj").write_text(  # the same cubes without materials
        "\n".join(line for line in lines if not line.startswith(("mtllib", "usemtl"))) + "\n")
    (tmp_path / "robot.urdf").write_text(
        '<robot name="colours"><material name="blue"><color rgba="0 0 1 1"/></material>'
        f'<link name="base">{INERTIAL}'
        '<visual><geometry><mesh filename="two_colours.obj"/></geometry><material name="blue"/></visual>'
        '<visual><geometry><mesh filename="plain.obj"/></geometry><material name="blue"/></visual>'
        '<collision><geometry><mesh filename="two_colours.obj"/></geometry></collision></link></robot>')
    robot = read(tmp_path / "robot.urdf")[0].robot
    out = tmp_path / "out" / "robot.xml"
    root = _export(robot, out)
    visual = root.findall(".//geom[@class='visual']")
    assert [g.get("material") for g in visual] == ["rgba_808080ff", "rgba_ff0000ff", None]
    assert visual[2].get("rgba") == "0 0 1 1"
    model = mujoco.MjModel.from_xml_path(str(out))
    by_name = {mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_MATERIAL, i): model.mat_rgba[i]
               for i in range(model.nmat)}
    assert np.allclose(by_name["rgba_ff0000ff"], [1, 0, 0, 1])
    assert np.allclose(by_name["rgba_808080ff"], [0.502, 0.502, 0.502, 1], atol=1e-3)
    # each colour's part is its own cube: 8 vertices, 12 triangles
    assert [int(model.mesh_facenum[model.geom_dataid[g]]) for g in range(model.ngeom)
            if model.geom_group[g] == 2 and model.geom_matid[g] >= 0] == [12, 12]
