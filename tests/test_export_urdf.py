"""SDF (and any model) → URDF: faithful, refused with reasons where URDF cannot hold the model."""

from __future__ import annotations

import glob
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import urdftool
from tests.conftest import ERD, FIXTURES, PBD
from urdftool.cli import main
from urdftool.model import KinematicTree
from urdftool.parse import read

PYBULLET_SDFS = sorted(glob.glob(str(PBD / "**" / "*.sdf"), recursive=True)) if PBD else []
CASSIE = ERD / "cassie_description" / "robots" / "cassie.sdf" if ERD else None


#: pybullet_data SDF files that break SDFormat's naming rules (sdf-name-collision, S106):
#: kiva_shelf repeats a collision name within a link.
SPEC_INVALID = {"kiva_shelf/model.sdf"}
#: models that repeat the name of a model before them in their world (kuka_iiwa/model2.sdf's
#: second lbr_iiwa): the finding is the repeating model's, and its export is refused with it
REPEATED_MODELS = {("kuka_iiwa/model2.sdf", 1)}


@pytest.mark.parametrize("path", PYBULLET_SDFS, ids=lambda p: str(Path(p).relative_to(PBD)))
def test_sdf_to_urdf_keeps_link_poses_and_inertias(path: str, tmp_path: Path) -> None:
    if str(Path(path).relative_to(PBD)) in SPEC_INVALID:
        # libsdformat refuses these (duplicate names); the export refuses them with that finding.
        with pytest.raises(urdftool.ConversionRefused) as refused:
            urdftool.to_urdf(path)
        assert {d.code for d in refused.value.diagnostics} == {"S106"}
        return
    for index, loaded in enumerate(read(path)):
        source = loaded.robot
        out = tmp_path / f"m{index}.urdf"
        if (str(Path(path).relative_to(PBD)), index) in REPEATED_MODELS:
            with pytest.raises(urdftool.ConversionRefused) as refused:
                urdftool.to_urdf(source, out)
            assert {d.code for d in refused.value.diagnostics} == {"S106"}
            continue
        urdftool.to_urdf(source, out)
        back = read(str(out))[0].robot
        assert back is not None
        assert not [d for d in back.diagnostics if d.severity.value == "error"]
        tree, tree_back = KinematicTree.of(source), KinematicTree.of(back)
        q = {j.name: 0.3 for j in tree.joints_in_order if j.dof == 1}
        poses, poses_back = tree.forward_kinematics(q), tree_back.forward_kinematics(q)
        for link, pose in poses.items():
            np.testing.assert_allclose(poses_back[link], pose, atol=1e-9, rtol=0, err_msg=link)
        for link in source.links:
            if link.inertial is not None:
                other = back.link(link.name).inertial
                assert other.mass == link.inertial.mass
                np.testing.assert_allclose(other.inertia_in_link_frame, link.inertial.inertia_in_link_frame,
                                           atol=1e-12)


def test_loops_and_ball_joints_are_refused_with_locations() -> None:
    with pytest.raises(urdftool.ConversionRefused) as caught:
        urdftool.to_urdf(CASSIE)
    diagnostics = caught.value.diagnostics
    reasons = {d.data["reason"] for d in diagnostics}
    assert reasons == {"closed chain", "joint type"}
    assert all(d.location and d.location.line and d.location.path.endswith("cassie.sdf") for d in diagnostics)


def test_cli_refuses_four_bar_and_writes_nothing(tmp_path: Path) -> None:
    out = tmp_path / "four_bar.urdf"
    result = CliRunner().invoke(main, ["convert", str(FIXTURES / "robots" / "four_bar.sdf"), "-o", str(out)])
    assert result.exit_code == 1
    assert "coupler_to_rocker" in result.output and "closes a kinematic loop" in result.output
    assert not out.exists()


