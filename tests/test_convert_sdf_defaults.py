"""SDFormat's default inertial in exports (sdf-default-inertia, C007) and the verifier on a model
without mass (a static SDF model): new-user report of 2026-11-26, problems 2 and 14."""

from __future__ import annotations

from pathlib import Path

import mujoco
import pytest
from click.testing import CliRunner

import urdftool
from tests.conftest import FIXTURES
from tests.test_rule_fixtures import expected_marks
from urdftool.cli import main
from urdftool.export import ExportOptions
from urdftool.export.mjcf_verify import verify
from urdftool.pipeline.convert import convert_robot
from urdftool.rules import lookup

C007 = FIXTURES / "rules" / "C007"
DOOR = FIXTURES / "newuser" / "static_door.world"


@pytest.mark.parametrize("target", ["mjcf", "pybullet", "urdf"])
def test_bad_fixture_reports_the_default_at_the_link(target: str, tmp_path: Path) -> None:
    path = C007 / "bad.sdf"
    lines, _ = expected_marks(path, "C007")
    robot = urdftool.load(path)
    found = [d for d in convert_robot(robot, target, tmp_path / "out", ExportOptions()).diagnostics
             if d.code == "C007"]
    assert {d.location.line for d in found if d.location} == lines
    assert all(d.name == lookup("C007").name and d.severity.value == "info" for d in found)  # type: ignore[union-attr]
    # what --repair-inertia reports is another matter: C002 never says this
    assert not [d for d in convert_robot(robot, target, tmp_path / "out", ExportOptions()).diagnostics
                if d.code == "C002"]


@pytest.mark.parametrize("target", ["mjcf", "pybullet", "urdf"])
def test_good_fixture_is_quiet(target: str, tmp_path: Path) -> None:
    robot = urdftool.load(C007 / "good.sdf")
    found = convert_robot(robot, target, tmp_path / "out", ExportOptions()).diagnostics
    assert not [d for d in found if d.code == "C007"]


def test_a_static_model_gets_no_invented_mass(tmp_path: Path) -> None:
    """A static model's links never move: MuJoCo gets them without mass, as the source has."""
    text = urdftool.to_mjcf(DOOR, model="door_3d")
    model = mujoco.MjModel.from_xml_string(text)
    assert mujoco.mj_getTotalmass(model) == 0.0
    assert 'mass="1"' not in text


def test_verify_on_a_static_model_passes_and_never_divides_by_zero(tmp_path: Path) -> None:
    out = tmp_path / "door.xml"
    command = ["convert", str(DOOR), "--model", "door_3d", "-o", str(out), "--verify"]
    result = CliRunner().invoke(main, command)
    assert result.exit_code == 0, result.output
    assert "total mass (kg; the source has none)" in result.output
    assert "e+" not in result.output.split("quantity", 1)[1]


def test_verify_compares_a_massless_source_in_kg(tmp_path: Path) -> None:
    """A mass written into a static model is reported as the kilograms it adds, not as 2e+300."""
    out = tmp_path / "door.xml"
    command = ["convert", str(DOOR), "--model", "door_3d", "-o", str(out)]
    assert CliRunner().invoke(main, command).exit_code == 0
    text = out.read_text()
    robot = urdftool.load(DOOR, model="door_3d")
    body = text.index('<body name="link_2"')
    end = text.index(">", body) + 1
    out.write_text(text[:end] + '<inertial pos="0 0 0" mass="2" diaginertia="1 1 1"/>' + text[end:])
    verdict = verify(robot, out, ExportOptions())
    row = next(r for r in verdict.rows if r[0].startswith("total mass"))
    assert row[0] == "total mass (kg; the source has none)" and row[1] == pytest.approx(2.0) and not row[3]
