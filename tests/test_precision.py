"""False errors found on real robot descriptions (docs/realworld.md), each as a minimal reproduction.

A CI gate must not fail valid models: each test here is a model that a real
consumer accepts and on which urdftool once reported an error.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import urdftool
from tests.conftest import FIXTURES
from urdftool.diagnostics import Severity
from urdftool.parse import xmlio
from urdftool.pipeline.check import CheckOptions, check_file
from urdftool.render.text import render_diagnostic
from urdftool.source import SourceIndex

RULES = FIXTURES / "rules"


def errors(path: Path) -> list[str]:
    return [f"{d.code} {d.message}" for d in urdftool.check(path).errors]


def test_pr2_style_sdf_link_in_a_gazebo_block_is_a_valid_reference() -> None:
    assert errors(RULES / "G001" / "good_sdf_link_in_gazebo.urdf") == []


def test_fuel_url_include_is_information_not_an_error() -> None:
    report = urdftool.check(FIXTURES / "precision" / "fuel_url.world")
    assert report.ok
    found = [d for d in report.diagnostics if d.code == "S103"]
    assert [d.severity for d in found] == [Severity.INFO]
    assert found[0].data["remote"] is True


def test_repeated_material_in_a_visual_is_a_warning_and_converts(tmp_path: Path) -> None:
    source = tmp_path / "cad.urdf"
    source.write_text(
        '<robot name="cad"><link name="base"><visual><geometry><box size="0.1 0.1 0.1"/></geometry>'
        '<material name="a"><color rgba="1 0 0 1"/></material>'
        '<material name="b"><color rgba="0 1 0 1"/></material></visual>'
        '<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>'
        "</inertial></link></robot>"
    )
    report = urdftool.check(source)
    repeated = [d for d in report.diagnostics if d.code == "S007"]
    assert [d.severity for d in repeated] == [Severity.WARNING] and report.ok
    assert "<mujoco" in urdftool.to_mjcf(source)
    # A repeated <axis> still changes the robot between loaders: an error that refuses the export.
    source.write_text(source.read_text().replace(
        "</link></robot>",
        '</link><link name="b"/><joint name="j" type="continuous"><parent link="base"/>'
        '<child link="b"/><axis xyz="1 0 0"/><axis xyz="0 1 0"/></joint></robot>'))
    assert any(d.code == "S007" and d.severity is Severity.ERROR for d in urdftool.check(source).errors)


def test_identical_repeated_element_is_a_warning() -> None:
    # Summit XL TIX (robotnik_sensors' D435 macro): <child link="camera_link"/> written twice in a
    # joint. Loaders that keep the first and those that keep the last build the same robot.
    report = urdftool.check(RULES / "S007" / "bad_identical_child.urdf")
    repeated = [d for d in report.diagnostics if d.code == "S007"]
    assert [d.severity for d in repeated] == [Severity.WARNING] and report.ok
    assert "a copy of the first one (line 14)" in repeated[0].message


def test_joint_locked_by_equal_limits_gets_one_warning() -> None:
    # RotorS and UUV Simulator mount every sensor on a revolute joint with lower = upper = effort =
    # velocity = 0 (Gazebo classic would merge a fixed joint's link away): inverted-limits
    # reports the lock, and zero-effort-or-velocity does not say it again.
    report = urdftool.check(RULES / "J003" / "good_locked_sensor_joint.urdf")
    found = [d for d in report.diagnostics if d.code in {"J003", "J004"}]
    assert [d.code for d in found] == ["J004"] and report.ok
    assert "preserveFixedJoint" in (found[0].help or "")


def test_kinematics_only_model_gets_one_finding_and_one_refusal() -> None:
    path = RULES / "I011" / "bad.urdf"
    report = urdftool.check(path)
    assert report.ok, errors(path)
    codes = [d.code for d in report.diagnostics]
    assert codes.count("I011") == 1
    assert not {"I001", "D001", "D004"} & set(codes)
    with pytest.raises(urdftool.ConversionRefused) as refused:
        urdftool.to_mjcf(path)
    assert [d.code for d in refused.value.diagnostics] == ["C003"]
    assert "kinematic model" in refused.value.diagnostics[0].message
    assert "<mujoco" in urdftool.to_mjcf(path, repair_inertia=True)


def test_a_model_with_some_inertia_still_reports_each_missing_link() -> None:
    report = urdftool.check(RULES / "I011" / "good.urdf")
    assert [d.element for d in report.diagnostics if d.code == "I001"] == ["link[link_2]"]


# A one-triangle COLLADA document written for this test. Derived from
# kuka_experimental's kuka_lbr_iiwa_support/meshes/lbr_iiwa_14_r820/visual/base_link.dae, which
# after </COLLADA> holds 75,560 NUL bytes and the tail of an older export.
TRIANGLE_DAE = b"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <library_geometries><geometry id="g"><mesh>
    <source id="p"><float_array id="pa" count="9">0 0 0 0.1 0 0 0 0.1 0</float_array>
      <technique_common><accessor source="#pa" count="3" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#g"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>"""
