"""The SRDF reader, its discovery beside the model, and the SRDF rules on real and broken files."""

from __future__ import annotations

import collections
import dataclasses
import glob
import pickle
import shutil
from pathlib import Path

import pytest

from tests.conftest import ERD
from urdftool.parse.srdf import read_srdf
from urdftool.pipeline.check import CheckOptions, check_file
from urdftool.pipeline.srdf import find_srdf

ROBOTS = Path(ERD) if ERD is not None else None

#: Every URDF of example-robot-data that has an SRDF of its stem, with the SRDF findings
#: (by code) on the pair. Each was reviewed: all are defects of the SRDF as MoveIt reads
#: it (docs/srdf.md lists them); the pairs not listed here check clean.
KNOWN = {
    "alex_description/urdf/alex_nub_hands.urdf": {"P002": 2},
    "alex_description/urdf/alex_psyonic_hands.urdf": {"P001": 1, "P002": 2, "P008": 2},
    "alex_description/urdf/alex_sake_hands.urdf": {"P001": 1, "P002": 2},
    "b1_description/urdf/b1-z1.urdf": {"P007": 12},
    "bolt_description/robots/bolt.urdf": {"P001": 1},
    "borinot_description/urdf/borinot_flying_arm_2.urdf": {"P002": 1},
    "finger_edu_description/robots/finger_edu.urdf": {"P001": 1, "P007": 1},
    "go2_description/urdf/go2.urdf": {"P001": 1},
    "hextilt_description/urdf/hextilt_flying_arm_5.urdf": {"P002": 1},
    "icub_description/robots/icub.urdf": {"P001": 1, "P004": 2},
    "kinova_description/robots/kinova.urdf": {"P008": 1},
    "romeo_description/urdf/romeo.urdf": {"P003": 8},
    "romeo_description/urdf/romeo_small.urdf": {"P003": 6},
    "simple_humanoid_description/urdf/simple_humanoid.urdf": {"P002": 4, "P005": 1, "P008": 4},
    "simple_humanoid_description/urdf/simple_humanoid_classical.urdf":
        {"P001": 1, "P002": 4, "P005": 1, "P008": 3},
    "solo_description/robots/solo.urdf": {"P002": 8, "P003": 12, "P005": 16},
    "ur_description/urdf/ur3_gripper.urdf": {"P001": 1},
    "z1_description/urdf/z1.urdf": {"P001": 1, "P002": 1},
}
CLEAN = [
    "a1_description/urdf/a1.urdf", "anymal_b_simple_description/robots/anymal-kinova.urdf",
    "anymal_b_simple_description/robots/anymal.urdf", "anymal_c_simple_description/urdf/anymal.urdf",
    "b1_description/urdf/b1.urdf", "centauro_description/urdf/centauro.urdf", "go1_description/urdf/go1.urdf",
    "panda_description/urdf/panda.urdf", "pr2_description/urdf/pr2.urdf",
    "ur_description/urdf/ur5_gripper.urdf", "ur_description/urdf/ur5_joint_limited_robot.urdf",
    "xarm_description/urdf/xarm7.urdf",
]
OPTIONS = CheckOptions(rule_options={"dynamics": False})


def srdf_findings(model: str, options: CheckOptions = OPTIONS) -> list:
    return [d for r in check_file(model, options) for d in r.diagnostics
            if d.location and d.location.path.endswith(".srdf")]


needs_erd = pytest.mark.skipif(ROBOTS is None, reason="example-robot-data is not installed")


@needs_erd
def test_every_example_robot_data_srdf_is_found_and_checked() -> None:
    assert ROBOTS is not None
    paired = {}
    for model in sorted(glob.glob(str(ROBOTS / "**" / "*.urdf"), recursive=True)):
        if find_srdf(model):
            counts = collections.Counter(d.code for d in srdf_findings(model))
            paired[str(Path(model).relative_to(ROBOTS))] = dict(counts)
    assert {k: v for k, v in paired.items() if v} == KNOWN
    assert sorted(k for k, v in paired.items() if not v) == sorted(CLEAN)


