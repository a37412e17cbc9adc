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
from urdftool.parse.srdf import choose_state, read_group_states
from urdftool.pipeline.check import CheckOptions
from urdftool.pipeline.convert import convert_robot, write_conversion
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
    states = read_group_states(ROBOTS / "solo_description/srdf/solo.srdf")
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
