"""Closed chains: the spanning-tree choice, loop closures, and each loop reported exactly once."""

from __future__ import annotations

import glob
from pathlib import Path

import numpy as np
import pytest

from tests.conftest import ERD, FIXTURES
from urdftool.model import Joint, JointType, KinematicTree, Limit
from urdftool.parse import read
from urdftool.parse.sdf_tree import spanning_tree
from urdftool.pipeline.check import CheckOptions, check_file

FOUR_BAR = FIXTURES / "robots" / "four_bar.sdf"
CASSIE = sorted(glob.glob(str(ERD / "cassie_description" / "robots" / "*.sdf"))) if ERD else []


def _codes(path: Path | str, *codes: str) -> list[tuple[str, int | None]]:
    reports = check_file(str(path), CheckOptions())
    return [(d.code, d.location.line if d.location else None)
            for r in reports for d in r.diagnostics if d.code in codes]


def test_four_bar_loads_with_one_loop_closure() -> None:
    robot = read(str(FOUR_BAR))[0].robot
    assert robot is not None
    (closure,) = robot.loop_closures
    assert closure.joint.name == "coupler_to_rocker"
    assert "coupler_to_rocker" not in {j.name for j in robot.joints}
    assert {(j.parent, j.child) for j in robot.joints} >= {("ground", "crank"), ("crank", "coupler"),
                                                            ("ground", "rocker")}


def test_four_bar_anchors_are_the_rocker_tip_in_both_bodies() -> None:
    robot = read(str(FOUR_BAR))[0].robot
    (closure,) = robot.loop_closures
    # the coupler's far end, 0.4123 m along its own z axis, and the rocker's tip, 0.3 m up
    np.testing.assert_allclose(closure.parent_anchor.xyz, [0, 0, 0.412310562561766], atol=1e-12)
    np.testing.assert_allclose(closure.child_anchor.xyz, [0, 0, 0.3], atol=1e-12)
    fk = KinematicTree.of(robot).forward_kinematics()
    in_parent = fk["coupler"] @ closure.parent_anchor.matrix
    in_child = fk["rocker"] @ closure.child_anchor.matrix
    np.testing.assert_allclose(in_parent, in_child, atol=1e-12)
    np.testing.assert_allclose(in_child[:3, 3], [0.4, 0, 0.3], atol=1e-12)
    # the cut joint turns about y in its own frame
    np.testing.assert_allclose(closure.joint.axis, [0, 1, 0], atol=1e-12)


def test_four_bar_loop_is_reported_with_its_links() -> None:
    reports = check_file(str(FOUR_BAR), CheckOptions())
    (finding,) = [d for r in reports for d in r.diagnostics if d.code == "L001"]
    assert finding.severity.value == "info"
    assert finding.data["links"] == ["coupler", "crank", "ground", "rocker"]
    assert finding.data["joints"] == ["crank_to_coupler", "crank_joint", "rocker_joint", "coupler_to_rocker"]
    assert not [d for r in reports for d in r.diagnostics if d.severity.value == "error"]


@pytest.mark.parametrize("path", CASSIE, ids=lambda p: Path(p).name)
def test_cassie_loops_are_reported_each_with_its_links(path: str) -> None:
    robot = read(path)[0].robot
    reports = check_file(path, CheckOptions())
    loops = [d for r in reports for d in r.diagnostics if d.code == "L001"]
    assert len(loops) == len(robot.loop_closures) >= 4
    for finding in loops:
        links = finding.data["links"]
        assert len(links) >= 2 and len(set(links)) == len(links)
        assert finding.data["cut_joint"] == finding.data["joints"][-1]
    # every anchor pair coincides at the initial pose
    fk = KinematicTree.of(robot).forward_kinematics()
    for closure in robot.loop_closures:
        a = fk[closure.joint.parent] @ closure.parent_anchor.matrix
        b = fk[closure.joint.child] @ closure.child_anchor.matrix
        np.testing.assert_allclose(a, b, atol=1e-9)


def test_cassie_achilles_loop_is_cut_at_the_passive_ball_joint() -> None:
    robot = read(str(Path(CASSIE[0]).with_name("cassie_v2.sdf")))[0].robot
    cut = {lc.joint.name: lc.joint.type for lc in robot.loop_closures}
    assert cut["left-pitch-rod-joint"] is JointType.SPHERICAL


def test_cassie_knee_spring_loop_keeps_the_slider_and_cuts_the_hinge() -> None:
    """The knee-spring loop (knee → spring by a hinge; knee → shin → spring by a slider) is cut at
    the hinge, which MJCF closes with two connects; the slider stays in the tree."""
    robot = read(CASSIE[0])[0].robot  # cassie.sdf
    assert Path(CASSIE[0]).name == "cassie.sdf"
    cut = {lc.joint.name: lc.joint.type for lc in robot.loop_closures}
    kept = {j.name: j for j in robot.joints}
    for side in ("left", "right"):
        assert cut[f"{side}-knee-spring-joint"] is JointType.CONTINUOUS
        slider = kept[f"{side}-shin-spring-joint"]
        assert slider.type is JointType.PRISMATIC
        assert (slider.parent, slider.child) == (f"{side}-shin", f"{side}-knee-spring")
    assert not any(t is JointType.PRISMATIC for t in cut.values())