@needs_erd
@pytest.mark.parametrize("srdf", sorted(glob.glob(str(ROBOTS / "*" / "srdf" / "*.srdf"))) if ROBOTS else [],
                         ids=lambda p: Path(p).name)
def test_every_example_robot_data_srdf_reads_without_findings(srdf: str) -> None:
    assert read_srdf(srdf).diagnostics == []


#: (line, old text, new text, code that must fire on that line) — single edits of the Panda SRDF.
PANDA_EDITS = [
    (2, '<robot name="panda">', '<robot name="panda_arm">', "P001"),
    (4, '"panda_joint1"/>', '"panda_joint_1"/>', "P003"),
    (14, '<joint name="panda_finger_joint1"/>', '<chain base_link="panda_hand" tip_link="panda_link0"/>',
     "P004"),
    (18, '<group name="arm"/>', '<group name="arms"/>', "P005"),
    (22, 'group="arm_and_hand"', 'group="arm_hand"', "P005"),
    (27, 'value="-2.35619"', 'value="0.5"', "P008"),
    (28, 'name="panda_joint5" value="0"', 'name="panda_joint5" value="0 0"', "P008"),
    (29, 'value="1.5707"', 'value="one"', "S005"),
    (30, '"panda_joint7"', '"panda_joint8"', "P007"),  # joint8 exists, fixed, outside the group
    (33, 'parent_link="panda_hand_tcp"', 'parent_link="panda_hand_tc"', "P002"),
    (33, 'group="arm"', 'group="armm"', "P005"),
    (35, 'link2="panda_leftfinger"', 'link2="panda_left_finger"', "P002"),
    (36, 'reason="Never"', 'reason="Nevr"', "P011"),
    (37, 'link2="panda_link4"', 'link2="panda_hand"', "P011"),
]


@needs_erd
@pytest.mark.parametrize(("line", "old", "new", "code"), PANDA_EDITS, ids=lambda v: str(v))
def test_single_edit_breakage_of_the_panda_srdf_is_found_at_its_line(
    tmp_path: Path, line: int, old: str, new: str, code: str
) -> None:
    assert ROBOTS is not None
    source = ROBOTS / "panda_description"
    shutil.copytree(source / "urdf", tmp_path / "urdf")
    shutil.copytree(source / "meshes", tmp_path / "meshes")
    lines = (source / "srdf" / "panda.srdf").read_text().splitlines(keepends=True)
    assert old in lines[line - 1]
    lines[line - 1] = lines[line - 1].replace(old, new, 1)
    (tmp_path / "srdf").mkdir()
    (tmp_path / "srdf" / "panda.srdf").write_text("".join(lines))
    model = str(tmp_path / "urdf" / "panda.urdf")
    found = srdf_findings(model)
    # the edit is found at its line; a follow-on finding (a state whose joint left the group) may join it
    assert (code, line) in [(d.code, d.location.line) for d in found], found


@needs_erd
def test_check_srdf_option_and_no_srdf(tmp_path: Path) -> None:
    assert ROBOTS is not None
    model = str(ROBOTS / "panda_description" / "urdf" / "panda.urdf")
    bad = tmp_path / "other.srdf"
    bad.write_text('<robot name="panda"><group name="g"><link name="nope"/></group></robot>')
    from dataclasses import replace

    found = srdf_findings(model, replace(OPTIONS, srdf=str(bad)))
    assert [(d.code, d.location.line, d.location.column) for d in found] == [("P002", 1, 37)]
    assert srdf_findings(model, replace(OPTIONS, discover_srdf=False)) == []


def test_xacro_srdf_is_expanded_and_located(tmp_path: Path) -> None:
    urdf = Path(__file__).parent.parent / "fixtures" / "rules" / "P002" / "good.urdf"
    shutil.copy(urdf, tmp_path / "arm.urdf")
    (tmp_path / "arm.srdf.xacro").write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="mini_arm">\n'
        '  <xacro:macro name="arm_group" params="tip">\n'
        '    <group name="arm"><chain base_link="base_link" tip_link="${tip}"/></group>\n'
        '  </xacro:macro>\n'
        '  <xacro:arm_group tip="hnad"/>\n'
        "</robot>\n"
    )
    reports = check_file(str(tmp_path / "arm.urdf"), OPTIONS)
    found = [d for r in reports for d in r.diagnostics if d.code == "P002"]
    assert [(Path(d.location.path).name, d.location.line) for d in found] == [("arm.srdf.xacro", 4)]


