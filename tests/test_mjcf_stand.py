"""`convert --scene --actuators auto` of six robots, simulated for 5 s in MuJoCo: each starts without
penetration and holds its home pose; Cassie's closed loops stay closed (docs/mjcf.md, "Standing").

One export and 2,500 steps per robot (about 10 s for all six); engine-heavy, so the module is in
tests/conftest.py's SLOW_MODULES.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
import pytest

from tests.conftest import ERD
from urdftool.export import ExportOptions
from urdftool.pipeline.check import CheckOptions
from urdftool.pipeline.convert import convert_robot, write_conversion
from urdftool.pipeline.load import load_one

assert ERD is not None

#: The hold criteria (docs/mjcf.md): deepest contact at t = 0; over 5 s, each servoed joint within
#: JOINT_TOLERANCE of its home value, a free base within BASE_TOLERANCE of its start height and
#: TILT_TOLERANCE of its start orientation; loops within LOOP_GAP and LOOP_ANGLE at every step.
PENETRATION = 0.001
SECONDS = 5.0
JOINT_TOLERANCE = 0.02
BASE_TOLERANCE = 0.02
TILT_TOLERANCE = 0.1  # Cassie rocks up to 0.048 rad on its cylinder (line-contact) feet
LOOP_GAP = 0.001
LOOP_ANGLE = 0.01


@dataclass(frozen=True)
class Case:
    name: str
    rel: str
    repair: bool = False  # Cassie's foot reference links break A + B >= C: --repair-inertia


CASES = [
    Case("panda", "panda_description/urdf/panda.urdf"),
    Case("ur5", "ur_description/urdf/ur5_robot.urdf"),
    Case("solo12", "solo_description/robots/solo12.urdf"),
    Case("go2", "go2_description/urdf/go2.urdf"),
    Case("talos", "talos_data/robots/talos_reduced.urdf"),
    Case("cassie", "cassie_description/robots/cassie.sdf", repair=True),
]


def export(case: Case, folder: Path) -> mujoco.MjModel:
    loaded = load_one(str(ERD / case.rel), CheckOptions())
    assert loaded.robot is not None
    options = ExportOptions(scene=True, actuators="auto", repair_inertia=case.repair)
    conversion = convert_robot(loaded.robot, "mjcf", folder / "robot.xml", options)
    assert not conversion.refused, [d.message for d in conversion.errors]
    write_conversion(conversion)
    return mujoco.MjModel.from_xml_path(str(folder / "robot.xml"))


def loop_error(model: mujoco.MjModel, data: mujoco.MjData) -> tuple[float, float]:
    """Largest gap (m) between the sites of a loop's ``connect``, and largest angle (rad) between a
    hinged cut's axis in its parent and in its child."""
    gap = angle = 0.0
    for e in range(model.neq):
        if model.eq_type[e] != mujoco.mjtEq.mjEQ_CONNECT:
            continue
        gap = max(gap, float(np.linalg.norm(data.site_xpos[model.eq_obj1id[e]]
                                            - data.site_xpos[model.eq_obj2id[e]])))
        name = model.eq(e).name
        if name.endswith("_axis"):
            site = {s: mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, f"{name[:-5]}_{s}")
                    for s in ("parent", "parent_axis", "child", "child_axis")}
            u = data.site_xpos[site["parent_axis"]] - data.site_xpos[site["parent"]]
            v = data.site_xpos[site["child_axis"]] - data.site_xpos[site["child"]]
            cos = float(u @ v / (np.linalg.norm(u) * np.linalg.norm(v)))
            angle = max(angle, float(np.arccos(np.clip(cos, -1.0, 1.0))))
    return gap, angle


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_scene_with_auto_actuators_holds_home_for_five_seconds(case: Case, tmp_path: Path) -> None:
    model = export(case, tmp_path)
    assert model.nkey == 1 and model.nu > 0
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    mujoco.mj_forward(model, data)
    assert max((-float(c.dist) for c in data.contact[:data.ncon]), default=0.0) <= PENETRATION
    home = data.qpos.copy()
    servoed = [int(model.jnt_qposadr[model.actuator_trnid[i, 0]]) for i in range(model.nu)
               if model.actuator_biastype[i] == mujoco.mjtBias.mjBIAS_AFFINE]
    assert servoed, "auto gives these robots position servos"
    # the keyframe commands every servo to its joint's home value: resetting to it is enough
    commanded = [home[int(model.jnt_qposadr[model.actuator_trnid[i, 0]])] for i in range(model.nu)]
    assert np.allclose(data.ctrl, commanded, atol=1e-12)
    free = model.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE
    loops = any(model.eq_type[e] == mujoco.mjtEq.mjEQ_CONNECT for e in range(model.neq))
    joint_dev = base_dev = tilt = gap = angle = 0.0
    if loops:
        gap, angle = loop_error(model, data)
    for _ in range(round(SECONDS / model.opt.timestep)):
        mujoco.mj_step(model, data)
        joint_dev = max(joint_dev, float(np.max(np.abs(data.qpos[servoed] - home[servoed]))))
        if free:
            base_dev = max(base_dev, abs(float(data.qpos[2] - home[2])))
            dot = abs(float(np.dot(data.qpos[3:7], home[3:7])))
            tilt = max(tilt, 2 * float(np.arccos(min(1.0, dot))))
        if loops:
            step_gap, step_angle = loop_error(model, data)
            gap, angle = max(gap, step_gap), max(angle, step_angle)
    assert np.all(np.isfinite(data.qpos))
    assert joint_dev <= JOINT_TOLERANCE, f"{case.name}: a joint moved {joint_dev:.4f} rad from home"
    assert base_dev <= BASE_TOLERANCE, f"{case.name}: the base moved {base_dev:.4f} m in height"
    assert tilt <= TILT_TOLERANCE, f"{case.name}: the base tilted {tilt:.4f} rad"
    assert gap <= LOOP_GAP and angle <= LOOP_ANGLE, f"{case.name}: loops {gap:.5f} m, {angle:.5f} rad"
    if case.name == "cassie":
        # 2 Achilles and 2 knee-spring loops (hinge cut: 2 connects each) + 2 plantar (ball cut)
        names = {model.eq(e).name for e in range(model.neq)}
        assert loops and model.neq == 10 and {f"{side}-knee-spring-joint_axis"
                                              for side in ("left", "right")} <= names