def _joint(name: str, parent: str, child: str, jtype: JointType = JointType.REVOLUTE,
           effort: float | None = None) -> Joint:
    limit = Limit(-1, 1, effort, 1) if effort is not None else None
    return Joint(name, jtype, parent, child, limit=limit)


def test_spanning_tree_prefers_shortest_path_then_actuated_joints() -> None:
    links = ["a", "b", "c", "d"]
    joints = [
        _joint("a_b", "a", "b"),
        _joint("b_d", "b", "d", effort=10),
        _joint("a_c", "a", "c"),
        _joint("c_d", "c", "d", JointType.SPHERICAL),
        _joint("a_d_long", "d", "b"),
    ]
    tree, cut = spanning_tree(links, joints)
    assert [j.name for j in tree] == ["a_b", "b_d", "a_c"]
    assert [j.name for j in cut] == ["c_d", "a_d_long"]
    # with the ball joint actuated instead, the unactuated revolute is cut
    joints[1] = _joint("b_d", "b", "d")
    joints[3] = _joint("c_d", "c", "d", effort=10)
    tree, cut = spanning_tree(links, joints)
    assert "c_d" in [j.name for j in tree] and "b_d" in [j.name for j in cut]


def test_spanning_tree_keeps_a_slider_and_cuts_the_hinge_reaching_the_same_link() -> None:
    # a -> c by a hinge (depth 1) and a -> b -> c with b -> c a slider (depth 2): breadth-first
    # cuts the slider, which no MJCF equality closes; the hinge is cut instead.
    links = ["a", "b", "c", "d"]
    joints = [_joint("a_b", "a", "b"), _joint("a_c", "a", "c", JointType.CONTINUOUS),
              _joint("b_c", "b", "c", JointType.PRISMATIC), _joint("c_d", "c", "d")]
    tree, cut = spanning_tree(links, joints)
    assert [j.name for j in tree] == ["a_b", "b_c", "c_d"] and [j.name for j in cut] == ["a_c"]
    # an actuated hinge (effort limit) is kept over a passive slider
    joints[1] = _joint("a_c", "a", "c", effort=10)
    tree, cut = spanning_tree(links, joints)
    assert [j.name for j in cut] == ["b_c"]
    # a slider whose parent hangs below its child would close a cycle: the slider stays cut
    joints = [_joint("a_c", "a", "c"), _joint("c_b", "c", "b"), _joint("b_c", "b", "c", JointType.PRISMATIC)]
    tree, cut = spanning_tree(["a", "b", "c"], joints)
    assert [j.name for j in cut] == ["b_c"]
    # a fixed joint reaching the link is cut too (MJCF closes it with a weld)
    joints = [_joint("a_b", "a", "b"), _joint("a_c", "a", "c", JointType.FIXED),
              _joint("b_c", "b", "c", JointType.PRISMATIC)]
    tree, cut = spanning_tree(["a", "b", "c"], joints)
    assert [j.name for j in cut] == ["a_c"]


def test_spanning_tree_of_a_closed_ring_without_root_is_deterministic() -> None:
    links = ["a", "b", "c"]
    joints = [_joint("ab", "a", "b"), _joint("bc", "b", "c"), _joint("ca", "c", "a")]
    tree, cut = spanning_tree(links, joints)
    assert [j.name for j in tree] == ["ab", "bc"] and [j.name for j in cut] == ["ca"]


def _urdf(tmp_path: Path, joints: str) -> Path:
    path = tmp_path / "r.urdf"
    links = "".join(f'<link name="{n}"/>' for n in ("l1", "l2", "l3", "l4"))
    path.write_text(f'<robot name="r">{links}\n{joints}</robot>\n')
    return path


def _j(name: str, parent: str, child: str) -> str:
    return f'<joint name="{name}" type="fixed"><parent link="{parent}"/><child link="{child}"/></joint>\n'


def test_urdf_diamond_is_one_multiple_parents_error(tmp_path: Path) -> None:
    path = _urdf(
        tmp_path, _j("a", "l1", "l2") + _j("b", "l1", "l3") + _j("c", "l2", "l4") + _j("d", "l3", "l4")
    )
    assert _codes(path, "L002", "S018", "L001") == [("L002", 5)]


def test_urdf_directed_cycle_is_one_kinematic_loop_error(tmp_path: Path) -> None:
    path = _urdf(tmp_path, _j("a", "l1", "l2") + _j("b", "l2", "l3") + _j("c", "l3", "l2"))
    assert _codes(path, "L002", "S018", "L001") == [("S018", 4)]


def test_sdf_loops_are_not_structural_errors() -> None:
    assert _codes(FOUR_BAR, "L002", "S018", "S017") == []