def test_xacro_srdf_gets_the_models_xacro_arguments(tmp_path: Path) -> None:
    """provenance: reduced from Universal_Robots_ROS2_Driver ur_moveit_config/srdf/ur.srdf.xacro
    (BSD-3-Clause), hand-written. The root reads $(arg name) before the file declares it, so xacro
    stops without a mapping; MoveIt's launch passes one, as ``-a name:=...`` passes it here. The
    model's other arguments (``names``, close to the SRDF's ``name``) are not the SRDF's to report."""
    urdf = Path(__file__).parent.parent / "fixtures" / "rules" / "P002" / "good.urdf"
    shutil.copy(urdf, tmp_path / "arm.urdf")
    srdf = tmp_path / "arm.srdf.xacro"
    srdf.write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="$(arg name)">\n'
        '  <xacro:arg name="name" default="mini_arm"/>\n'
        '  <group name="arm"><chain base_link="base_link" tip_link="hnad"/></group>\n'
        "</robot>\n"
    )
    bare = check_file(str(tmp_path / "arm.urdf"), OPTIONS)
    assert "X001" in {d.code for r in bare for d in r.diagnostics}  # as xacro does without it
    given = dataclasses.replace(OPTIONS, xacro_args={"name": "mini_arm", "names": "ur5e"})
    reports = check_file(str(tmp_path / "arm.urdf"), given)
    codes = [(d.code, Path(d.location.path).name) for r in reports for d in r.diagnostics
             if d.code.startswith(("X", "P"))]
    assert codes == [("P002", "arm.srdf.xacro")]


def test_collision_pairs_are_built_when_first_read_and_pickle_built(tmp_path: Path) -> None:
    """SRDFs list hundreds to thousands of pairs and a structural check reads none: the reader
    reports an entry that does not name both links where it stands, and builds the pairs on the
    first read of ``collisions``, in document order, with their spans."""
    path = tmp_path / "arm.srdf"
    path.write_text(
        '<robot name="arm">\n'
        '  <disable_collisions link1="base" link2="upper" reason="Adjacent"/>\n'
        '  <disable_collisions link1="  " link2="upper"/>\n'
        '  <enable_collisions link1="upper" link2="lower"/>\n'
        "</robot>\n"
    )
    srdf = read_srdf(str(path))
    assert [(d.name, d.location.line if d.location else None) for d in srdf.diagnostics] == [
        ("missing-attribute", 3)]
    assert "collisions" not in vars(srdf)  # not built yet
    # The rules test every pair's names first, without building the pairs and their spans.
    names = [("base", "upper", "Adjacent", False), ("upper", "lower", None, True)]
    assert srdf.collision_names == names and "collisions" not in vars(srdf)
    pairs = [(p.link1.name, p.link2.name, p.reason, p.enable, p.span.line if p.span else None)
             for p in srdf.collisions]
    assert pairs == [("base", "upper", "Adjacent", False, 2), ("upper", "lower", None, True, 4)]
    copied = pickle.loads(pickle.dumps(read_srdf(str(path))))
    assert copied.collisions == srdf.collisions and copied.collision_pairs is None
    assert copied.collision_names == names and copied.collision_names_of is None


