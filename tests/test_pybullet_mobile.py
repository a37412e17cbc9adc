"""Mobile robots whose root link is massless (``base_footprint``) fall onto the floor and rest in
PyBullet, with their total mass exact, and ``sim`` loads the very file ``convert`` writes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import urdftool
from tests.conftest import ERD, PBD, ROOT, SEEDS
from urdftool.backends.pybullet import captured_output, import_pybullet
from urdftool.cli import main
from urdftool.facts.simulation.scene import SimOptions, prepare
from urdftool.pipeline.simulate import export_for_engine

assert ERD is not None and PBD is not None
TURTLEBOT3 = SEEDS / "turtlebot3" / "turtlebot3_description" / "urdf"
MOBILE = {
    "turtlebot3_burger": TURTLEBOT3 / "turtlebot3_burger.urdf",
    "turtlebot3_waffle": TURTLEBOT3 / "turtlebot3_waffle.urdf",
    "turtlebot3_waffle_pi": TURTLEBOT3 / "turtlebot3_waffle_pi.urdf",
    "husky": PBD / "husky" / "husky.urdf",
    "a1": ERD / "a1_description" / "urdf" / "a1.urdf",
    "simple_humanoid": ERD / "simple_humanoid_description" / "urdf" / "simple_humanoid.urdf",
    "diffbot": ROOT / "urdftool" / "examples" / "diffbot" / "urdf" / "diffbot.urdf.xacro",
}
#: Seconds of free fall and settling, and the drop height (m) of the lowest collision point.
SETTLE, DROP = 3.0, 0.05


def source(name: str, tmp_path: Path) -> Path:
    """The robot's file; pybullet_data's Husky carries ``$(optenv ...)`` defaults, so it is read
    as xacro (a copy beside a link to its meshes)."""
    path = MOBILE[name]
    if name != "husky":
        return path
    folder = tmp_path / "husky"
    folder.mkdir()
    (folder / "meshes").symlink_to(path.parent / "meshes")
    copy = folder / "husky.urdf.xacro"
    copy.write_bytes(path.read_bytes())
    return copy


def drop(path: Path) -> dict[str, float]:
    """Load *path* with its lowest collision point :data:`DROP` above a floor, as a user gets it
    (PyBullet's default motors hold every joint's velocity at 0), and let it fall for :data:`SETTLE` s."""
    p = import_pybullet()
    with captured_output():
        client = p.connect(p.DIRECT)
    try:
        p.setGravity(0, 0, -9.81, physicsClientId=client)
        floor = p.createMultiBody(0, p.createCollisionShape(p.GEOM_PLANE, physicsClientId=client),
                                  physicsClientId=client)
        with captured_output():
            body = p.loadURDF(str(path), flags=p.URDF_USE_INERTIA_FROM_FILE, physicsClientId=client)
        links = list(range(-1, p.getNumJoints(body, physicsClientId=client)))
        masses = [p.getDynamicsInfo(body, i, physicsClientId=client)[0] for i in links]
        colliding = [i for i in links if p.getCollisionShapeData(body, i, physicsClientId=client)]
        lowest = min(p.getAABB(body, i, physicsClientId=client)[0][2] for i in colliding)
        position, orientation = p.getBasePositionAndOrientation(body, physicsClientId=client)
        start = (position[0], position[1], position[2] - lowest + DROP)
        p.resetBasePositionAndOrientation(body, start, orientation, physicsClientId=client)
        heights = []
        for _ in range(round(SETTLE * 240)):
            p.stepSimulation(physicsClientId=client)
            heights.append(p.getBasePositionAndOrientation(body, physicsClientId=client)[0][2])
        end = p.getBasePositionAndOrientation(body, physicsClientId=client)[0]
        velocity = p.getBaseVelocity(body, physicsClientId=client)[0]
        touching = len(p.getContactPoints(bodyA=body, bodyB=floor, physicsClientId=client))
    finally:
        p.disconnect(physicsClientId=client)
    return {"base_mass": masses[0], "mass": float(sum(masses)), "fell": start[2] - end[2],
            "vertical_speed": abs(velocity[2]), "settling": float(np.ptp(heights[-120:])),
            "contacts": touching}


@pytest.mark.parametrize("name", [
    pytest.param(name, marks=pytest.mark.slow) if name == "a1" else name  # a1: DAE meshes, ~5 s
    for name in MOBILE
])
def test_massless_root_robot_falls_and_rests_in_pybullet(name: str, tmp_path: Path) -> None:
    src = source(name, tmp_path)
    robot = urdftool.load(src)
    root = robot.links[0]
    assert root.inertial is None or root.inertial.mass == 0  # base_footprint: PyBullet would weld it
    out = tmp_path / "cli" / "robot.urdf"
    result = CliRunner().invoke(main, ["convert", str(src), "-o", str(out), "--to", "pybullet"])
    assert result.exit_code == 0, result.output
    state = drop(out)
    assert state["base_mass"] > 0
    assert state["mass"] == pytest.approx(robot.total_mass, rel=1e-9, abs=0)
    assert state["fell"] > 0.8 * DROP  # free: it fell (a welded base stays where it was put)
    # ... and it rests on the floor: touching it, its height steady over the last 0.5 s
    assert state["contacts"] > 0 and state["vertical_speed"] < 0.01 and state["settling"] < 0.001
    # `sim` writes (and loads) the same bytes as `convert`.
    scene = prepare(robot)
    assert scene.floating
    (tmp_path / "sim").mkdir()
    options = SimOptions(engines=("pybullet",))
    exported = export_for_engine(robot, "pybullet", tmp_path / "sim", options, scene)
    assert exported.path is not None and exported.path.read_bytes() == out.read_bytes()
    assert exported.command == f"urdftool convert {src.name} -o robot.urdf --to pybullet"
