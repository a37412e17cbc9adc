"""SDF input: the corpora load, and poses, axes, frames, includes and worlds mean what the spec says."""

from __future__ import annotations

import glob
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from tests.conftest import ERD, FIXTURES, PBD, SEEDS
from urdftool.cli import main
from urdftool.model import JointType, KinematicTree
from urdftool.parse import read
from urdftool.parse.packages import PackageResolver
from urdftool.pipeline.check import CheckOptions, check_file

SDF_DIR = FIXTURES / "robots" / "sdf"
CASSIE = sorted(glob.glob(str(ERD / "cassie_description" / "robots" / "*.sdf"))) if ERD else []
PYBULLET_SDFS = sorted(glob.glob(str(PBD / "**" / "*.sdf"), recursive=True)) if PBD else []
SEED_FILES = [
    "hyundai_ngv/m_robot_gazebo/worlds/m_robot.world",
    "go_chase_it/my_robot/worlds/UdacityOffice.world",
    "go_chase_it/my_robot/worlds/empty.world",
    "hyundai_ngv/models/Capstone_Map/model.sdf",
    "go_chase_it/models/my_ball/model.sdf",
]


#: Genuine errors in the corpora, by file name: what is wrong with the files themselves.
GENUINE = {
    # the foot-reference links' principal moments 9.31e-07 + 9.49e-07 < 9.4e-06 kg·m²
    "cassie.sdf": {"I005"},
    # collision meshes at the absolute path /meshes/link_0.stl, which does not exist
    "kuka_with_gripper.sdf": {"M002"},
    "kuka_with_gripper2.sdf": {"M002"},
    # meshes/coarse/ is not shipped with pybullet_data
    "kuka_world.sdf": {"M002"},
    "model2.sdf": {"M002", "S106"},
    # kiva_shelf/model.sdf: two collisions named pod_collision in one link; model2.sdf: two
    # models named lbr_iiwa in one world (libsdformat refuses both: "already exists")
    "model.sdf": {"S106"},
    # the stadium OBJ parts have degenerate faces the mesh reader cannot load
    "stadium.sdf": {"M003"},
    "stadium_no_collision.sdf": {"M003"},
    # (UdacityOffice.world's suv, fire_hydrant, pine_tree and radio_tower come from Gazebo Classic's
    # online model database, which Classic downloads: an M001 info, not an error)
}


def _errors(path: str) -> list[str]:
    """Error findings other than the genuine ones listed above."""
    allowed = GENUINE.get(Path(path).name, set())
    reports = check_file(path, CheckOptions())
    return [f"{d.location}: {d.code} {d.message}" for r in reports for d in r.diagnostics
            if d.severity.value == "error" and d.code not in allowed]


def test_corpus_counts() -> None:
    assert len(CASSIE) == 5
    assert len(PYBULLET_SDFS) >= 15


@pytest.mark.parametrize("path", PYBULLET_SDFS, ids=lambda p: str(Path(p).relative_to(PBD)))
def test_pybullet_sdf_loads_without_errors(path: str) -> None:
    models = read(path)
    assert models and all(m.robot is not None and m.robot.links for m in models)
    assert _errors(path) == []


@pytest.mark.parametrize("path", CASSIE, ids=lambda p: Path(p).name)
def test_cassie_loads_with_its_loops(path: str) -> None:
    (loaded,) = read(path)
    robot = loaded.robot
    assert robot is not None and robot.name == "cassie"
    tree = KinematicTree.of(robot)
    assert not tree.cycle_joints and len(tree.roots) == 1
    # each leg closes at least the achilles/heel-spring and plantar-rod linkages
    assert len(robot.loop_closures) >= 4
    assert {lc.joint.name for lc in robot.loop_closures}.isdisjoint({j.name for j in robot.joints})
    assert _errors(path) == []


@pytest.mark.parametrize("relative", SEED_FILES)
def test_seed_worlds_and_models_load_and_check(relative: str) -> None:
    path = str(SEEDS / relative)
    models = read(path)
    assert models
    assert _errors(path) == []


