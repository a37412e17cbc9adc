"""Pinocchio built from the typed model agrees with Pinocchio's own URDF parser.

Pinocchio's parser is an independent reading of the same file: link frames and
the joint-space mass matrix must agree at random configurations, with joints
matched by name (continuous joints are one angle here, cos/sin there).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from tests.conftest import ERD
from urdftool.backends.pinocchio import FREE_FLYER, build_model
from urdftool.parse import read

ROBOTS = [
    ("ur_description/urdf/ur5_robot.urdf", False),
    ("solo_description/robots/solo12.urdf", True),
    ("panda_description/urdf/panda.urdf", False),
    ("double_pendulum_description/urdf/double_pendulum_continuous.urdf", False),
]


def _reference(path: str, free_flyer: bool):  # type: ignore[no-untyped-def]
    if free_flyer:
        return pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer())
    return pin.buildModelFromUrdf(path)


@pytest.mark.parametrize(("relative", "free_flyer"), ROBOTS, ids=[r for r, _ in ROBOTS])
def test_matches_pinocchios_urdf_parser(relative: str, free_flyer: bool) -> None:
    assert ERD is not None
    path = str(ERD / relative)
    robot = read(path)[0].robot
    assert robot is not None
    ours = build_model(robot, free_flyer=free_flyer)
    ref = _reference(path, free_flyer)
    ours_data, ref_data = ours.model.createData(), ref.createData()
    rng = np.random.default_rng(1)
    for _ in range(5):
        q = np.zeros(ours.model.nq)
        qref = pin.neutral(ref)
        v_map = np.zeros((ref.nv, ours.model.nv))
        for name, jid in ours.joints.items():
            ref_name = "root_joint" if name == FREE_FLYER else name
            rj = ref.joints[ref.getJointId(ref_name)]
            oj = ours.model.joints[jid]
            if oj.nq == 7:
                quat = rng.normal(size=4)
                quat /= np.linalg.norm(quat)
                value = np.concatenate([rng.uniform(-1, 1, 3), quat])
                q[oj.idx_q:oj.idx_q + 7] = value
                qref[rj.idx_q:rj.idx_q + 7] = value
                v_map[rj.idx_v:rj.idx_v + 6, oj.idx_v:oj.idx_v + 6] = np.eye(6)
                continue
            angle = rng.uniform(-1.5, 1.5)
            q[oj.idx_q] = angle
            if rj.nq == 2:  # RevoluteUnbounded: cos, sin
                qref[rj.idx_q:rj.idx_q + 2] = (np.cos(angle), np.sin(angle))
            else:
                qref[rj.idx_q] = angle
            v_map[rj.idx_v, oj.idx_v] = 1.0
        pin.framesForwardKinematics(ours.model, ours_data, q)
        pin.framesForwardKinematics(ref, ref_data, qref)
        for link, fid in ours.link_frames.items():
            if not ref.existFrame(link):
                continue
            expected = ref_data.oMf[ref.getFrameId(link)]
            np.testing.assert_allclose(ours_data.oMf[fid].homogeneous, expected.homogeneous, atol=1e-12)
        m_ours = np.triu(pin.crba(ours.model, ours_data, q))
        m_ref = np.triu(pin.crba(ref, ref_data, qref))
        m_ours = m_ours + np.triu(m_ours, 1).T
        m_ref = m_ref + np.triu(m_ref, 1).T
        np.testing.assert_allclose(m_ours, v_map.T @ m_ref @ v_map, atol=1e-12 * np.abs(m_ref).max())


def test_every_link_is_a_body_frame_and_mimics_are_listed() -> None:
    assert ERD is not None
    path = ERD / "panda_description" / "urdf" / "panda.urdf"
    robot = read(path)[0].robot
    assert robot is not None
    ours = build_model(robot)
    assert set(ours.link_frames) == {link.name for link in robot.links}
    assert all(ours.model.frames[f].type == pin.FrameType.BODY for f in ours.link_frames.values())
    mimic = [j for j in robot.joints if j.mimic is not None]
    assert {j.name for j in mimic} == set(ours.mimics)
    g, independent = ours.mimic_projection()
    assert g.shape == (ours.model.nv, ours.model.nv - len(mimic)) and len(independent) == g.shape[1]
    for follower, (leader, multiplier, _) in ours.mimics.items():
        column = independent.index(ours.idx_v(leader))
        assert g[ours.idx_v(follower), column] == multiplier


def test_planar_joint_moves_in_the_plane_normal_to_its_axis(tmp_path) -> None:  # type: ignore[no-untyped-def]
    path = tmp_path / "planar.urdf"
    inertial = (
        '<inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>'
    )
    path.write_text(
        f'<robot name="p"><link name="a">{inertial}</link><link name="b">{inertial}</link>'
        '<joint name="j" type="planar"><parent link="a"/><child link="b"/><axis xyz="1 0 0"/></joint></robot>'
    )
    robot = read(path)[0].robot
    assert robot is not None
    ours = build_model(robot)
    data = ours.model.createData()
    theta = 0.7
    q = np.array([0.3, -0.2, np.cos(theta), np.sin(theta)])
    pin.framesForwardKinematics(ours.model, data, q)
    placement = data.oMf[ours.link_frames["b"]]
    assert placement.translation[0] == pytest.approx(0.0)  # no motion along the normal
    assert np.linalg.norm(placement.translation) == pytest.approx(np.hypot(0.3, 0.2))
    np.testing.assert_allclose(placement.rotation @ [1, 0, 0], [1, 0, 0], atol=1e-15)
