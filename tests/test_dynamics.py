"""The dynamics pass (D rules): Pinocchio numbers on fixtures and on example-robot-data."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import ERD, FIXTURES, ROOT
from urdftool.diagnostics import Diagnostic
from urdftool.facts.dynamics.analysis import analyse
from urdftool.facts.dynamics.configurations import configurations, joint_range, zero_configuration
from urdftool.facts.dynamics.coverage import floating_base, not_covered
from urdftool.model import JointType, KinematicTree
from urdftool.parse import read
from urdftool.physics.com import center_of_mass
from urdftool.pipeline.check import CheckOptions, check_file

RULES = FIXTURES / "rules"


def dynamics_findings(path: str | Path, **options: object) -> list[Diagnostic]:
    reports = check_file(str(path), CheckOptions(select=("D",), rule_options=options))
    return [d for r in reports for d in r.diagnostics]


def load(path: str | Path):  # type: ignore[no-untyped-def]
    from urdftool import load as load_robot

    return load_robot(path)


def test_horizontal_link_needs_24_5_newton_metres() -> None:
    found = dynamics_findings(RULES / "D003" / "bad.urdf")
    assert [d.name for d in found] == ["gravity-torque-exceeds-effort"]
    finding = found[0]
    assert "needs 24.5 N·m" in finding.message and "limit 10 N·m" in finding.message
    assert finding.data["torque"] == pytest.approx(5 * 9.81 * 0.5)
    assert finding.data["configuration"] == {"shoulder": 0.0}
    assert finding.location is not None and finding.location.line == 11


def test_correct_arm_is_not_reported() -> None:
    assert dynamics_findings(FIXTURES / "robots" / "two_link_arm.urdf") == []
    assert dynamics_findings(RULES / "D003" / "good.urdf") == []


def test_gravity_torque_is_the_worst_over_the_samples() -> None:
    # Upright at q = 0, the two-link arm's shoulder holds nothing; the samples tilt it.
    robot = load(FIXTURES / "robots" / "two_link_arm.urdf")
    tree = KinematicTree.of(robot)
    result = analyse(robot, tree, floating=False, base_reason="test")
    shoulder = next(load for load in result.gravity if load.joint.name == "shoulder")
    assert shoulder.sample > 0
    # Both 1 kg links fully horizontal would need 9.81 · (0.25 + 0.75) N·m.
    assert 2.0 < shoulder.torque < 9.81 * 1.0


def test_massless_moving_link_makes_the_mass_matrix_singular() -> None:
    found = dynamics_findings(RULES / "D001" / "bad.urdf")
    assert [d.code for d in found] == ["D001"]
    assert "joint 'finger'" in found[0].message and found[0].data["light_joint"] == "finger"


def test_placeholder_inertia_is_ill_conditioned() -> None:
    found = dynamics_findings(RULES / "D002" / "bad.urdf")
    assert [d.code for d in found] == ["D002"]
    assert found[0].data["condition_number"] == pytest.approx(1.6677e9, rel=1e-3)
    assert found[0].data["light_joint"] == "wrist"


def test_invalid_inertia_is_said_once_and_nothing_else() -> None:
    found = dynamics_findings(RULES / "D004" / "bad.urdf")
    assert [d.code for d in found] == ["D004"]
    assert "'arm'" in found[0].message and found[0].location is not None and found[0].location.line == 15


def test_no_dynamics_switch_turns_the_pass_off() -> None:
    assert dynamics_findings(RULES / "D003" / "bad.urdf", dynamics=False) == []


def test_no_dynamics_check_does_not_import_pinocchio() -> None:
    script = (
        "import sys\n"
        "from click.testing import CliRunner\n"
        "from urdftool.cli import main\n"
        "result = CliRunner().invoke(\n"
        f"    main, ['check', '--no-dynamics', {str(RULES / 'D003' / 'bad.urdf')!r}]\n"
        ")\n"
        "assert result.exit_code == 0, result.output\n"
        "print('pinocchio' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=ROOT, check=True)
    assert out.stdout.strip() == "False"


def test_check_runs_dynamics_by_default_through_the_cli() -> None:
    from click.testing import CliRunner

    from urdftool.cli import main

    result = CliRunner().invoke(main, ["check", "--format", "json", str(RULES / "D003" / "bad.urdf")])
    codes = [d["code"] for f in json.loads(result.output)["files"] for d in f["diagnostics"]]
    assert "D003" in codes and result.exit_code == 0  # a warning does not fail without --strict


def test_same_input_same_numbers() -> None:
    robot = load(FIXTURES / "robots" / "two_link_arm.urdf")
    tree = KinematicTree.of(robot)
    first = analyse(robot, tree, False, "test")
    second = analyse(robot, tree, False, "test")
    assert first.conditioning == second.conditioning
    assert [(g.joint.name, g.torque, g.sample) for g in first.gravity] == \
        [(g.joint.name, g.torque, g.sample) for g in second.gravity]


def test_samples_stay_within_limits_and_start_at_zero() -> None:
    robot = load(RULES / "D002" / "bad.urdf")
    tree = KinematicTree.of(robot)
    poses = configurations(tree, 50)
    assert poses[0] == zero_configuration(tree) == {"shoulder": 0.0, "wrist": 0.0}
    for pose in poses:
        for name, value in pose.items():
            joint = robot.joint(name)
            assert joint is not None
            low, high = joint_range(joint)  # type: ignore[misc]
            assert low <= value <= high


def test_mobile_robots_get_a_free_flyer_and_no_gravity_check() -> None:
    assert ERD is not None
    robot = load(ERD / "solo_description" / "robots" / "solo12.urdf")
    tree = KinematicTree.of(robot)
    floating, why = floating_base(robot, tree)
    assert floating and "legs" in why
    result = analyse(robot, tree, floating, why, samples=2)
    assert result.dof == 12 + 6 and not result.gravity_computed and result.gravity == []


def test_mimic_joints_are_reduced_to_their_leader() -> None:
    assert ERD is not None
    robot = load(ERD / "panda_description" / "urdf" / "panda.urdf")
    tree = KinematicTree.of(robot)
    mimics = [j for j in robot.joints if j.mimic is not None]
    assert mimics, "panda's second finger mimics the first"
    result = analyse(robot, tree, False, "test", samples=2)
    assert result.dof == tree.dof
    assert {g.joint.name for g in result.gravity}.isdisjoint({j.name for j in mimics})


def test_center_of_mass_of_the_weak_shoulder() -> None:
    robot = load(RULES / "D003" / "bad.urdf")
    com = center_of_mass(robot)
    assert com == pytest.approx((2.5 / 7, 0.0, 0.5 / 7))


def test_info_reports_total_mass_and_com() -> None:
    from click.testing import CliRunner

    from urdftool.cli import main

    result = CliRunner().invoke(main, ["info", "--format", "json", str(RULES / "D003" / "bad.urdf")])
    summary = json.loads(result.output)
    assert summary["total_mass"] == pytest.approx(7.0)
    assert summary["center_of_mass"] == pytest.approx([2.5 / 7, 0.0, 0.5 / 7])
    text = CliRunner().invoke(main, ["info", str(RULES / "D003" / "bad.urdf")]).output
    assert "COM:         (0.3571, 0, 0.07143) m" in text


def test_unsupported_joint_types_are_not_covered() -> None:
    import dataclasses

    robot = load(FIXTURES / "robots" / "two_link_arm.urdf")
    joints = tuple(
        dataclasses.replace(j, type=JointType.SCREW) if j.name == "elbow" else j for j in robot.joints
    )
    screwed = dataclasses.replace(robot, joints=joints)
    reason = not_covered(screwed, KinematicTree.of(screwed))
    assert reason is not None and "'elbow' (screw)" in reason.reason


#: What the pass finds on example-robot-data (calibration, docs/dynamics.md).
KNOWN = {
    "baxter_description/urdf/baxter.urdf": {"D003"},
    "talos_data/robots/talos_left_arm.urdf": {"D003"},
    "romeo_description/urdf/romeo.urdf": {"D001"},
    "ur_description/urdf/ur5_robot.urdf": set(),
    "panda_description/urdf/panda.urdf": set(),
    "solo_description/robots/solo12.urdf": set(),
    "anymal_c_simple_description/urdf/anymal.urdf": {"D004"},
}


@pytest.mark.parametrize("relative", sorted(KNOWN))
def test_known_findings_on_example_robot_data(relative: str) -> None:
    assert ERD is not None
    found = {d.code for d in dynamics_findings(ERD / relative)}
    assert found == KNOWN[relative]


def test_every_example_robot_data_model_gets_through_the_pass() -> None:
    """No rule crash on the whole corpus, and each model is either checked or says why not."""
    from tests.conftest import erd_urdfs
    from urdftool.facts.dynamics.run import Skipped, dynamics_of
    from urdftool.parse.packages import PackageResolver

    checked = skipped = 0
    for path in erd_urdfs():
        for loaded in read(path, {}, PackageResolver.create()):
            if loaded.robot is None:
                continue
            tree = KinematicTree.of(loaded.robot)
            result = dynamics_of(loaded.robot, tree, {"dynamics_samples": 2})
            if isinstance(result, Skipped):
                skipped += 1
                assert result.why.elements
            else:
                checked += 1
    assert checked >= 45 and skipped >= 10, (checked, skipped)


def test_mimic_cycle_is_not_covered_and_does_not_hang() -> None:
    found = dynamics_findings(RULES / "J009" / "bad.urdf")
    assert [d.code for d in found] == ["D004"]
    assert "mimic joints follow each other in a cycle" in found[0].message