OLD_TAIL = b"\n      </mesh>\n    </geometry>\n  </library_geometries>\n</COLLADA>\n"


def _mesh_robot(folder: Path, dae: bytes) -> Path:
    (folder / "base.dae").write_bytes(dae)
    urdf = folder / "r.urdf"
    urdf.write_text(
        '<robot name="r"><link name="base"><visual><geometry><mesh filename="base.dae"/></geometry>'
        '</visual><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0"'
        ' izz="0.01"/></inertial></link></robot>'
    )
    return urdf


@pytest.mark.parametrize("lean", [True, False])
def test_collada_with_nul_padding_and_an_old_tail_reads_as_assimp_does(tmp_path: Path, lean: bool) -> None:
    # Assimp (RViz) and PyBullet read a COLLADA file as a C string: the bytes after
    # the first NUL are not there for them, so the file is a well-formed one-triangle mesh.
    from urdftool.backends import meshes

    urdf = _mesh_robot(tmp_path, TRIANGLE_DAE + b"\0" * 64 + OLD_TAIL)
    assert errors(urdf) == []
    assert len(meshes.load_trimesh(str(tmp_path / "base.dae"), lean).faces) == 1


def test_collada_with_an_old_tail_and_no_nul_is_still_unreadable(tmp_path: Path) -> None:
    # Without the NUL the tail is XML after the document: Assimp 5.2 refuses it ("malformed XML").
    urdf = _mesh_robot(tmp_path, TRIANGLE_DAE + OLD_TAIL)
    assert [e.split()[0] for e in errors(urdf)] == ["M003"]


@pytest.mark.parametrize("lean", [True, False])
def test_collada_with_angle_brackets_in_an_attribute_reads_as_assimp_does(tmp_path: Path, lean: bool) -> None:
    # provenance: reduced from velodyne_description's VLP16_base_1.dae (BSD-3-Clause), whose
    # Assimp STL export names its node id="<STL_BINARY>": lxml refuses it, Assimp 5 (RViz) and
    # PyBullet's tinyxml2 read the value up to its quote (the real file: 1,912 faces in both).
    from urdftool.backends import meshes

    urdf = _mesh_robot(tmp_path, TRIANGLE_DAE.replace(b'<node id="n">', b'<node id="<STL_BINARY>">'))
    assert errors(urdf) == []
    assert len(meshes.load_trimesh(str(tmp_path / "base.dae"), lean).faces) == 1


def test_collada_with_a_broken_tag_is_still_unreadable(tmp_path: Path) -> None:
    # Escaping an attribute's brackets repairs nothing else: a tag left open is still refused.
    broken = TRIANGLE_DAE.replace(b'<node id="n">', b'<node id="<STL_BINARY>">')
    broken = broken.replace(b"</mesh>", b"</mesh")
    urdf = _mesh_robot(tmp_path, broken)
    assert [e.split()[0] for e in errors(urdf)] == ["M003"]


def test_vendor_controller_types_get_a_note_not_a_misleading_suggestion(tmp_path: Path) -> None:
    # provenance: controller types of Universal_Robots_ROS2_Driver's ur_controllers.yaml and
    # ros2_kortex's MoveIt configurations (BSD-3-Clause), hand-written. Every ros2_controllers
    # package ends in _controller(s): a whole-name match offered pid_controller/PidController for
    # ur_controllers/ForceModeController; a misspelt ros2_controllers type still gets its name.
    shutil.copy(RULES / "G203" / "bad.urdf", tmp_path / "bad.urdf")
    (tmp_path / "bad.yaml").write_text(
        "controller_manager:\n  ros__parameters:\n"
        + "".join(f"    c{n}:\n      type: {t}\n" for n, t in enumerate((
            "ur_controllers/ForceModeController", "ur_controllers/GPIOController",
            "picknik_twist_controller/PicknikTwistController",
            "position_controller/JointGroupPositionController")))
    )
    found = [(d.severity, d.data.get("suggestion")) for d in urdftool.check(tmp_path / "bad.urdf").diagnostics
             if d.code == "G203"]
    assert found == [(Severity.INFO, None)] * 3 + [
        (Severity.WARNING, "position_controllers/JointGroupPositionController")]


