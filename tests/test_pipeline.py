"""One pipeline: the API refuses what convert refuses, and sim loads the bytes convert writes."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

import urdftool
from tests.conftest import ERD, FIXTURES, SEEDS
from urdftool.cli import main
from urdftool.facts.simulation.scene import SimOptions, prepare
from urdftool.pipeline.simulate import ENGINE_EXPORTS, export_for_engine

#: A wheeled robot (free base, massless base_footprint) and a fixed-base arm.
MOBILE = SEEDS / "go_chase_it" / "my_robot" / "urdf" / "my_robot.xacro"
ARM = FIXTURES / "robots" / "two_link_arm.urdf"


def test_to_mjcf_refuses_what_convert_refuses_with_the_same_findings(tmp_path: Path) -> None:
    broken = FIXTURES / "rules" / "S005" / "bad.urdf"  # invalid numbers: structural errors
    result = CliRunner().invoke(main, ["convert", str(broken), "-o", str(tmp_path / "out.xml")])
    assert result.exit_code == 1 and not (tmp_path / "out.xml").exists()
    with pytest.raises(urdftool.ConversionRefused) as refused:
        urdftool.to_mjcf(broken)
    printed = [line for line in result.output.splitlines() if "error[" in line]
    codes = [d.code for d in refused.value.diagnostics]
    assert codes and len(printed) == len(codes)
    assert all(f"error[{d.code} {d.name}] {d.message}" in line
               for d, line in zip(refused.value.diagnostics, printed, strict=True))


@pytest.mark.parametrize("source", [MOBILE, ARM], ids=["mobile", "arm"])
@pytest.mark.parametrize("engine", ["mujoco", "pybullet"])
def test_sim_loads_the_bytes_convert_writes(source: Path, engine: str, tmp_path: Path) -> None:
    robot = urdftool.load(source)
    options = SimOptions(engines=(engine,))
    scene = prepare(robot)
    (tmp_path / "sim").mkdir()
    exported = export_for_engine(robot, engine, tmp_path / "sim", options, scene)
    assert exported.path is not None, exported
    # The command the run names, run for real, writes the same bytes.
    words = exported.command.split()
    assert words[:3] == ["urdftool", "convert", source.name]
    _target, name, _flags = ENGINE_EXPORTS[engine]
    out = tmp_path / "cli" / name
    out.parent.mkdir()
    args = ["convert", str(source), "-o", str(out), *words[5:]]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    sim_files = {p.relative_to(exported.path.parent): p.read_bytes()
                 for p in exported.path.parent.rglob("*") if p.is_file()}
    cli_files = {p.relative_to(out.parent): p.read_bytes() for p in out.parent.rglob("*") if p.is_file()}
    assert sim_files == cli_files
    assert scene.floating is (source == MOBILE)
    summary = [d for d in urdftool.simulate(source, engine=engine, duration=0.2).diagnostics
               if d.code == "R005"]
    assert summary and summary[0].data["summary"]["loaded"] == exported.command


def test_the_pybullet_export_of_a_mobile_robot_is_free_and_keeps_its_mass(tmp_path: Path) -> None:
    """PyBullet welds a massless base to the world: the export roots the robot at base_link."""
    import pybullet

    out = tmp_path / "robot.urdf"
    urdftool.to_urdf(MOBILE, out, flavor="pybullet")
    robot = urdftool.load(MOBILE)
    client = pybullet.connect(pybullet.DIRECT)
    try:
        body = pybullet.loadURDF(str(out), flags=pybullet.URDF_USE_INERTIA_FROM_FILE, physicsClientId=client)
        base_mass = pybullet.getDynamicsInfo(body, -1, physicsClientId=client)[0]
        total = base_mass + sum(pybullet.getDynamicsInfo(body, i, physicsClientId=client)[0]
                                for i in range(pybullet.getNumJoints(body, physicsClientId=client)))
    finally:
        pybullet.disconnect(client)
    assert base_mass > 0
    assert total == pytest.approx(robot.total_mass, rel=1e-9)
    assert ERD is not None


def test_the_reader_records_each_mesh_resolution_and_the_facts_reuse_it() -> None:
    from urdftool.facts.context import CheckContext
    from urdftool.facts.meshes import lookup, mesh_uses
    from urdftool.model import KinematicTree

    robot = urdftool.load(FIXTURES / "rules" / "M002" / "bad.urdf")
    ctx = CheckContext(robot, KinematicTree.of(robot))
    uses = mesh_uses(ctx)
    assert uses and all(use.mesh.resolution is not None for use in uses)
    for use in uses:
        assert lookup(ctx, use) is use.mesh.resolution  # read from the model, not resolved again
        assert use.mesh.resolution.tried or use.mesh.resolution.path