def test_world_reports_each_model_and_skips_standard_ones() -> None:
    models = read(str(SDF_DIR / "static_world.world"))
    assert [m.robot.name for m in models if m.robot] == ["shelf", "cart"]
    shelf = models[0].robot
    assert shelf is not None
    # static: every free link is welded to the world at the model's pose in the world
    fk = KinematicTree.of(shelf).forward_kinematics()
    assert KinematicTree.of(shelf).roots == ["world"]
    np.testing.assert_allclose(fk["board"][:3, 3], [2, 0, 0.5])
    np.testing.assert_allclose(fk["post"][:3, 3], [2, 0, 0])


def test_world_findings_go_with_the_model_that_holds_them(tmp_path: Path) -> None:
    # provenance: reduced from gz-sim's examples/worlds/diff_drive.sdf (Apache-2.0): a URDF <origin>
    # in the second vehicle's link, and a <sensor> straight under a third model
    path = tmp_path / "world.sdf"
    path.write_text("""<?xml version="1.0"?>
<sdf version="1.9">
  <world name="w">
    <model name="ground"><static>true</static><link name="g"/></model>
    <model name="blue">
      <link name="chassis"><origin xyz="0 0 1"/></link>
    </model>
    <model name="camera"><link name="body"/><sensor name="cam" type="camera"/></model>
    <bogus/>
  </world>
</sdf>
""")
    reports = check_file(str(path), CheckOptions(select=("S",)))
    by_model = {r.robot: [(d.code, d.location.line) for d in r.diagnostics if d.location]
                for r in reports}
    assert ("S008", 6) in by_model["blue"]
    assert ("S008", 8) in by_model["camera"]
    assert ("S008", 9) in by_model["ground"]  # the world's own elements: the first model's report
    assert not any(line in (6, 8) for _, line in by_model["ground"])


def test_seed_world_include_resolves_the_map_with_its_include_pose() -> None:
    (loaded,) = read(str(SEEDS / "hyundai_ngv/m_robot_gazebo/worlds/m_robot.world"))
    robot = loaded.robot
    assert robot is not None and robot.name == "Capstone_Map2"
    assert any(f.endswith("Capstone_Map/model.sdf") for f in loaded.files)
    joint = next(j for j in robot.joints if j.child == "Wall_0")
    # include pose (0, -2, 0) replaces the model's own pose; Wall_0 sits at (0, 2.42, 0) in the model
    np.testing.assert_allclose(joint.origin.xyz, [0, 0.42, 0], atol=1e-12)
    assert robot.link("Wall_0").span.path.endswith("Capstone_Map/model.sdf")


def test_sdf_14_axis_is_in_the_model_frame() -> None:
    robot = read(str(SDF_DIR / "v14_axis_model_frame.sdf"))[0].robot
    hinge = robot.joint("hinge")
    # the model's x axis, seen from a link yawed by +90°, is its -y axis
    np.testing.assert_allclose(hinge.axis, [0, -1, 0], atol=1e-12)


def test_sdf_16_axis_in_joint_frame_and_offset_joint_moves_the_link_frame() -> None:
    robot = read(str(SDF_DIR / "v16_axis_joint_frame.sdf"))[0].robot
    hinge = robot.joint("hinge")
    np.testing.assert_allclose(hinge.axis, [1, 0, 0], atol=1e-12)
    # the joint sits 0.5 m along the yawed link's x: the link frame moves there,
    # and the inertial (written at the same point) is now at the frame's origin
    np.testing.assert_allclose(hinge.origin.xyz, [0, 0.5, 1], atol=1e-12)
    np.testing.assert_allclose(robot.link("arm").inertial.origin.xyz, [0, 0, 0], atol=1e-12)
    # turning the hinge turns the link about the joint's point
    fk = KinematicTree.of(robot).forward_kinematics({"hinge": 0.3})
    np.testing.assert_allclose(fk["arm"][:3, 3], [0, 0.5, 1], atol=1e-12)