def _ament_package(root: Path, destination: str) -> Path:
    """A package whose xacro includes a file at the path its CMake install rule gives it.

    Derived from ros2_control_demos' example_1 (rrbot.urdf.xacro includes
    $(find ros2_control_demo_example_1)/ros2_control/rrbot.ros2_control.xacro; the file is
    description/ros2_control/ in the source tree, installed to share/<package>/ros2_control).
    """
    (root / "package.xml").write_text('<package format="3"><name>demo_arm</name></package>')
    (root / "CMakeLists.txt").write_text(
        "project(demo_arm)\n# description/ros2_control lands in share/demo_arm/ros2_control\n"
        f"install(\n  DIRECTORY description/ros2_control description/urdf\n  DESTINATION {destination}\n)\n"
    )
    (root / "description" / "ros2_control").mkdir(parents=True)
    (root / "description" / "urdf").mkdir()
    (root / "description" / "ros2_control" / "arm.ros2_control.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:macro name="arm_control">'
        '<ros2_control name="arm" type="system"><hardware><plugin>mock_components/GenericSystem</plugin>'
        '</hardware><joint name="j"><command_interface name="position"/><state_interface name="position"/>'
        "</joint></ros2_control></xacro:macro></robot>"
    )
    inertial = ('<inertial><mass value="1"/>'
                '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>')
    model = root / "description" / "urdf" / "arm.urdf.xacro"
    model.write_text(
        '<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:include filename="$(find demo_arm)/ros2_control/arm.ros2_control.xacro"/>'
        f'<link name="base">{inertial}</link><link name="tip">{inertial}</link>'
        '<joint name="j" type="revolute"><parent link="base"/><child link="tip"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="10" velocity="1"/></joint><xacro:arm_control/></robot>'
    )
    return model


def test_include_written_for_the_ament_install_layout_is_read_quietly(tmp_path: Path) -> None:
    # In ROS 2, $(find demo_arm) is share/demo_arm, where install() put description/ros2_control.
    report = urdftool.check(_ament_package(tmp_path, "share/${PROJECT_NAME}"))
    assert [d.code for d in report.diagnostics if d.code.startswith("X")] == []
    assert report.ok, errors(tmp_path / "description" / "urdf" / "arm.urdf.xacro")


def test_include_that_no_ament_install_rule_explains_is_still_reported(tmp_path: Path) -> None:
    # catkin: $(find) is the source folder in a devel space, so the include is broken there.
    report = urdftool.check(_ament_package(tmp_path, "${CATKIN_PACKAGE_SHARE_DESTINATION}"))
    assert [d.code for d in report.diagnostics if d.code.startswith("X")] == ["X003"]


def test_gz_sim_world_quirks_that_sdformat_reads_are_no_errors() -> None:
    """gz-sim's own example worlds: `--` in comments, `<gz::system_priority>`, an undeclared
    `gz:` attribute prefix and a Fuel mesh URL. 25 of its 131 worlds failed as xml-syntax and
    5 reported mesh-not-found before."""
    report = urdftool.check(FIXTURES / "precision" / "gz_world_quirks.sdf")
    assert not report.errors, [d.message for d in report.errors]
    infos = {(d.code, d.severity) for d in report.diagnostics if d.code in ("S001", "M002")}
    assert infos == {("S001", Severity.INFO), ("M002", Severity.INFO)}
    messages = " ".join(d.message for d in report.diagnostics)
    assert "'--'" in messages and "'::'" in messages and "prefix gz" in messages
    assert "web address" in messages


def test_double_hyphen_comment_in_a_urdf_is_a_warning(tmp_path: Path) -> None:
    path = tmp_path / "r.urdf"
    path.write_text('<robot name="r"><!-- run: roslaunch --wait --><link name="a"/></robot>')
    report = urdftool.check(path)
    assert not report.errors
    [found] = [d for d in report.diagnostics if d.code == "S001"]
    assert found.severity is Severity.WARNING and "xacro" in found.message


