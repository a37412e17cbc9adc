"""A five-follower mimic linkage (TIAGo Pro's gripper) holds within 0.01 rad in PyBullet and MuJoCo.

The gripper is cut out of example-robot-data's ``tiago_pro.urdf`` at test time
(the links below ``gripper_left_base_link``): one leader, ``gripper_left_finger_joint``,
and five followers with multipliers ±1, two of them carried by other followers.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import mujoco
import numpy as np
import pytest

import urdftool
from tests.conftest import ERD
from urdftool.backends.pybullet import captured_output, couple_mimics, import_pybullet
from urdftool.export import ExportOptions, export_model
from urdftool.model import KinematicTree, Robot

LEADER = "gripper_left_finger_joint"
#: The leader's target (rad): from 0 through most of its range (0..0.80) and back, smoothly.
SWEEP = 3.0  # rad/s


def target(t: float) -> float:
    return 0.35 - 0.35 * math.cos(SWEEP * t)


@pytest.fixture(scope="module")
def gripper() -> Robot:
    assert ERD is not None
    robot = urdftool.load(ERD / "tiago_pro_description" / "robots" / "tiago_pro.urdf")
    keep = {link.name for _, link, _ in KinematicTree.of(robot).walk("gripper_left_base_link")}
    joints = tuple(j for j in robot.joints if j.parent in keep and j.child in keep)
    cut = dataclasses.replace(robot, links=tuple(link for link in robot.links if link.name in keep),
                              joints=joints, extensions=())
    assert [j.name for j in joints if j.mimic] and sum(j.mimic is not None for j in joints) == 5
    assert {j.mimic.joint for j in joints if j.mimic} == {LEADER}
    return cut


def followers(robot: Robot) -> list[tuple[str, str, float, float]]:
    return [(j.name, j.mimic.joint, j.mimic.multiplier, j.mimic.offset) for j in robot.joints if j.mimic]


def write(robot: Robot, target_name: str, out: Path, options: ExportOptions) -> Path:
    result = export_model(robot, target_name, out, options)
    assert not result.failed, [d.message for d in result.diagnostics if d.severity.value == "error"]
    for rel, data in result.files.items():
        (out.parent / rel).parent.mkdir(parents=True, exist_ok=True)
        (out.parent / rel).write_bytes(data)
    return out


def pybullet_sweep(path: Path, robot: Robot, coupled: bool) -> tuple[float, float]:
    """Drive the leader through :func:`target` for 2 s under gravity; (leader's range, worst error)."""
    p = import_pybullet()
    with captured_output():
        client = p.connect(p.DIRECT)
    try:
        body = p.loadURDF(str(path), flags=p.URDF_USE_INERTIA_FROM_FILE, useFixedBase=True,
                          physicsClientId=client)
        p.setGravity(0, 0, -9.81, physicsClientId=client)
        index = {p.getJointInfo(body, i, physicsClientId=client)[1].decode(): i
                 for i in range(p.getNumJoints(body, physicsClientId=client))}
        p.setJointMotorControlArray(body, list(index.values()), p.VELOCITY_CONTROL,
                                    forces=[0.0] * len(index), physicsClientId=client)
        pairs = followers(robot)
        if coupled:
            assert len(couple_mimics(p, client, body, pairs)) == 5
        else:  # the recipe as it was: PyBullet's default error reduction and solver iterations
            for follower, leader, multiplier, _ in pairs:
                c = p.createConstraint(body, index[follower], body, index[leader], jointType=p.JOINT_GEAR,
                                       jointAxis=[0, 0, 1], parentFramePosition=[0, 0, 0],
                                       childFramePosition=[0, 0, 0], physicsClientId=client)
                p.changeConstraint(c, gearRatio=-multiplier, maxForce=100, physicsClientId=client)
        dt = p.getPhysicsEngineParameters(physicsClientId=client)["fixedTimeStep"]
        worst, leader_seen = 0.0, []
        for step in range(int(2.0 / dt)):
            p.setJointMotorControl2(body, index[LEADER], p.POSITION_CONTROL, targetPosition=target(step * dt),
                                    force=0.1, physicsClientId=client)  # the leader's effort limit
            p.stepSimulation(physicsClientId=client)
            q = {name: p.getJointState(body, i, physicsClientId=client)[0] for name, i in index.items()}
            leader_seen.append(q[LEADER])
            worst = max(worst, max(abs(q[f] - (m * q[lead] + o)) for f, lead, m, o in pairs))
    finally:
        p.disconnect(physicsClientId=client)
    return float(np.ptp(leader_seen)), worst


def test_pybullet_gear_constraints_hold_five_followers(gripper: Robot, tmp_path: Path) -> None:
    path = write(gripper, "pybullet", tmp_path / "gripper.urdf", ExportOptions())
    swept, worst = pybullet_sweep(path, gripper, coupled=True)
    assert swept > 0.6  # the leader really moves through its range
    assert worst < 0.01
    # PyBullet's defaults (no error reduction, 50 iterations) drift by tenths of a radian.
    _, drift = pybullet_sweep(path, gripper, coupled=False)
    assert drift > 0.1


def test_pybullet_recipe_names_the_settings_that_hold(gripper: Robot, tmp_path: Path) -> None:
    result = export_model(gripper, "pybullet", tmp_path / "g.urdf", ExportOptions())
    helps = [d.help or "" for d in result.diagnostics if d.data.get("reason") == "mimic"]
    assert len(helps) == 5
    assert all("erp=1" in h and "numSolverIterations=200" in h and "relativePositionTarget" in h
               for h in helps)


def test_mujoco_equalities_hold_five_followers(gripper: Robot, tmp_path: Path) -> None:
    path = write(gripper, "mjcf", tmp_path / "gripper.xml", ExportOptions(actuators="position"))
    model = mujoco.MjModel.from_xml_path(str(path))
    assert model.neq == 5 and model.nu == 1
    # A servo about twice as firm as the exported one (kp from the 0.1 N·m effort), damped by the
    # exporter's own rule kv = max(2·sqrt(kp·I), kp·dt), so that the leader sweeps its range
    # under gravity: the point is what the followers do. (MuJoCo cannot make an equality stiffer
    # than a 2-step time constant, so a much firmer servo on these 10 g fingers outruns any
    # coupling: kp = 5 lags by 0.09 rad.)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    mass_matrix = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, mass_matrix)
    dof = int(model.jnt_dofadr[model.actuator_trnid[0, 0]])
    kp = 1.0
    kv = max(2 * math.sqrt(kp * mass_matrix[dof, dof]), kp * model.opt.timestep)
    model.actuator_gainprm[0, 0], model.actuator_biasprm[0, 1:3] = kp, (-kp, -kv)
    model.actuator_forcerange[0] = (-1.0, 1.0)
    data = mujoco.MjData(model)
    address = {model.joint(i).name: int(model.jnt_qposadr[i]) for i in range(model.njnt)}
    pairs = followers(gripper)
    worst, leader_seen = 0.0, []
    for step in range(int(2.0 / model.opt.timestep)):
        data.ctrl[0] = target(step * model.opt.timestep)
        mujoco.mj_step(model, data)
        q = {name: data.qpos[a] for name, a in address.items()}
        leader_seen.append(q[LEADER])
        worst = max(worst, max(abs(q[f] - (m * q[lead] + o)) for f, lead, m, o in pairs))
    assert np.ptp(leader_seen) > 0.6
    assert worst < 0.01


def test_sim_reports_the_linkage_holding_in_both_engines(gripper: Robot) -> None:
    """``urdftool sim``: the unactuated gripper, started half open, falls shut under gravity (onto
    its joint limits), its followers with it."""
    half_open = dataclasses.replace(gripper, home={LEADER: 0.5})
    report = urdftool.simulate(half_open, engine="all", duration=1.0)
    runs = {d.data["summary"]["engine"]: d.data["summary"] for d in report.diagnostics
            if d.code == "R005"}
    assert set(runs) == {"mujoco", "pybullet"}
    for engine, run in runs.items():
        assert run["ran"] and run["finite"], engine
        assert run["max_mimic_error"] < 0.01, (engine, run["worst_mimic_joint"], run["max_mimic_error"])
        assert run["max_joint_speed"] > 0.5, engine  # the linkage did move


def test_couple_mimics_keeps_the_offset(tmp_path: Path) -> None:
    inertial = ('<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" '
                'izz="0.01"/></inertial>')
    joints = "".join(
        f'<joint name="j{i}" type="revolute"><parent link="base"/><child link="l{i}"/>'
        f'<origin xyz="0 {0.3 * i} 0"/><axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="5" '
        f'velocity="2"/>{extra}</joint>'
        for i, extra in ((1, ""), (2, '<mimic joint="j1" multiplier="0.5" offset="0.2"/>')))
    src = tmp_path / "pair.urdf"
    src.write_text(f'<robot name="pair"><link name="base">{inertial}</link><link name="l1">{inertial}</link>'
                   f'<link name="l2">{inertial}</link>{joints}</robot>')
    robot = urdftool.load(src)
    path = write(robot, "pybullet", tmp_path / "out" / "pair.urdf", ExportOptions())
    p = import_pybullet()
    with captured_output():
        client = p.connect(p.DIRECT)
    try:
        body = p.loadURDF(str(path), flags=p.URDF_USE_INERTIA_FROM_FILE, useFixedBase=True,
                          physicsClientId=client)
        p.setJointMotorControlArray(body, [0, 1], p.VELOCITY_CONTROL, forces=[0.0, 0.0],
                                    physicsClientId=client)
        assert len(couple_mimics(p, client, body, followers(robot))) == 1
        for _ in range(240):
            p.setJointMotorControl2(body, 0, p.POSITION_CONTROL, targetPosition=0.8, force=5,
                                    physicsClientId=client)
            p.stepSimulation(physicsClientId=client)
        leader, follower = (p.getJointState(body, i, physicsClientId=client)[0] for i in (0, 1))
    finally:
        p.disconnect(physicsClientId=client)
    assert leader == pytest.approx(0.8, abs=0.01)
    assert follower == pytest.approx(0.5 * leader + 0.2, abs=1e-3)