def test_nested_model_degrees_and_frames() -> None:
    robot = read(str(SDF_DIR / "nested_degrees.sdf"))[0].robot
    assert [link.name for link in robot.links] == ["base", "gripper::palm"]
    mount = robot.joint("mount")
    np.testing.assert_allclose(mount.origin.xyz, [0, 0, 0.5], atol=1e-12)
    np.testing.assert_allclose(mount.origin.rpy, [0, 0, math.pi / 2], atol=1e-12)
    (frame,) = [e for e in robot.extensions if e.tag == "frame"]
    assert frame.attributes["attached_to"] == "gripper::palm"
    assert frame.attributes["name"] == "gripper::tcp"


def test_bad_numbers_are_located_and_do_not_stop_reading(tmp_path: Path) -> None:
    path = tmp_path / "bad.sdf"
    path.write_text(
        '<sdf version="1.7">\n<model name="m">\n<link name="a">\n'
        "<inertial><mass>1.2,</mass></inertial>\n</link>\n"
        '<link name="b"><pose>0 0 1 0 0</pose></link>\n</model>\n</sdf>\n'
    )
    (loaded,) = read(str(path))
    found = {(d.code, d.location.line) for d in loaded.diagnostics}
    assert ("S005", 4) in found and ("S006", 6) in found
    # libsdformat reads a double with std::stod: 1.2 from "1.2,", so a warning and the value 1.2
    [comma] = [d for d in loaded.diagnostics if d.code == "S005"]
    assert comma.severity.value == "warning"
    assert loaded.robot is not None and loaded.robot.link("a").inertial.mass == 1.2


def test_model_include_through_gz_resource_path(tmp_path: Path) -> None:
    crate = FIXTURES / "rules" / "S103" / "models"
    world = FIXTURES / "rules" / "S103" / "good.world"
    copied = tmp_path / "w.world"
    copied.write_text(world.read_text())
    missing = read(str(copied), resolver=PackageResolver.create(environ={}))
    assert any(d.code == "S103" for m in missing for d in m.diagnostics)
    found = read(str(copied), resolver=PackageResolver.create(environ={"GZ_SIM_RESOURCE_PATH": str(crate)}))
    assert [m.robot.name for m in found if m.robot] == ["crate"]


def test_cli_model_option_picks_one_model() -> None:
    world = str(SDF_DIR / "static_world.world")
    result = CliRunner().invoke(main, ["info", world, "--model", "cart", "--format", "json"])
    assert result.exit_code == 0, result.output
    assert '"robot": "cart"' in result.output and "shelf" not in result.output
    result = CliRunner().invoke(main, ["check", world, "--model", "nope"])
    assert result.exit_code == 2
    result = CliRunner().invoke(main, ["check", world, "--model", "shelf", "--format", "json"])
    assert (
        result.exit_code in (0, 1) and '"robot": "shelf"' in result.output and '"cart"' not in result.output
    )


def test_joint_types_are_read() -> None:
    robot = read(CASSIE[0])[0].robot  # cassie.sdf: ball, gearbox, prismatic, revolute
    types = {j.type for j in robot.joints} | {lc.joint.type for lc in robot.loop_closures}
    assert {JointType.SPHERICAL, JointType.GEARBOX, JointType.PRISMATIC, JointType.REVOLUTE} <= types