def test_comment_ending_in_a_hyphen_is_read_as_tinyxml_reads_it(tmp_path: Path) -> None:
    """`<!-- text --->`: the comment's text ends with a hyphen, which XML forbids and TinyXML
    reads. It is mended as `--` inside a comment is, and warned about."""
    path = tmp_path / "r.urdf"
    path.write_text('<robot name="r"><!-- a banner ---><link name="a"/></robot>')
    report = urdftool.check(path)
    assert not report.errors
    assert [d.severity for d in report.diagnostics if d.code == "S001"] == [Severity.WARNING]


@settings(max_examples=400, deadline=None)
@given(st.lists(st.sampled_from([b"<!--", b"-->", b"-", b"--", b"a", b"<a/>", b">", b"!"]), max_size=12))
def test_mended_comments_keep_every_position(parts: list[bytes]) -> None:
    """Mending `--` in comments changes bytes in place, warns once when it changes any, and
    hands back the text itself when it changes none (then the parser's refusal stands)."""
    data = b"<r>" + b"".join(parts) + b"</r>"
    warnings: list = []
    mended = xmlio._hyphens_in_comments(data, "r.urdf", warnings)
    assert len(mended) == len(data) and mended.count(b"\n") == data.count(b"\n")
    assert (mended is data) == (not warnings) and len(warnings) <= 1
    if mended is not data:
        assert mended != data


def test_blank_lines_before_the_declaration_keep_every_position(tmp_path: Path) -> None:
    """TinyXML reads a file whose XML declaration follows blank lines; libxml2 refuses it. It is
    read with a warning, and every finding keeps the line and column it has in the file, on the
    declaration's own line too (moving the blank lines behind the declaration shifted them)."""
    path = tmp_path / "r.urdf"
    text = ('\n\n<?xml version="1.0"\n  encoding="utf-8"?><robot name="r"><link name="a"><inertial>'
            '<mass valeu="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>'
            "</link></robot>\n")
    path.write_text(text)
    report = urdftool.check(path)
    found = {d.code: d for d in report.diagnostics}
    assert found["S001"].severity is Severity.WARNING and found["S001"].location.line == 3
    line = text.split("\n")[3]
    assert (found["S009"].location.line, found["S009"].location.column) == (4, line.index("valeu=") + 1)
    assert (found["S010"].location.line, found["S010"].location.column) == (4, line.index("<mass") + 1)


def test_declared_version_other_than_1_0_is_read_as_1_0(tmp_path: Path) -> None:
    """Several exporters write version="0.0"; TinyXML ignores the version, libxml2 refuses it."""
    path = tmp_path / "r.urdf"
    path.write_text('<?xml version="0.0"?>\n<robot name="r"><link name="a"/></robot>\n')
    report = urdftool.check(path)
    assert not report.errors
    assert [d.message for d in report.diagnostics if d.code == "S001"] == [
        'XML declaration has version "0.0"; read as 1.0']


@pytest.mark.parametrize("encoding", ["utf-16", "utf-16-be", "utf-32", "latin-1", "utf-8-sig"])
def test_findings_in_a_file_not_in_utf8_point_at_the_attribute(tmp_path: Path, encoding: str) -> None:
    """The readers decode UTF-16/32 (by BOM or NUL pattern) and a declared encoding; the
    attribute search and the excerpt read the text the same way, not as UTF-8."""
    declared = "ISO-8859-1" if encoding == "latin-1" else encoding.split("-sig")[0].upper()
    text = (f'<?xml version="1.0" encoding="{declared}"?>\n<robot name="r">\n  <link name="bra\u00e7o">\n'
            '    <inertial><mass valeu="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/>'
            "</inertial>\n  </link>\n</robot>\n")
    path = tmp_path / "r.urdf"
    path.write_bytes(text.encode(encoding))
    reports = check_file(str(path), CheckOptions(select=("S",)))
    [found] = [d for r in reports for d in r.diagnostics if d.code == "S009"]
    line = text.split("\n")[3]
    assert (found.location.line, found.location.column) == (4, line.index("valeu=") + 1)
    rendered = render_diagnostic(found, SourceIndex())
    assert line.strip() in rendered and "bra\u00e7o" in found.message


