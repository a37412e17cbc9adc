"""``convert --collision``: a concave tray decomposed into convex parts holds a ball in MuJoCo.

The tray is pybullet_data's ``tray/tray.urdf`` (installed with PyBullet): one
OBJ file whose collision mesh MuJoCo hulls into a solid block.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from click.testing import CliRunner

from tests.conftest import FIXTURES, PBD
from urdftool.cli import main
from urdftool.pipeline.check import CheckOptions, check_file

pytestmark = pytest.mark.slow

TRAY = PBD / "tray" / "tray.urdf" if PBD else None
needs_tray = pytest.mark.skipif(TRAY is None or not TRAY.is_file(), reason="pybullet_data not installed")


def convert(source: Path, out: Path, *args: str) -> str:
    result = CliRunner().invoke(main, ["convert", str(source), "-o", str(out), *args])
    assert result.exit_code == 0, result.output
    return result.output


def drop_ball(mjcf: Path) -> tuple[float, float, float]:
    """Drop a 2 cm ball into the middle of the tray from 15 cm up; where it is after 1.5 s."""
    mujoco = pytest.importorskip("mujoco")
    root = ET.parse(mjcf).getroot()
    compiler = root.find("compiler")
    if compiler is None:
        compiler = ET.SubElement(root, "compiler")
    compiler.set("meshdir", str(mjcf.parent))
    world = root.find("worldbody")
    assert world is not None
    ball = ET.SubElement(world, "body", name="ball", pos="0.05 0.03 0.15")
    ET.SubElement(ball, "freejoint")
    ET.SubElement(ball, "inertial", pos="0 0 0", mass="0.05", diaginertia="8e-6 8e-6 8e-6")
    ET.SubElement(ball, "geom", type="sphere", size="0.02")
    model = mujoco.MjModel.from_xml_string(ET.tostring(root, encoding="unicode"))
    data = mujoco.MjData(model)
    while data.time < 1.5:
        mujoco.mj_step(model, data)
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "ball")
    x, y, z = (float(v) for v in data.xpos[body])
    return x, y, z


@needs_tray
def test_as_is_tray_is_warned_and_the_ball_rests_on_the_hull(tmp_path: Path) -> None:
    assert TRAY is not None
    options = CheckOptions(select=("T003",), rule_options={"targets": ("mujoco",)})
    found = [d for r in check_file(str(TRAY), options) for d in r.diagnostics]
    assert len(found) == 1 and "MuJoCo will treat" in found[0].message
    assert found[0].data["fill"] < 0.5
    convert(TRAY, tmp_path / "tray.xml", "--collision", "as-is")
    _, _, z = drop_ball(tmp_path / "tray.xml")
    assert z > 0.14  # on the lid of the hull (the rim is 0.133 m up at scale 0.5)


@needs_tray
def test_decomposed_tray_holds_the_ball(tmp_path: Path) -> None:
    assert TRAY is not None
    output = convert(TRAY, tmp_path / "tray.xml", "--collision", "decompose")
    assert "C006" in output and "volume error" in output
    root = ET.parse(tmp_path / "tray.xml").getroot()
    meshes = {m.get("name"): m.get("file") for m in root.iter("mesh")}
    geoms = [g for g in root.iter("geom") if g.get("mesh")]
    collision = [g for g in geoms if g.get("contype") != "0" and g.get("group") != "2"]
    parts = {meshes[g.get("mesh")] for g in collision}
    assert len(parts) >= 4, parts
    # visual mesh untouched: the original OBJ is still referenced
    assert any(str(f).endswith("tray_textured4.obj") for f in meshes.values())
    x, y, z = drop_ball(tmp_path / "tray.xml")
    assert abs(x) < 0.25 and abs(y) < 0.25 and z < 0.06, (x, y, z)


@needs_tray
def test_decomposition_volume_and_cache(tmp_path: Path) -> None:
    trimesh = pytest.importorskip("trimesh")
    from urdftool.backends.collision_shapes import simplify
    from urdftool.backends.mesh_shape import shape_facts

    assert TRAY is not None
    mesh = str(TRAY.parent / "tray_textured4.obj")
    result = simplify(mesh, "decompose")
    assert len(result.parts) >= 4
    pieces = [trimesh.load(p, force="mesh") for p in result.parts]
    assert all(p.is_convex for p in pieces)
    union = trimesh.boolean.union(pieces, engine="manifold").volume
    assert union == pytest.approx(shape_facts(mesh).solid_volume, rel=0.10)
    assert abs(result.volume_error) < 0.10
    again = simplify(mesh, "decompose")
    assert again.cached and again.parts == result.parts


def test_hull_and_primitives_on_fixtures(tmp_path: Path) -> None:
    source = FIXTURES / "targets" / "heavy_mesh.urdf"
    output = convert(source, tmp_path / "out.urdf", "--collision", "primitives")
    assert "became a sphere" in output
    root = ET.parse(tmp_path / "out.urdf").getroot()
    bob = next(link for link in root.iter("link") if link.get("name") == "bob")
    assert bob.find("collision/geometry/sphere") is not None
    assert bob.find("visual/geometry/mesh") is not None  # the visual keeps its mesh
    output = convert(FIXTURES / "targets" / "bowl.urdf", tmp_path / "bowl.urdf", "--collision", "hull")
    assert "became its convex hull" in output
    root = ET.parse(tmp_path / "bowl.urdf").getroot()
    written = [m.get("filename") for m in root.iter("mesh")]
    assert any(str(f).startswith("collision/") for f in written)
    assert all((tmp_path / f).is_file() for f in written if str(f).startswith("collision/"))