def test_cassie_closes_every_loop_and_keeps_its_knee_spring_sliders(tmp_path: Path) -> None:
    """No loop closure of Cassie is dropped: the knee-spring sliders are tree ``slide`` joints
    (the spanning tree cuts the hinge beside them, docs/sdf.md) and the gearboxes become armature."""
    loaded = load_one(str(ERD / "cassie_description/robots/cassie.sdf"), CheckOptions())
    robot = loaded.robot
    assert robot is not None
    options = ExportOptions(scene=True, actuators="auto", repair_inertia=True)
    conversion = convert_robot(robot, "mjcf", tmp_path / "robot.xml", options)
    closures = {f"joint[{closure.joint.name}]" for closure in robot.loop_closures}
    dropped = [d.message for d in conversion.diagnostics
               if d.code == "C001" and d.data.get("element") in closures and d.severity.value != "info"]
    assert len(closures) == 16 and not dropped, dropped
    write_conversion(conversion)
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "robot.xml"))
    for side in ("left", "right"):
        joint = model.joint(f"{side}-shin-spring-joint")
        assert joint.type == mujoco.mjtJoint.mjJNT_SLIDE
        assert model.body(int(joint.bodyid[0])).name == f"{side}-knee-spring"
        assert model.body(int(model.body(f"{side}-knee-spring").parentid[0])).name == f"{side}-shin"


def test_cassie_gearboxes_become_the_reflected_rotor_inertia(tmp_path: Path) -> None:
    """Cassie's ten SDF gearbox closures (motor rotor to joint output) reach MuJoCo as armature on
    the output joint: the rotor's spin inertia about its hinge divided by the ratio squared."""
    loaded = load_one(str(ERD / "cassie_description/robots/cassie.sdf"), CheckOptions())
    robot = loaded.robot
    assert robot is not None
    options = ExportOptions(scene=True, actuators="auto", repair_inertia=True)
    conversion = convert_robot(robot, "mjcf", tmp_path / "robot.xml", options)
    geared = {d.data["joint"]: d.data["armature"] for d in conversion.diagnostics
              if d.code == "C001" and d.data.get("reason") == "gearbox written as reflected rotor inertia"}
    assert len(geared) == 10
    write_conversion(conversion)
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "robot.xml"))
    rotor = next(j for j in robot.joints if j.name == "left-pitch-ip")
    link = robot.link(rotor.child)
    assert link is not None and link.inertial is not None
    inertial = link.inertial
    axis = np.asarray(rotor.axis) / np.linalg.norm(rotor.axis)
    com = np.asarray(inertial.origin.xyz)
    spin = axis @ inertial.inertia_in_link_frame @ axis + inertial.mass * (com @ com - (axis @ com) ** 2)
    assert geared["left-pitch-op"] == pytest.approx(spin / 0.0625**2, rel=1e-12)
    for name, value in geared.items():
        dof = int(model.jnt_dofadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)])
        assert model.dof_armature[dof] == pytest.approx(value, rel=1e-6), name