def test_unknown_attribute_suggests_no_name_the_tag_already_has(tmp_path: Path) -> None:
    """ANYmal B's <limit> carries ANYbotics' command_effort beside effort: "did you mean
    'effort'?" would send the user to write effort twice. A misspelling with the intended name
    absent is still answered."""
    path = tmp_path / "r.urdf"
    path.write_text(
        '<robot name="r"><link name="a"/><link name="b"/>'
        '<joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>'
        '<limit command_effort="80" effort="80" lower="-1" upper="1" velocity="2"/></joint>'
        '<joint name="k" type="revolute"><parent link="b"/><child link="c"/><axis xyz="0 0 1"/>'
        '<limit efort="80" lower="-1" upper="1" velocity="2"/></joint><link name="c"/></robot>')
    messages = [d.message for r in check_file(str(path), CheckOptions(select=("S009",)))
                for d in r.diagnostics]
    assert messages == [
        "joint[j]/limit: <limit> has no attribute 'command_effort'",
        "joint[k]/limit: <limit> has no attribute 'efort'; did you mean 'effort'?",
    ]


def test_controllers_yaml_written_for_the_ament_install_layout_is_read(tmp_path: Path) -> None:
    """ros2_control_demos' example_9 names `$(find pkg)/config/rrbot_controllers.yaml`, which its
    CMake install rule takes from bringup/config: G106 reported it missing in the source tree.
    Read from there, its controllers are checked (a wrong joint in it is found)."""
    (tmp_path / "package.xml").write_text('<package format="3"><name>demo_bot</name></package>')
    (tmp_path / "CMakeLists.txt").write_text(
        "project(demo_bot)\ninstall(\n  DIRECTORY bringup/config description/urdf\n"
        "  DESTINATION share/${PROJECT_NAME}\n)\n")
    (tmp_path / "bringup" / "config").mkdir(parents=True)
    (tmp_path / "bringup" / "config" / "controllers.yaml").write_text(
        "controller_manager:\n  ros__parameters:\n    update_rate: 100\n"
        "    arm_controller:\n      type: forward_command_controller/ForwardCommandController\n"
        "arm_controller:\n  ros__parameters:\n    joints:\n      - jj\n    interface_name: position\n")
    (tmp_path / "description" / "urdf").mkdir(parents=True)
    inertial = ('<inertial><mass value="1"/>'
                '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>')
    model = tmp_path / "description" / "urdf" / "bot.urdf.xacro"
    model.write_text(
        '<robot name="bot" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        f'<link name="base">{inertial}</link><link name="tip">{inertial}</link>'
        '<joint name="j" type="revolute"><parent link="base"/><child link="tip"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="10" velocity="1"/></joint>'
        '<ros2_control name="bot" type="system"><hardware><plugin>gz_ros2_control/GazeboSimSystem</plugin>'
        '</hardware><joint name="j"><command_interface name="position"/><state_interface name="position"/>'
        '</joint></ros2_control>'
        '<gazebo><plugin filename="gz_ros2_control-system"'
        ' name="gz_ros2_control::GazeboSimROS2ControlPlugin">'
        '<parameters>$(find demo_bot)/config/controllers.yaml</parameters></plugin></gazebo></robot>')
    report = urdftool.check(model)
    codes = [d.code for d in report.errors]
    assert "G106" not in codes
    assert "G201" in codes  # the YAML was read: its joint 'jj' is not declared


def test_closed_mesh_with_reversed_triangles_is_a_solid(tmp_path: Path) -> None:
    """A closed box whose first six triangles face inward (CAD exports write such meshes):
    MuJoCo reads it as the 0.2 m box it is (8 kg at 1000 kg/m³ for a link without inertial);
    urdftool measured 0 m³ (the signed volumes cancel) and called it flat (M008, an error)."""
    import trimesh

    box = trimesh.creation.box(extents=(0.2, 0.2, 0.2))
    faces = box.faces.copy()
    faces[:6] = faces[:6, ::-1]
    trimesh.Trimesh(box.vertices, faces, process=False).export(str(tmp_path / "flipped.obj"))
    model = tmp_path / "r.urdf"
    model.write_text(
        '<robot name="r"><link name="base"/><joint name="j" type="revolute"><parent link="base"/>'
        '<child link="a"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'
        '</joint><link name="a"><collision><geometry><mesh filename="flipped.obj"/></geometry>'
        "</collision></link></robot>")
    report = urdftool.check(model)
    assert not report.errors, [d.message for d in report.errors]
    options = CheckOptions(select=("T",), rule_options={"targets": ("mujoco",)})
    found = [d for r in check_file(str(model), options) for d in r.diagnostics]
    [mass] = [d for d in found if d.code == "T001"]
    assert mass.data["mass"] == pytest.approx(8.0, rel=1e-6)
    assert not [d for d in found if d.code == "T003"]


