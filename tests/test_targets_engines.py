"""The consumer tables cannot drift from the engines: every prediction is measured in the engine.

For MuJoCo, PyBullet and Pinocchio (Drake: tests/test_targets_drake.py), each
fixture of fixtures/targets/ is checked with ``--target`` that engine, loaded in the engine itself, and every
finding's predicted effect measured: the mass a link gets, which bodies exist
after fusing, whether a ball inside a concave collision mesh collides with its
hull, the inertia PyBullet computes, welded joints, the configuration size.
"""

from __future__ import annotations

import contextlib
import os
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import pytest

from tests.conftest import FIXTURES
from urdftool.pipeline.check import CheckOptions, check_file

pytestmark = pytest.mark.slow

TARGET_FIXTURES = sorted((FIXTURES / "targets").glob("*.urdf"))


def findings(path: Path, target: str) -> list[Any]:
    options = CheckOptions(select=("T",), rule_options={"targets": (target,)})
    return [d for r in check_file(str(path), options) for d in r.diagnostics]


@contextlib.contextmanager
def inside(folder: Path):  # type: ignore[no-untyped-def]
    before = os.getcwd()
    os.chdir(folder)
    try:
        yield
    finally:
        os.chdir(before)


# -- MuJoCo ------------------------------------------------------------------------------


def _mujoco_ball_collides(path: Path) -> bool:
    """A 1 cm ball placed in the open volume of the fixture's concave collision mesh: does it touch?"""
    mujoco = pytest.importorskip("mujoco")
    with inside(path.parent):
        model = mujoco.MjModel.from_xml_path(path.name)
        saved = Path("/tmp") / f"urdftool-targets-{os.getpid()}.xml"
        mujoco.mj_saveLastXML(str(saved), model)
    root = ET.parse(saved).getroot()
    saved.unlink()
    compiler = root.find("compiler")
    if compiler is not None:
        compiler.set("meshdir", str(path.parent))
    assert any(g.get("mesh") for g in root.iter("geom")), "no mesh geom"
    body = root.find("worldbody")
    assert body is not None
    ball = ET.SubElement(body, "body", name="probe", pos=_probe_position(path))
    ET.SubElement(ball, "freejoint")
    ET.SubElement(ball, "geom", type="sphere", size="0.01", mass="0.01")
    model = mujoco.MjModel.from_xml_string(ET.tostring(root, encoding="unicode"))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    probe = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "probe")
    return any(
        probe in (model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]) for c in data.contact[: data.ncon]
    )


def _probe_position(path: Path) -> str:
    """Inside the open volume of the concave fixtures, well clear of the mesh surface."""
    return {"tray.urdf": "0 0 0.05", "bowl.urdf": "0 0 0.06"}[path.name]


def test_every_engine_effect_is_measured() -> None:
    """The fixtures exercise each kind of prediction in each engine (no vacuous pass)."""
    engines = ("mujoco", "pybullet", "pinocchio", "drake")  # drake: tests/test_targets_drake.py
    codes = {t: {d.code for p in TARGET_FIXTURES for d in findings(p, t)} for t in engines}
    assert codes == {
        "mujoco": {"T001", "T002", "T003"},
        "pybullet": {"T001", "T003", "T004", "T005", "T010"},
        "pinocchio": {"T001", "T002", "T004", "T005"},
        "drake": {"T001", "T003", "T004", "T005", "T006"},
    }


def _hull_volume(mesh: Path) -> float:
    import trimesh

    return float(trimesh.load(str(mesh), force="mesh").convex_hull.volume)


@pytest.mark.parametrize("path", TARGET_FIXTURES, ids=lambda p: p.stem)
def test_mujoco_predictions(path: Path) -> None:
    mujoco = pytest.importorskip("mujoco")
    with inside(path.parent):
        model = mujoco.MjModel.from_xml_path(path.name)
    bodies = {mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, i) for i in range(model.nbody)}
    for d in findings(path, "mujoco"):
        if d.code == "T001" and d.data.get("open_mesh"):
            # an open collision mesh: MuJoCo's mass is not the closed part's (1000 kg/m³ x hull)
            body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, d.data["link"])
            closed = 1000.0 * _hull_volume(path.parent / d.data["open_mesh"])
            assert abs(model.body_mass[body] - closed) > 0.05 * closed, d.message
        elif d.code == "T001":
            body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, d.data["link"])
            assert model.body_mass[body] == pytest.approx(d.data["mass"], rel=1e-6), d.message
        elif d.code == "T002":
            assert d.data["child"] not in bodies, d.message
        elif d.code == "T003":
            assert _mujoco_ball_collides(path), d.message
        else:
            pytest.fail(f"no engine measure for {d.code}: {d.message}")
    # Links the table says MuJoCo keeps are bodies of their own.
    fused = {d.data["child"] for d in findings(path, "mujoco") if d.code == "T002"}
    for joint in ET.parse(path).getroot().iter("joint"):
        if joint.get("type") != "fixed":
            child = joint.find("child")
            assert child is not None and child.get("link") in bodies - fused


