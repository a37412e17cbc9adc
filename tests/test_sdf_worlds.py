"""SDF worlds and free bodies through convert: which model is exported, and free links as free joints."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from click.testing import CliRunner

from tests.conftest import FIXTURES
from urdftool.cli import main
from urdftool.pipeline.check import CheckOptions, check_file

INERTIAL = ("<inertial><mass>1</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz></inertia>"
            "</inertial>")
WORLD = f"""<sdf version="1.8"><world name="w">
  <model name="ground"><static>true</static><link name="slab"/></model>
  <model name="pair">
    <pose>1 0 0 0 0 0</pose>
    <link name="box">{INERTIAL}
      <collision name="c"><geometry><box><size>0.1 0.1 0.1</size></box></geometry></collision></link>
    <link name="ball"><pose>0 0.5 0.2 0 0 0.3</pose>{INERTIAL}
      <collision name="c"><geometry><sphere><radius>0.05</radius></sphere></geometry></collision></link>
  </model>
</world></sdf>
"""


def run(*args: object) -> tuple[int, str]:
    result = CliRunner().invoke(main, [str(a) for a in args])
    return result.exit_code, result.output + (result.stderr if result.stderr_bytes else "")


def test_a_world_asks_which_model_and_exports_one_or_all(tmp_path: Path) -> None:
    world = tmp_path / "w.sdf"
    world.write_text(WORLD)
    code, output = run("convert", world, "-o", tmp_path / "out.urdf")
    assert code == 2 and "2 models (ground, pair)" in output and "--all-models" in output
    assert not (tmp_path / "out.urdf").exists()
    code, output = run("convert", world, "-o", tmp_path / "out.xml", "--model", "pair")
    assert code == 0, output
    code, output = run("convert", world, "-o", tmp_path / "all.xml", "--all-models")
    assert code == 0, output
    assert (tmp_path / "all_ground.xml").is_file() and (tmp_path / "all_pair.xml").is_file()
    code, output = run("convert", world, "-o", tmp_path / "x.xml", "--model", "nope")
    assert code == 2 and "no model named 'nope'" in output


def test_free_bodies_become_free_joints_in_mjcf_where_the_model_puts_them(tmp_path: Path) -> None:
    import mujoco

    world = tmp_path / "w.sdf"
    world.write_text(WORLD)
    out = tmp_path / "pair.xml"
    code, output = run("convert", world, "-o", out, "--model", "pair")
    assert code == 0, output
    model = mujoco.MjModel.from_xml_path(str(out))
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    mujoco.mj_forward(model, data)
    box, ball = (model.body(name).id for name in ("box", "ball"))
    assert model.body_jntnum[ball] == 1
    assert model.jnt_type[model.body_jntadr[ball]] == mujoco.mjtJoint.mjJNT_FREE
    # The ball sits 0.5 m along y and 0.2 m up from the box, turned 0.3 rad about z, in the model frame.
    np.testing.assert_allclose(data.xpos[ball] - data.xpos[box], [0, 0.5, 0.2], atol=1e-12)
    yaw = np.arctan2(data.xmat[ball].reshape(3, 3)[1, 0], data.xmat[ball].reshape(3, 3)[0, 0])
    assert abs(yaw - 0.3) < 1e-12
    mujoco.mj_step(model, data)
    assert np.isfinite(data.qpos).all()


def test_a_missing_gazebo_model_gets_gazebo_help_once_per_file() -> None:
    # neo_workshop.world: 26 copies of a wall whose model:// folder is not on the search path got
    # ROS package advice (package.xml), 26 times
    path = FIXTURES / "rules" / "M001" / "bad_gazebo_model.world"
    found = {r.robot: d for r in check_file(str(path), CheckOptions(select=("M001",)))
             for d in r.diagnostics}
    first, second = found["wall"], found["wall_clone"]
    assert first.help and second.help
    assert "model.config" in first.help and "GZ_SIM_RESOURCE_PATH" in first.help
    assert "GAZEBO_MODEL_PATH" in first.help and "package.xml" not in first.help
    assert first.help.startswith("2 models of this file use 'urdftool_fixture_missing_wall'")
    assert second.help == ("2 models of this file use 'urdftool_fixture_missing_wall': "
                           "see model 'wall' (line 13)")