def test_sdf_scalar_with_a_stray_character_is_read_as_libsdformat_reads_it(tmp_path: Path) -> None:
    """Drake's iiwa14 SDF: `<velocity>2.356194490192345"</velocity>`. libsdformat parses a double
    with std::stod, which reads the number and ignores the quote, so Drake and Gazebo both get
    2.356 rad/s: a warning, and the limit is the value they read."""
    report = urdftool.check(FIXTURES / "precision" / "sdf_number_stray_quote.sdf")
    assert not report.errors, [d.message for d in report.errors]
    [found] = [d for d in report.diagnostics if d.code == "S005"]
    assert found.severity is Severity.WARNING and "libsdformat reads 2.356194490192345" in found.message
    joint = next(j for j in urdftool.load(FIXTURES / "precision" / "sdf_number_stray_quote.sdf").joints
                 if j.name == "wrist")
    assert joint.limit is not None
    assert joint.limit.velocity == pytest.approx(2.356194490192345)


@pytest.mark.parametrize("text", ["1,5", "1.2.3", "0x10", "bad", "nan"])
def test_sdf_scalar_that_loses_digits_or_is_no_number_stays_an_error(tmp_path: Path, text: str) -> None:
    # std::stod reads "1" from "1,5": the half is dropped silently, which is the error S005 is for
    source = (FIXTURES / "precision" / "sdf_number_stray_quote.sdf").read_text()
    path = tmp_path / "arm.sdf"
    path.write_text(source.replace('2.356194490192345"', text))
    found = [d for d in urdftool.check(path).diagnostics if d.code == "S005"]
    assert [d.severity for d in found] == [Severity.ERROR]


def test_drake_custom_shape_in_an_sdf_geometry_is_no_unknown_element(tmp_path: Path) -> None:
    """Drake's WSG-50 bubble gripper: `<drake:ellipsoid>` in a `<geometry>` is a custom element
    (SDFormat 1.6+), which libsdformat keeps and ignores and Drake reads; it was a warning
    "<{urn:undeclared:drake}ellipsoid> is not an SDF shape"."""
    path = tmp_path / "finger.sdf"
    path.write_text(
        '<sdf version="1.7"><model name="finger"><link name="bubble">'
        "<inertial><mass>0.1</mass><inertia><ixx>1e-4</ixx><iyy>1e-4</iyy><izz>1e-4</izz></inertia></inertial>"
        '<collision name="ellipsoid"><geometry><drake:ellipsoid><a>0.03</a><b>0.04</b><c>0.02</c>'
        "</drake:ellipsoid></geometry></collision></link></model></sdf>"
    )
    report = urdftool.check(path)
    assert not report.errors
    assert [d.message for d in report.diagnostics if d.code in ("S008", "S023")] == []


def test_gltf_mesh_in_an_sdf_model_is_a_note_not_a_warning(tmp_path: Path) -> None:
    """Drake's iiwa, WSG-50, Allegro and YCB SDFs use glTF visuals (76 warnings on 10 models):
    gz-sim and Drake, the consumers of an SDF, read glTF; MuJoCo and PyBullet only meet the
    model through an export, so M004 is an info there. A URDF keeps the warning."""
    mesh = FIXTURES / "rules" / "M004" / "meshes" / "ascii.stl"
    shutil.copy(mesh, tmp_path / "part.stl")
    sdf = tmp_path / "part.sdf"
    sdf.write_text(
        '<sdf version="1.7"><model name="part"><link name="base">'
        "<inertial><mass>0.1</mass><inertia><ixx>1e-4</ixx><iyy>1e-4</iyy><izz>1e-4</izz></inertia></inertial>"
        '<visual name="v"><geometry><mesh><uri>part.stl</uri></mesh></geometry></visual>'
        "</link></model></sdf>"
    )
    urdf = tmp_path / "part.urdf"
    urdf.write_text('<robot name="part"><link name="base"><visual><geometry><mesh filename="part.stl"/>'
                    "</geometry></visual></link></robot>")
    assert [d.severity for d in urdftool.check(sdf).diagnostics if d.code == "M004"] == [Severity.INFO]
    assert [d.severity for d in urdftool.check(urdf).diagnostics if d.code == "M004"] == [Severity.WARNING]


