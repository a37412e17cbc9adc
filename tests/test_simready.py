"""Exports that simulate as they are: floor placement, stances from SRDF, contact excludes, actuators.

Every check here loads the written MJCF in MuJoCo and measures after
``mj_forward`` (no stepping) or after a run of a few seconds.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

from tests.conftest import ERD
from urdftool.export import ExportOptions
from urdftool.parse.srdf import read_srdf
from urdftool.pipeline.check import CheckOptions
from urdftool.pipeline.convert import convert_robot, write_conversion
from urdftool.pipeline.home import choose_state, group_states
from urdftool.pipeline.load import load_one

assert ERD is not None
ROBOTS = ERD

SOLO12 = "solo_description/robots/solo12.urdf"
A1 = "a1_description/urdf/a1.urdf"
GO1 = "go1_description/urdf/go1.urdf"
TALOS = "talos_data/robots/talos_reduced.urdf"
PANDA = "panda_description/urdf/panda.urdf"


def export_mjcf(rel: str, folder: Path, **options: object) -> mujoco.MjModel:
    loaded = load_one(str(ROBOTS / rel), CheckOptions())
    assert loaded.robot is not None
    conversion = convert_robot(loaded.robot, "mjcf", folder / "robot.xml",
                               ExportOptions(**options))  # type: ignore[arg-type]
    assert not conversion.refused, [d.message for d in conversion.errors]
    write_conversion(conversion)
    return mujoco.MjModel.from_xml_path(str(folder / "robot.xml"))


def start(model: mujoco.MjModel, key: int | None) -> mujoco.MjData:
    data = mujoco.MjData(model)
    if key is None:
        mujoco.mj_resetData(model, data)
    else:
        mujoco.mj_resetDataKeyframe(model, data, key)
    mujoco.mj_forward(model, data)
    return data


def floor_gap(model: mujoco.MjModel, data: mujoco.MjData) -> float:
    floor = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "floor")
    return min(mujoco.mj_geomDistance(model, data, floor, g, 1.0, None)
               for g in range(model.ngeom) if g != floor and model.geom_contype[g])


def deepest_contact(data: mujoco.MjData) -> float:
    return max((-float(c.dist) for c in data.contact[:data.ncon]), default=0.0)


def test_srdf_group_state_is_the_home_configuration() -> None:
    states = group_states(read_srdf(str(ROBOTS / "solo_description/srdf/solo.srdf")))
    joints = [f"{leg}_{j}" for leg in ("FL", "FR", "HL", "HR") for j in ("HAA", "HFE", "KFE")]
    chosen = choose_state(states, joints)
    assert chosen is not None and chosen.name == "standing"
    assert "root_joint" not in chosen.values  # the 7-value floating entry is skipped
    assert choose_state(states, joints[:4]) is None  # a robot lacking joints gets none
    robot = load_one(str(ROBOTS / SOLO12), CheckOptions()).robot
    assert robot is not None and robot.home is not None and robot.home["FL_KFE"] == -1.6


@pytest.mark.parametrize("rel", [SOLO12, A1, GO1, TALOS])
def test_free_robot_starts_one_millimetre_above_the_floor(rel: str, tmp_path: Path) -> None:
    model = export_mjcf(rel, tmp_path, scene=True, repair_inertia=True)
    assert model.nkey == 1
    for key in (None, 0):
        data = start(model, key)
        assert floor_gap(model, data) == pytest.approx(0.001, abs=2e-5)
        assert deepest_contact(data) <= 0.001
    home = start(model, 0)
    # the keyframe holds the stance: a legged robot's knees are bent
    assert np.ptp(home.qpos[7:]) > 0.5


def test_panda_starts_without_self_penetration(tmp_path: Path) -> None:
    model = export_mjcf(PANDA, tmp_path, scene=True)
    for key in (None, 0):
        assert deepest_contact(start(model, key)) == 0.0
    hand = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "panda_hand")
    link7 = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "panda_link7")
    excluded = {frozenset((int(model.exclude_signature[i]) >> 16, int(model.exclude_signature[i]) & 0xFFFF))
                for i in range(model.nexclude)}
    # the hand is welded to link8, fixed to link7: not MuJoCo parent and child, so excluded
    assert frozenset((link7, hand)) in excluded


def hold(model: mujoco.MjModel, seconds: float) -> tuple[np.ndarray, np.ndarray]:
    """Start at the home keyframe, command it, run; (home qpos, largest deviation per qpos)."""
    data = start(model, 0)
    home = data.qpos.copy()
    for i in range(model.nu):
        data.ctrl[i] = home[model.jnt_qposadr[model.actuator_trnid[i, 0]]]
    worst = np.zeros_like(home)
    for _ in range(int(seconds / model.opt.timestep)):
        mujoco.mj_step(model, data)
        worst = np.maximum(worst, np.abs(data.qpos - home))
    assert np.all(np.isfinite(data.qpos))
    return home, worst


def test_panda_position_actuators_hold_the_home_pose(tmp_path: Path) -> None:
    model = export_mjcf(PANDA, tmp_path, scene=True, actuators="position")
    assert model.nu == 8
    kp = {model.actuator(i).name: float(model.actuator_gainprm[i, 0]) for i in range(model.nu)}
    assert 2000 < kp["panda_joint2"] < 10000  # Menagerie: 4500
    _, worst = hold(model, 5.0)
    assert worst.max() < 0.005


def test_auto_actuators_follow_the_transmission(tmp_path: Path) -> None:
    urdf = tmp_path / "r.urdf"
    box = ('<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" '
           'izz="0.01"/></inertial>')
    joints = "".join(
        f'<link name="l{i}">{box}</link><joint name="j{i}" type="revolute"><parent link="l{i - 1}"/>'
        f'<child link="l{i}"/><origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>'
        f'<limit effort="10" velocity="1" lower="-1" upper="1"/></joint>' for i in (1, 2, 3))
    urdf.write_text(
        f'<robot name="r"><link name="l0">{box}</link>{joints}'
        '<transmission name="t1"><type>transmission_interface/SimpleTransmission</type>'
        '<joint name="j1"><hardwareInterface>hardware_interface/EffortJointInterface</hardwareInterface>'
        '</joint><actuator name="m1"><mechanicalReduction>50</mechanicalReduction>'
        '<motorInertia>0.0001</motorInertia></actuator></transmission>'
        '<ros2_control name="c" type="system"><joint name="j2"><command_interface name="velocity"/>'
        '</joint></ros2_control></robot>')
    loaded = load_one(str(urdf), CheckOptions())
    assert loaded.robot is not None
    conversion = convert_robot(loaded.robot, "mjcf", tmp_path / "r.xml", ExportOptions(actuators="auto"))
    write_conversion(conversion)
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "r.xml"))
    kinds = {model.actuator(i).name: (int(model.actuator_gaintype[i]), int(model.actuator_biastype[i]))
             for i in range(model.nu)}
    assert kinds["j1"] == (0, 0)  # motor
    assert kinds["j2"][1] == 1 and model.actuator_biasprm[1, 1] == 0  # velocity: bias -kv qdot only
    assert kinds["j3"][1] == 1 and model.actuator_biasprm[2, 1] < 0  # position servo
    assert model.dof_armature[0] == pytest.approx(0.0001 * 50**2)
