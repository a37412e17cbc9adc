"""The smoke simulation: command line, Python API, determinism, the seed systems, loops."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from tests.conftest import ERD, FIXTURES, SEEDS
from urdftool import load, simulate
from urdftool.cli import main
from urdftool.diagnostics import Report
from urdftool.facts.simulation.scene import SimOptions, prepare
from urdftool.model import KinematicTree
from urdftool.physics.mobility import reroot_massless_base
from urdftool.pipeline.simulate import simulator as run_engines

RULES = FIXTURES / "rules"
ARM = FIXTURES / "robots" / "two_link_arm.urdf"


def summaries(report: Report) -> dict[str, dict]:
    return {d.data["engine"]: d.data["summary"] for d in report.diagnostics if d.code == "R005"}


def test_sim_command_gives_a_verdict_per_engine() -> None:
    result = CliRunner().invoke(main, ["sim", str(ARM), "--format", "json"])
    assert result.exit_code == 0, result.output
    diagnostics = json.loads(result.output)["files"][0]["diagnostics"]
    verdicts = {d["data"]["engine"]: d["message"] for d in diagnostics if d["code"] == "R005"}
    assert set(verdicts) == {"mujoco", "pybullet"}
    assert all(": passed:" in message for message in verdicts.values())
    summary = next(d["data"]["summary"] for d in diagnostics if d["code"] == "R005")
    for key in (
        "max_joint_speed",
        "energy_drift",
        "final_base_displacement",
        "penetration_depth",
        "wall_time",
    ):
        assert key in summary


def test_sim_command_fails_on_an_unstable_robot() -> None:
    result = CliRunner().invoke(main, ["sim", str(RULES / "R001" / "bad.urdf"), "--engine", "pybullet"])
    assert result.exit_code == 1 and "R001 sim-unstable" in result.output


def test_sim_command_usage_errors_exit_2(tmp_path: Path) -> None:
    assert CliRunner().invoke(main, ["sim", str(tmp_path / "missing.urdf")]).exit_code == 2
    assert CliRunner().invoke(main, ["sim", str(ARM), "--engine", "gazebo"]).exit_code == 2
    assert CliRunner().invoke(main, ["sim", str(ARM), "--duration", "0"]).exit_code == 2


def test_check_sim_adds_the_runtime_verdicts() -> None:
    plain = CliRunner().invoke(main, ["check", str(ARM), "--format", "json"])
    with_sim = CliRunner().invoke(
        main, ["check", str(ARM), "--sim", "--engine", "mujoco", "--format", "json"]
    )
    codes = [d["code"] for f in json.loads(with_sim.output)["files"] for d in f["diagnostics"]]
    assert "R005" in codes and "R005" not in plain.output


def test_same_input_same_numbers() -> None:
    first = summaries(simulate(RULES / "R003" / "bad.urdf"))
    second = summaries(simulate(RULES / "R003" / "bad.urdf"))
    for engine in first:
        first[engine].pop("wall_time")
        second[engine].pop("wall_time")
    assert first == second


def test_exporter_refusal_is_reported_instead_of_a_verdict() -> None:
    report = simulate(RULES / "D004" / "bad.urdf")
    codes = [d.code for d in report.diagnostics]
    assert "C003" in codes and not report.ok
    assert all("not simulated" in d.message for d in report.diagnostics if d.code == "R005")


def test_repair_inertia_lets_the_model_run() -> None:
    report = simulate(RULES / "D004" / "bad.urdf", repair_inertia=True, engine="mujoco")
    assert summaries(report)["mujoco"]["ran"]


def test_hold_keeps_a_strong_arm_still_and_lets_a_weak_one_sag() -> None:
    # D003 says the 10 N·m shoulder cannot hold its 5 kg link; held by PD clipped at 10 N·m it falls.
    weak = summaries(simulate(RULES / "D003" / "bad.urdf", hold=True, engine="mujoco"))["mujoco"]
    strong = summaries(simulate(RULES / "D003" / "good.urdf", hold=True, engine="mujoco"))["mujoco"]
    assert weak["max_joint_speed"] > 1.0
    assert strong["max_joint_speed"] < 0.5


def test_floating_robot_is_dropped_from_just_above_the_ground() -> None:
    result = run_engines(load(RULES / "R003" / "good.urdf"), SimOptions(duration=0.5))
    for run in result.runs:
        assert run.ran and run.base_displacement < 0.02, run.summary()


def test_massless_footprint_is_rerooted_for_pybullet() -> None:
    robot = load(SEEDS / "go_chase_it" / "my_robot" / "urdf" / "my_robot.xacro")
    scene = prepare(robot)
    rerooted = reroot_massless_base(robot, scene.tree)
    assert scene.floating
    root = robot.link(scene.tree.root or "")
    if root is not None and (root.inertial is None or root.inertial.mass == 0):
        # The old root stays as a fixed child: same links, same total mass, a new root.
        new_tree = KinematicTree.of(rerooted)
        assert {link.name for link in rerooted.links} == {link.name for link in robot.links}
        assert new_tree.root != scene.tree.root and rerooted.total_mass == robot.total_mass
        old = new_tree.forward_kinematics()
        before = scene.tree.forward_kinematics()
        for name in before:  # every frame keeps its place relative to the others
            relative_before = np.linalg.inv(before[new_tree.root]) @ before[name]
            assert np.allclose(old[name], relative_before, atol=1e-12)
    else:
        assert rerooted is robot


def test_sdf_loops_simulate_in_mujoco() -> None:
    report = simulate(FIXTURES / "robots" / "four_bar.sdf", engine="all", duration=0.5)
    runs = summaries(report)
    assert runs["mujoco"]["ran"] and runs["mujoco"]["finite"]
    assert not runs["pybullet"]["ran"]  # PyBullet's URDF cannot hold a closed chain
    # the loop closure's gap is measured in the engine over the whole run, and stays closed
    assert 0.0 <= runs["mujoco"]["max_loop_gap"] < 1e-4, runs["mujoco"]
    verdict = next(d.message for d in report.diagnostics if d.code == "R005" and "MuJoCo" in d.message)
    assert verdict.startswith("MuJoCo: passed") and "loop gap" in verdict, verdict


def test_a_loop_that_opens_fails_the_verdict() -> None:
    from urdftool.facts.simulation.record import EngineRun
    from urdftool.rules.runtime import LOOP_TOLERANCE, _verdict

    robot = load(FIXTURES / "robots" / "four_bar.sdf")
    run = EngineRun("mujoco", timestep=0.002, steps=1000, energy_scale=1.0)
    run.loop_gap = 0.5 * LOOP_TOLERANCE
    assert _verdict(robot, run, floating=False, hold=False).startswith("passed")
    run.loop_gap = 5 * LOOP_TOLERANCE
    verdict = _verdict(robot, run, floating=False, hold=False)
    assert verdict.startswith("failed (loops open)") and "loop gap 5.00 mm" in verdict, verdict


#: The seed robots the issue names, with their file and xacro arguments.
SEED_ROBOTS = {
    "minimal one-DOF robot": "learning_ros/minimal_robot_description/minimal_robot_description.urdf",
    "mobot": "learning_ros/mobot_urdf/urdf/mobot_links.xacro",
    "mobot with arm": "learning_ros/mobot_urdf/urdf/mobot_w_arm.xacro",
    "rrbot": "gazebo_ros_demos/rrbot_description/urdf/rrbot.xacro",
    "my_robot": "go_chase_it/my_robot/urdf/my_robot.xacro",
    "m_robot": "hyundai_ngv/m_robot_description/urdf/m_robot.xacro",
}


@pytest.mark.parametrize("name", sorted(SEED_ROBOTS))
def test_seed_robot_gets_a_verdict_from_both_engines(name: str) -> None:
    path = SEEDS / SEED_ROBOTS[name]
    assert path.is_file(), path
    runs = summaries(simulate(path, package_paths=[SEEDS], duration=1.0))
    assert set(runs) == {"mujoco", "pybullet"}
    assert all(run["ran"] for run in runs.values()), runs


def test_seed_sensor_links_without_mass_do_not_destabilise_m_robot() -> None:
    # The static rules report m_robot's camera and lidar links as massless; they are welded
    # to the chassis, so the simulation carries them and stays stable.
    report = simulate(SEEDS / SEED_ROBOTS["m_robot"], package_paths=[SEEDS], duration=1.0)
    assert not [d for d in report.diagnostics if d.code == "R001"]


def test_api_rejects_an_unknown_engine() -> None:
    with pytest.raises(ValueError):
        simulate(ARM, engine="gazebo")


def test_api_on_a_loaded_robot() -> None:
    assert ERD is not None
    robot = load(ERD / "double_pendulum_description" / "urdf" / "double_pendulum.urdf")
    runs = summaries(simulate(robot, engine="mujoco", duration=0.5))
    assert runs["mujoco"]["ran"] and runs["mujoco"]["max_joint_speed"] > 0


def test_unactuated_sag_is_expected_and_held_sag_fails() -> None:
    # the 5 kg link on a 10 N·m shoulder (D003): without actuators it falls, which is expected
    free = simulate(RULES / "D003" / "bad.urdf", engine="mujoco")
    verdicts = [d for d in free.diagnostics if d.code == "R005"]
    assert [d.data["verdict"] for d in verdicts] == ["passed"]
    assert "expected without actuators: the arm sags" in verdicts[0].message
    assert all(d.severity.value != "warning" for d in free.diagnostics if d.code in ("R003", "R004"))
    result = CliRunner().invoke(main, ["sim", str(RULES / "D003" / "bad.urdf"), "--engine", "mujoco"])
    assert result.exit_code == 0, result.output