def _solidworks_export(root: Path, names: tuple[str, str], on_disk: tuple[str, str]) -> Path:
    """A CAD export laid out as Poppy Humanoid's: ``robots/robot.URDF`` naming its meshes
    ``package://meshes/NAME`` (no package; the folder ``meshes/`` sits beside ``robots/``)."""
    import trimesh

    (root / "robots").mkdir(parents=True)
    (root / "meshes").mkdir()
    for name in on_disk:
        trimesh.creation.box(extents=(0.05, 0.05, 0.05)).export(str(root / "meshes" / name))
    inertial = ('<inertial><mass value="0.1"/><inertia ixx="4e-5" ixy="0" ixz="0" iyy="4e-5" iyz="0"'
                ' izz="4e-5"/></inertial>')
    links = "".join(f'<link name="l{i}">{inertial}<collision><geometry><mesh filename="package://meshes/'
                    f'{name}"/></geometry></collision></link>' for i, name in enumerate(names))
    joint = ('<joint name="j" type="revolute"><parent link="l0"/><child link="l1"/><axis xyz="0 0 1"/>'
             '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>')
    model = root / "robots" / "robot.URDF"
    model.write_text(f'<robot name="cad">{links}{joint}</robot>')
    return model


def _loads_in_pybullet(model: Path) -> bool | None:
    try:
        import pybullet
    except ImportError:
        return None
    client = pybullet.connect(pybullet.DIRECT)
    try:
        pybullet.loadURDF(str(model), physicsClientId=client)
    except pybullet.error:
        return False
    finally:
        pybullet.disconnect(client)
    return True


def test_package_less_mesh_uri_pybullet_finds_one_folder_up_is_a_warning(tmp_path: Path) -> None:
    """Poppy Humanoid (poppy-project/poppy-humanoid) writes `package://meshes/pelvis_visual.STL`
    in `robots/Poppy_Humanoid.URDF`: no ROS package is called `meshes`, but PyBullet drops the
    scheme and looks in the file's folder and every folder above, where `meshes/` is. M001 was
    an error: urdftool looked beside the file only."""
    model = _solidworks_export(tmp_path / "URDF", ("base.STL", "arm.STL"), ("base.STL", "arm.STL"))
    found = [d for d in urdftool.check(model).diagnostics if d.code == "M001"]
    assert [d.severity for d in found] == [Severity.WARNING]
    assert found[0].data["pybullet_finds"] == str(tmp_path / "URDF" / "meshes" / "base.STL")
    assert _loads_in_pybullet(model) in (True, None)


def test_package_less_mesh_uri_with_one_file_pybullet_misses_stays_an_error(tmp_path: Path) -> None:
    """Poppy's URDF names ten meshes `*.STL` whose files are `*.stl`: PyBullet finds the other 42,
    misses these on a case-sensitive file system and refuses the whole robot."""
    model = _solidworks_export(tmp_path / "URDF", ("base.STL", "arm.STL"), ("base.STL", "arm.stl"))
    found = [d for d in urdftool.check(model).diagnostics if d.code == "M001"]
    assert [d.severity for d in found] == [Severity.ERROR]
    assert "PyBullet finds 1 of these 2 meshes but not 'package://meshes/arm.STL'" in (found[0].help or "")
    assert _loads_in_pybullet(model) in (False, None)


