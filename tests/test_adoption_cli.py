"""Command-line behaviour CI gates rely on: did-you-mean for commands and options, ``sim``
failing on a failed verdict, ``urdftool schema`` and the schema shipping in the wheel."""

from __future__ import annotations

import json
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from click.testing import CliRunner

from tests.conftest import FIXTURES, ROOT
from urdftool.cli import main
from urdftool.diagnostics import Diagnostic, FileReport, Report, Severity
from urdftool.facts.simulation.verdict import verdict_failed


def test_unknown_command_suggests_the_nearest() -> None:
    result = CliRunner().invoke(main, ["chek", "robot.urdf"])
    assert result.exit_code == 2
    assert "No such command 'chek'. Did you mean 'check'?" in result.output


def test_unknown_command_far_from_any_has_no_suggestion() -> None:
    result = CliRunner().invoke(main, ["zzzzzz"])
    assert result.exit_code == 2 and "Did you mean" not in result.output


def test_unknown_option_suggests_the_nearest() -> None:
    result = CliRunner().invoke(main, ["check", "--fromat", "json", "x.urdf"])
    assert result.exit_code == 2 and "Did you mean '--format'?" in result.output


def test_schema_command_prints_the_report_schema() -> None:
    result = CliRunner().invoke(main, ["schema"])
    assert result.exit_code == 0
    assert result.output == (ROOT / "schemas" / "report.schema.json").read_text(encoding="utf-8")
    assert json.loads(result.output)["properties"]["schema_version"]


def test_shipped_schema_is_the_documented_one() -> None:
    shipped = ROOT / "urdftool" / "schemas" / "report.schema.json"
    assert shipped.read_bytes() == (ROOT / "schemas" / "report.schema.json").read_bytes()


def test_wheel_ships_the_schema_and_the_licence(tmp_path: Path) -> None:
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(tmp_path), str(ROOT)],
        check=True, capture_output=True, timeout=600,
    )
    (wheel,) = tmp_path.glob("urdftool-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    assert "urdftool/schemas/report.schema.json" in names
    assert any(n.endswith("LICENSE") for n in names)


def _verdict(message: str, verdict: str) -> Report:
    d = Diagnostic("R005", "sim-summary", Severity.INFO, message, data={"verdict": verdict})
    return Report((FileReport("a.urdf", "urdf", "a", (d,)),))


def test_failed_verdict_is_read_from_the_summary() -> None:
    assert verdict_failed(_verdict("MuJoCo: failed (not settled): 1000 steps", "failed"))
    assert not verdict_failed(_verdict("MuJoCo: passed: 1000 steps", "passed"))
    assert not verdict_failed(_verdict("PyBullet: not simulated: PyBullet is not installed", "not simulated"))


@pytest.mark.parametrize("args", [["sim"], ["check", "--sim", "--no-dynamics"]])
def test_a_failed_verdict_exits_1_even_without_errors(
    args: list[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """A verdict that fails on warnings alone: D003's weak arm held at its start pose
    (``sim --hold``) sags; ``check --sim`` has no ``--hold``, so there a closed loop is made to
    count as open (the tolerance below any gap).

    (An unactuated robot sagging or collapsing is an expected verdict, not a failure, and an
    overlap PyBullet does not simulate does not fail it: docs/sim.md.)"""
    if args[0] == "sim":
        robot, engine = FIXTURES / "rules" / "D003" / "bad.urdf", ["pybullet", "--hold", "--duration", "0.5"]
    else:
        monkeypatch.setattr("urdftool.rules.runtime.LOOP_TOLERANCE", -1.0)
        robot, engine = FIXTURES / "robots" / "four_bar.sdf", ["mujoco"]
    result = CliRunner().invoke(main, [*args, str(robot), "--engine", *engine, "--format", "json"])
    report = json.loads(result.stdout)
    assert ": failed (" in result.stderr and "exit 1: " in result.stderr  # why: the summary says 0 errors
    assert report["summary"]["errors"] == 0
    assert any(": failed" in d["message"] for f in report["files"] for d in f["diagnostics"]
               if d["code"] == "R005")
    assert result.exit_code == 1