def test_merged_include_by_bare_name_joins_the_model(tmp_path: Path) -> None:
    # PX4's x500_depth: <include merge="true"><uri>x500</uri></include> names a model folder on
    # gz-sim's resource path, and its plugins name the merged joints without a scope.
    base = FIXTURES / "sdf-conformance" / "valid" / "models" / "merged_base" / "model.sdf"
    (tmp_path / "merged_base").mkdir()
    (tmp_path / "merged_base" / "model.sdf").write_text(base.read_text())
    (tmp_path / "drone").mkdir()
    drone = tmp_path / "drone" / "model.sdf"
    drone.write_text(
        '<sdf version="1.9"><model name="drone">'
        '<include merge="true"><uri>merged_base</uri><pose>0 0 1 0 0 0</pose></include>'
        '<plugin filename="gz-sim-multicopter-motor-model-system"'
        ' name="gz::sim::systems::MulticopterMotorModel">'
        "<jointName>rotor_joint</jointName><linkName>rotor</linkName></plugin>"
        "</model></sdf>"
    )
    resolver = PackageResolver.create(environ={"GZ_SIM_RESOURCE_PATH": str(tmp_path)})
    (loaded,) = read(str(drone), resolver=resolver)
    robot = loaded.robot
    assert robot is not None
    assert [link.name for link in robot.links] == ["base_link", "rotor"]
    np.testing.assert_allclose(robot.joint("rotor_joint").origin.xyz, [0.2, 0, 0.06], atol=1e-12)
    options = CheckOptions(package_paths=(str(tmp_path),), rule_options={"dynamics": False})
    findings = [d for r in check_file(str(drone), options) for d in r.diagnostics]
    assert [d.code for d in findings if d.severity.value == "error"] == []
    assert not any(d.code == "G003" for d in findings)


def test_sdf_link_without_inertial_is_a_warning_with_the_sdf_default() -> None:
    path = FIXTURES / "rules" / "I001" / "bad_sdf_default_inertial.sdf"
    options = CheckOptions(select=("I001",), rule_options={"dynamics": False})
    (found,) = [d for r in check_file(str(path), options) for d in r.diagnostics]
    assert found.severity.value == "warning"
    assert "SDF readers give it 1 kg" in found.message


def test_dynamics_of_an_sdf_link_without_inertial_use_the_sdf_default() -> None:
    # PX4's lawnmower: visual-only links on revolute joints weigh 1 kg in every SDF reader, so
    # the mass matrix is not singular (no mass-matrix-singular error).
    pytest.importorskip("pinocchio")
    path = FIXTURES / "rules" / "I001" / "bad_sdf_default_inertial.sdf"
    found = [d for r in check_file(str(path), CheckOptions()) for d in r.diagnostics]
    assert [d.code for d in found if d.severity.value == "error"] == []


def test_exports_write_sdformats_default_inertial_for_a_link_without_one(tmp_path: Path) -> None:
    """An SDF link without <inertial> weighs 1 kg with a unit inertia in gz-sim; the MJCF, PyBullet
    and URDF exports write that out (reported as info), so the export weighs what the source does."""
    import mujoco
    from lxml import etree

    import urdftool

    source = FIXTURES / "rules" / "I001" / "bad_sdf_default_inertial.sdf"
    model = mujoco.MjModel.from_xml_string(urdftool.to_mjcf(source))
    blades = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "blades")
    assert model.body_mass[blades] == 1.0 and list(model.body_inertia[blades]) == [1.0, 1.0, 1.0]
    assert abs(sum(model.body_mass) - 21.0) < 1e-12
    urdf = etree.fromstring(urdftool.to_urdf(source).encode())
    assert urdf.find("link[@name='blades']/inertial/mass").get("value") == "1"
    from urdftool.export import ExportOptions
    from urdftool.pipeline.convert import convert_robot

    notes = convert_robot(urdftool.load(source), "pybullet", tmp_path / "r.urdf", ExportOptions()).diagnostics
    defaulted = [(d.code, d.severity.value) for d in notes if "SDFormat's default" in d.message]
    assert defaulted == [("C007", "info")]


def test_an_included_light_or_actor_is_not_a_missing_model() -> None:
    """Gazebo Classic worlds add their sun by including model://sun, whose file holds a <light>;
    an <actor> may be included the same way. libsdformat reads both: no error, found or not."""
    folder = FIXTURES / "sdf_light_include"
    world = str(folder / "world.world")
    found = check_file(world, CheckOptions(package_paths=(str(folder / "models"),)))
    assert [d.code for r in found for d in r.diagnostics] == []
    for name, article in (("sun", "a <light>"), ("walker", "an <actor>")):
        (alone,) = check_file(str(folder / "models" / name / "model.sdf"), CheckOptions())
        assert [(d.code, d.severity.value, d.message) for d in alone.diagnostics] == [
            ("S105", "info", f"the SDF file holds {article}, which has no links or joints to check")]