def test_a_collada_file_with_a_comment_among_its_primitives_is_read(tmp_path: Path,
                                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    """aws-robomaker-hospital-world's aws_BookshelfB_01_visual.DAE: the lean reader refuses its
    reused id, and pycollada took the comment in its <mesh> for a primitive and found no triangles
    (M003, a false error: assimp and gz-common skip comments). Read without a warm cache."""
    monkeypatch.setenv("URDFTOOL_NO_CACHE", "1")
    from urdftool.backends import meshes

    mesh = FIXTURES / "precision" / "collada_comment_in_mesh.dae"
    facts = meshes.read_facts(str(mesh))
    assert facts.faces == 4 and facts.watertight
    robot = tmp_path / "robot.urdf"
    robot.write_text('<robot name="r"><link name="base"><visual><geometry>'
                     f'<mesh filename="{mesh}"/></geometry></visual></link></robot>')
    found = urdftool.check(robot).diagnostics
    assert [d.code for d in found if d.code == "M003" or d.severity is Severity.ERROR] == []


_FLAT_STL = ("solid flat\n" + "".join(
    "facet normal 0 1 0\nouter loop\n" + "".join(f"vertex {v}\n" for v in face) + "endloop\nendfacet\n"
    for face in (("0 0 0", "1 0 0", "1 0 1"), ("0 0 0", "1 0 1", "0 0 1"))) + "endsolid flat\n")


@pytest.mark.parametrize("fmt, severity", [("sdf", Severity.WARNING), ("urdf", Severity.ERROR)])
def test_a_flat_collision_mesh_is_an_error_only_where_a_convex_hull_is_built(
        tmp_path: Path, fmt: str, severity: Severity) -> None:
    """aws-robomaker-hospital-world's hospital sign: a static SDF model whose collision mesh is one
    plane. Gazebo, which reads SDF, collides with its triangles; MuJoCo and PyBullet, which read
    URDF, need the convex hull of a solid."""
    (tmp_path / "sign.stl").write_text(_FLAT_STL)
    path = tmp_path / f"sign.{fmt}"
    mesh = "<mesh><uri>sign.stl</uri></mesh>" if fmt == "sdf" else '<mesh filename="sign.stl"/>'
    collision = f'<collision name="c"><geometry>{mesh}</geometry></collision>'
    path.write_text(
        f'<sdf version="1.9"><model name="sign"><static>true</static><link name="l">{collision}</link>'
        '</model></sdf>' if fmt == "sdf" else f'<robot name="sign"><link name="l">{collision}</link></robot>')
    found = [d.severity for d in urdftool.check(path).diagnostics if d.code == "M008"]
    assert found == [severity]


def test_scenery_sizes_are_no_evidence_of_a_unit_slip(tmp_path: Path) -> None:
    """ardupilot_gazebo's runway: a static SDF model whose airfield mesh is 14 km across and whose
    links sit 546 m apart. Scenery is no robot; the same model, not static, is still judged."""
    (tmp_path / "field.stl").write_text(_FLAT_STL.replace("1 0 1", "14000 0 14000")
                                        .replace("1 0 0", "14000 0 0").replace("0 0 1", "0 0 14000"))
    links = "".join(f'<link name="l{i}"><pose>{546 * i} 0 0 0 0 0</pose>'
                    '<visual name="v"><geometry><mesh><uri>field.stl</uri></mesh></geometry></visual></link>'
                    for i in range(2))
    links += '<joint name="j" type="fixed"><parent>l0</parent><child>l1</child></joint>'
    for static, expected in (("<static>true</static>", []), ("", ["M005"])):
        path = tmp_path / f"runway{len(static)}.sdf"
        path.write_text(f'<sdf version="1.9"><model name="runway">{static}{links}</model></sdf>')
        assert [d.code for d in urdftool.check(path, select=["M005"]).diagnostics] == expected


@pytest.mark.parametrize("mass, expected", [("1e-15", []), ("1e-16", ["I002"])])
def test_a_mass_at_mujocos_floor_is_a_mass(tmp_path: Path, mass: str, expected: list[str]) -> None:
    """PX4's typhoon_h480 sonar weighs exactly 1e-15 kg on a revolute joint: MuJoCo refuses a moving
    body below mjMINVAL (1e-15) and compiles this one, so it is no zero mass."""
    path = tmp_path / "sonar.urdf"
    path.write_text(
        '<robot name="r"><link name="base"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" '
        'ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>'
        f'<link name="sonar"><inertial><mass value="{mass}"/><inertia ixx="1e-5" ixy="0" ixz="0" '
        'iyy="1e-5" iyz="0" izz="1e-5"/></inertial></link>'
        '<joint name="j" type="revolute"><parent link="base"/><child link="sonar"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>')
    found = [d.code for d in urdftool.check(path, select=["I002"]).diagnostics]
    assert found == expected