@pytest.mark.parametrize("virtual, expected", [
    # MoveIt skips a fixed virtual joint on another link and fixes the root in place: a warning
    ('type="fixed" parent_frame="world" child_link="link1"', [("P010", "warning")]),
    # a planar base that MoveIt skips is planned as fixed: an error
    ('type="planar" parent_frame="odom" child_link="link1"', [("P010", "error")]),
    # a fixed virtual joint's parent frame is not used: a robot link is fine there
    ('type="fixed" parent_frame="base_link" child_link="base_link"', []),
    ('type="floating" parent_frame="hand" child_link="base_link"', [("P010", "error")]),
    ('type="fixed" parent_frame="world" child_link="base_link"', []),
])
def test_a_virtual_joint_is_judged_as_moveit_builds_it(tmp_path: Path, virtual: str,
                                                       expected: list[tuple[str, str]]) -> None:
    rules = Path(__file__).parent.parent / "fixtures" / "rules" / "P010"
    model = tmp_path / "arm.urdf"
    shutil.copy(rules / "good.urdf", model)
    (tmp_path / "arm.srdf").write_text(
        f'<robot name="mini_arm"><virtual_joint name="v" {virtual}/></robot>')
    found = [(d.code, d.severity.value) for d in srdf_findings(str(model)) if d.code == "P010"]
    assert found == expected


def test_the_gazebo_world_joint_and_the_setup_assistants_virtual_joint_agree(tmp_path: Path) -> None:
    """schunk_lwa4d's pattern (good_world_root.*): a URDF that starts at "world" and fixes base_link
    to it, and an SRDF whose fixed virtual joint says the same. A virtual joint on a link the URDF
    does not fix to its root is still reported."""
    rules = Path(__file__).parent.parent / "fixtures" / "rules" / "P010"
    assert [d.code for d in srdf_findings(str(rules / "good_world_root.urdf")) if d.code == "P010"] == []
    model = tmp_path / "arm.urdf"
    shutil.copy(rules / "good_world_root.urdf", model)
    (tmp_path / "arm.srdf").write_text(
        '<robot name="mini_arm"><virtual_joint name="v" type="fixed" parent_frame="world" '
        'child_link="link1"/></robot>')
    assert [(d.code, d.severity.value) for d in srdf_findings(str(model))] == [("P010", "warning")]


@pytest.mark.parametrize("gripper, expected", [
    # the flange's fixed joint in both groups, as the Setup Assistant writes the Panda's hand
    ('<joint name="hand_joint"/><joint name="finger_l_joint"/>', []),
    # a moving joint in both: two groups command it
    ('<joint name="j3"/><joint name="finger_l_joint"/>', [("P009", "warning")]),
])
def test_an_end_effector_may_share_fixed_joints_with_its_arm(tmp_path: Path, gripper: str,
                                                            expected: list[tuple[str, str]]) -> None:
    model = tmp_path / "arm.urdf"
    shutil.copy(Path(__file__).parent.parent / "fixtures" / "rules" / "P009" / "good.urdf", model)
    (tmp_path / "arm.srdf").write_text(
        '<robot name="mini_arm"><group name="arm"><chain base_link="base_link" tip_link="hand"/></group>'
        f'<group name="gripper">{gripper}</group>'
        '<end_effector name="eef" parent_link="link3" group="gripper" parent_group="arm"/></robot>')
    found = [(d.code, d.severity.value) for d in srdf_findings(str(model)) if d.code == "P009"]
    assert found == expected


def test_a_top_level_element_inside_a_group_is_named_as_misplaced(tmp_path: Path) -> None:
    """turtlebot3_manipulation's SRDF writes its gripper's <passive_joint> inside the <group>: an
    SRDF element, in a place MoveIt does not read it."""
    model = tmp_path / "arm.urdf"
    shutil.copy(Path(__file__).parent.parent / "fixtures" / "rules" / "P009" / "good.urdf", model)
    (tmp_path / "arm.srdf").write_text(
        '<robot name="mini_arm"><group name="gripper"><joint name="finger_l_joint"/>'
        '<passive_joint name="finger_r_joint"/><linkk name="hand"/></group></robot>')
    found = [(d.code, d.message, d.help) for d in srdf_findings(str(model)) if d.code == "S008"]
    assert found == [
        ("S008", "<passive_joint> is an SRDF element of <robot>, not of <group>; MoveIt ignores it here",
         "move <passive_joint> out of <group>, to the top level"),
        ("S008", "<linkk> is not an SRDF element; MoveIt ignores it; did you mean 'link'?", None),
    ]