def test_frames_become_fixed_links_and_sdf_extras_go_to_gazebo_blocks(tmp_path: Path) -> None:
    text = urdftool.to_urdf(FIXTURES / "robots" / "sdf" / "nested_degrees.sdf")
    assert '<link name="gripper::tcp"/>' in text
    assert '<joint name="gripper::tcp_frame" type="fixed">' in text
    shelf = tmp_path / "shelf.sdf"
    shelf.write_text(
        '<sdf version="1.6"><model name="shelf"><static>true</static><link name="board">'
        '<inertial><mass>2</mass><inertia><ixx>0.1</ixx><iyy>0.1</iyy><izz>0.1</izz></inertia></inertial>'
        '<collision name="c"><geometry><box><size>1 0.3 0.02</size></box></geometry></collision>'
        "</link></model></sdf>"
    )
    text = urdftool.to_urdf(shelf)
    assert "urdftool-src" not in text
    assert '<joint name="world_to_' in text  # a static model is welded to the world


def test_urdf_export_is_deterministic_and_rereads_identically(tmp_path: Path) -> None:
    source = FIXTURES / "robots" / "two_link_arm.urdf"
    first = urdftool.to_urdf(source)
    assert first == urdftool.to_urdf(source)
    again = tmp_path / "again.urdf"
    again.write_text(first)
    assert urdftool.to_urdf(again) == first
    original, reread = read(str(source))[0].robot, read(str(again))[0].robot
    assert (original.links, original.joints, original.materials) == (
        reread.links,
        reread.joints,
        reread.materials,
    )


def test_cli_convert_sdf_to_urdf_and_never_over_the_input(tmp_path: Path) -> None:
    source = str(PBD / "kuka_iiwa" / "model.sdf")
    out = tmp_path / "kuka.urdf"
    result = CliRunner().invoke(main, ["convert", source, "-o", str(out)])
    assert result.exit_code == 0, result.output
    before = out.read_bytes()
    result = CliRunner().invoke(main, ["convert", source, "-o", str(out)])
    assert result.exit_code == 0 and out.read_bytes() == before
    copied = tmp_path / "in.urdf"
    copied.write_bytes(before)
    result = CliRunner().invoke(main, ["convert", str(copied), "-o", str(copied)])
    assert result.exit_code == 2


def _check_urdf() -> tuple[str, dict[str, str]]:
    import os
    import sys

    for entry in sys.path:
        prefix = Path(entry) / "cmeel.prefix"
        if (prefix / "bin" / "check_urdf").exists():
            return str(prefix / "bin" / "check_urdf"), dict(os.environ, LD_LIBRARY_PATH=str(prefix / "lib"))
    raise AssertionError("check_urdf comes with Pinocchio's cmeel-urdfdom, a test dependency")


SDF_SOURCES = [
    *[p for p in PYBULLET_SDFS if str(Path(p).relative_to(PBD)) not in SPEC_INVALID],
    *sorted(str(p) for p in (FIXTURES / "robots" / "sdf").glob("*.sdf")),
]


@pytest.mark.parametrize("path", SDF_SOURCES, ids=lambda p: Path(p).name)
def test_sdf_to_urdf_output_passes_urdfdom_check_urdf(path: str, tmp_path: Path) -> None:
    """SDF's unlimited effort and velocity get finite stand-ins, so urdfdom accepts every output."""
    import subprocess

    binary, env = _check_urdf()
    for index, loaded in enumerate(read(path)):
        if (loaded.robot is None or not loaded.robot.links
                or (str(Path(path).relative_to(PBD)) if PBD and path.startswith(str(PBD)) else path, index)
                in REPEATED_MODELS):
            continue
        out = tmp_path / f"m{index}.urdf"
        urdftool.to_urdf(loaded.robot, out)
        proc = subprocess.run([binary, str(out)], capture_output=True, text=True, env=env, timeout=60)
        assert proc.returncode == 0, proc.stdout + proc.stderr
        back = read(str(out))[0].robot
        assert back is not None
        assert not [d for d in back.diagnostics if d.severity.value == "error"]
        assert not [d for d in urdftool.check(out, select=["J"]).errors]
