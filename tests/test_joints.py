"""The joint rules on robots built here and on the corpora."""

from __future__ import annotations

import dataclasses
import math

import pytest

from tests.conftest import ERD
from urdftool.model import Inertial, Joint, JointType, Limit, Link, Mimic, Robot
from urdftool.pipeline.check import CheckOptions, check_file, run_rules
from urdftool.rules import Selection
from urdftool.rules.joints import home_position


def _link(name: str) -> Link:
    return Link(name, Inertial(1.0, Inertial.tensor(0.01, 0, 0, 0.01, 0, 0.01)))


def _revolute(
    name: str,
    parent: str,
    child: str,
    lower: float = -1.0,
    upper: float = 1.0,
    mimic: Mimic | None = None,
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0),
) -> Joint:
    return Joint(
        name,
        JointType.REVOLUTE,
        parent,
        child,
        axis=axis,
        limit=Limit(lower, upper, 10.0, 1.0),
        mimic=mimic,
    )


def _chain(count: int, mimic_of: dict[int, int] | None = None) -> Robot:
    """A chain of *count* revolute joints; ``mimic_of[i] = j`` makes joint i follow joint j."""
    mimic_of = mimic_of or {}
    links = tuple(_link(f"l{i}") for i in range(count + 1))
    joints = tuple(
        _revolute(
            f"j{i}", f"l{i}", f"l{i + 1}", mimic=Mimic(f"j{mimic_of[i]}") if i in mimic_of else None
        )
        for i in range(count)
    )
    return Robot("chain", links=links, joints=joints, path="built-in-test.urdf")


def _found(robot: Robot, code: str) -> list:  # type: ignore[type-arg]
    return run_rules(robot, Selection.of((code,), ()))


def test_a_long_mimic_cycle_terminates_and_is_reported_once() -> None:
    count = 400
    robot = _chain(count, {i: (i + 1) % count for i in range(count)})
    found = _found(robot, "J009")
    assert len(found) == 1
    assert len(found[0].data["cycle"]) == count
    assert found[0].element == "joint[j0]/mimic"


def test_joints_leading_into_a_cycle_are_not_cycles() -> None:
    robot = _chain(4, {0: 1, 1: 2, 2: 1, 3: 0})  # j0 -> j1 <-> j2, j3 -> j0
    found = _found(robot, "J009")
    assert [d.data["cycle"] for d in found] == [["j1", "j2"]]


def test_home_position_follows_mimic_chains_and_the_named_home() -> None:
    robot = _chain(3, {1: 0, 2: 1})
    robot = dataclasses.replace(
        robot,
        joints=(
            robot.joints[0],
            dataclasses.replace(robot.joints[1], mimic=Mimic("j0", 2.0, 0.1)),
            dataclasses.replace(robot.joints[2], mimic=Mimic("j1", -1.0, 0.5)),
        ),
    )
    named = dataclasses.replace(robot, home={"j0": 0.3})
    assert home_position(named, robot.joints[0]) == pytest.approx(0.3)
    assert home_position(named, robot.joints[1]) == pytest.approx(0.7)
    assert home_position(named, robot.joints[2]) == pytest.approx(-0.2)
    assert home_position(robot, robot.joints[2]) == pytest.approx(0.4)


def test_named_home_is_used_for_home_outside_limits() -> None:
    robot = _chain(1)
    robot = dataclasses.replace(robot, joints=(_revolute("j0", "l0", "l1", 0.5, 2.0),))
    assert [d.data["position"] for d in _found(robot, "J010")] == [0.0]
    inside = dataclasses.replace(robot, home={"j0": 1.0})
    assert _found(inside, "J010") == []
    outside = dataclasses.replace(robot, home={"j0": 2.5})
    (finding,) = _found(outside, "J010")
    assert finding.message.startswith("the home pose puts joint 'j0' at 2.5 rad")
    assert finding.data["nearest"] == 2.0


def test_non_unit_axis_reports_the_normalised_axis() -> None:
    robot = _chain(1)
    robot = dataclasses.replace(robot, joints=(_revolute("j0", "l0", "l1", axis=(0.0, 3.0, 4.0)),))
    (finding,) = _found(robot, "J007")
    assert finding.data["normalized"] == pytest.approx([0.0, 0.6, 0.8])
    assert finding.help == 'write <axis xyz="0 0.6 0.8"/>'
    assert math.isclose(finding.data["length"], 5.0)


def test_rounded_axes_are_unit_enough() -> None:
    robot = _chain(1)
    robot = dataclasses.replace(
        robot, joints=(_revolute("j0", "l0", "l1", axis=(0.0, 0.7071, 0.7071)),)
    )
    assert _found(robot, "J007") == []


def test_mimic_target_missing_suggests_the_near_name() -> None:
    robot = _chain(2)
    robot = dataclasses.replace(
        robot, joints=(robot.joints[0], dataclasses.replace(robot.joints[1], mimic=Mimic("j_0")))
    )
    (finding,) = _found(robot, "J008")
    assert "did you mean 'j0'" in finding.message


def test_a1_calf_joints_start_outside_their_limits() -> None:
    assert ERD is not None
    path = ERD / "a1_description" / "urdf" / "a1.urdf"
    found = [
        d for r in check_file(str(path), CheckOptions(select=("J010",))) for d in r.diagnostics
    ]
    assert {d.element for d in found} == {
        f"joint[{leg}_calf_joint]/limit" for leg in ("FR", "FL", "RR", "RL")
    }
    assert all(d.data["upper"] < 0 and d.data["nearest"] == d.data["upper"] for d in found)


def test_joint_rules_run_on_example_robot_data_without_internal_errors() -> None:
    from tests.conftest import erd_urdfs

    options = CheckOptions(select=("J", "S000"))
    for path in erd_urdfs():
        for report in check_file(path, options):
            assert not [d for d in report.diagnostics if d.code == "S000"], path