# -- PyBullet ----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def bullet():  # type: ignore[no-untyped-def]
    pybullet = pytest.importorskip("pybullet")
    client = pybullet.connect(pybullet.DIRECT)
    yield pybullet, client
    pybullet.disconnect(client)


def _bullet_links(p: Any, body: int, client: int) -> dict[str, int]:
    links = {p.getBodyInfo(body, physicsClientId=client)[0].decode(): -1}
    for index in range(p.getNumJoints(body, physicsClientId=client)):
        links[p.getJointInfo(body, index, physicsClientId=client)[12].decode()] = index
    return links


@pytest.mark.parametrize("path", TARGET_FIXTURES, ids=lambda p: p.stem)
def test_pybullet_predictions(path: Path, bullet: Any) -> None:
    p, client = bullet
    with inside(path.parent):
        body = p.loadURDF(path.name, physicsClientId=client)
    links = _bullet_links(p, body, client)
    count = p.getNumJoints(body, physicsClientId=client)
    infos = [p.getJointInfo(body, i, physicsClientId=client) for i in range(count)]
    joints = {info[1].decode(): info[2] for info in infos}
    for d in findings(path, "pybullet"):
        if d.code == "T001":
            info = p.getDynamicsInfo(body, links[d.data["link"]], physicsClientId=client)
            assert info[0] == pytest.approx(d.data["mass"]), d.message
        elif d.code == "T010":
            info = p.getDynamicsInfo(body, links[d.data["link"]], physicsClientId=client)
            predicted = sorted(d.data["predicted"])
            measured = sorted(info[2])
            if max(predicted) == 0:
                assert max(measured) < 1e-5, d.message
            else:
                assert measured == pytest.approx(predicted, rel=0.3), d.message
        elif d.code == "T005":
            assert joints[d.data["joint"]] == p.JOINT_FIXED, d.message
        elif d.code == "T004":
            # no constraint couples the follower: driving the leader leaves it where it was
            assert p.getNumConstraints(physicsClientId=client) == 0, d.message
        elif d.code == "T003":
            assert _bullet_ball_penetrates(p, client, path), d.message
        else:
            pytest.fail(f"no engine measure for {d.code}: {d.message}")
    p.removeBody(body, physicsClientId=client)


def _bullet_ball_penetrates(p: Any, client: int, path: Path) -> bool:
    with inside(path.parent):
        body = p.loadURDF(path.name, useFixedBase=True, physicsClientId=client)
    x, y, z = (float(v) for v in _probe_position(path).split())
    shape = p.createCollisionShape(p.GEOM_SPHERE, radius=0.01, physicsClientId=client)
    ball = p.createMultiBody(0.01, shape, basePosition=(x, y, z), physicsClientId=client)
    p.performCollisionDetection(physicsClientId=client)
    hit = bool(p.getContactPoints(ball, body, physicsClientId=client))
    p.removeBody(ball, physicsClientId=client)
    p.removeBody(body, physicsClientId=client)
    return hit


def test_pybullet_keeps_multi_object_obj_open(bullet: Any) -> None:
    """The table says PyBullet hulls each OBJ object: the tray stays open (no T003 for it)."""
    p, client = bullet
    path = FIXTURES / "targets" / "tray.urdf"
    assert not [d for d in findings(path, "pybullet") if d.code == "T003"]
    assert not _bullet_ball_penetrates(p, client, path)
    assert _mujoco_ball_collides(path)


# -- Pinocchio ---------------------------------------------------------------------------


@pytest.mark.parametrize("path", TARGET_FIXTURES, ids=lambda p: p.stem)
def test_pinocchio_predictions(path: Path) -> None:
    pin = pytest.importorskip("pinocchio")
    model = pin.buildModelFromUrdf(str(path))
    urdf = ET.parse(path).getroot()
    child_joint = {
        j.find("child").get("link"): j.get("name")  # type: ignore[union-attr]
        for j in urdf.iter("joint")
    }
    for d in findings(path, "pinocchio"):
        if d.code == "T001":
            joint = model.getJointId(child_joint[d.data["link"]])
            assert model.inertias[joint].mass == 0.0, d.message
        elif d.code == "T002":
            assert model.existFrame(d.data["child"]), d.message
            assert not model.existJointName(d.data["joint"]), d.message
        elif d.code == "T004":
            follower = model.getJointId(d.data["joint"])
            assert follower < model.njoints and model.joints[follower].nq == 1, d.message
            with_mimic = pin.buildModelFromUrdf(str(path), mimic=True)
            assert with_mimic.nq == model.nq - 1, d.message
        elif d.code == "T005":
            joint = model.joints[model.getJointId(d.data["joint"])]
            assert (joint.nq, joint.nv) == (2, 1), d.message
        else:
            pytest.fail(f"no engine measure for {d.code}: {d.message}")
