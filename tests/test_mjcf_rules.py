"""The conversion rules (C001-C005) on their fixtures, through the MJCF exporter.

``check`` cannot trigger them (they describe what an export loses or changes), so
each bad fixture is exported (C005: exported, written and verified with MuJoCo)
and the findings must sit exactly on the lines marked ``<!-- expect: CODE -->``;
the good fixture must export without that code.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.conftest import FIXTURES
from tests.test_rule_fixtures import expected_marks
from urdftool.export import ExportOptions
from urdftool.export.mjcf import export
from urdftool.export.mjcf_verify import verify
from urdftool.parse import read
from urdftool.rules import lookup

RULES = FIXTURES / "rules"
#: code -> options the export runs with (C002 is what --repair-inertia reports)
OPTIONS = {
    "C001": ExportOptions(),
    "C002": ExportOptions(repair_inertia=True),
    "C003": ExportOptions(),
    "C004": ExportOptions(),
    "C005": ExportOptions(),
}


def findings(path: Path, code: str, tmp_path: Path) -> list:
    robot = read(path)[0].robot
    assert robot is not None
    out = tmp_path / "robot.xml"
    result = export(robot, out, OPTIONS[code])
    found = [d for d in result.diagnostics if d.code == code]
    if code == "C005" and not result.failed:
        for rel, data in result.files.items():
            (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
            (tmp_path / rel).write_bytes(data)
        found += [d for d in verify(robot, out, OPTIONS[code]).diagnostics if d.code == code]
    return found


@pytest.mark.parametrize("code", sorted(OPTIONS))
def test_bad_fixture_fires_on_marked_lines(code: str, tmp_path: Path) -> None:
    path = RULES / code / "bad.urdf"
    lines, _ = expected_marks(path, code)
    assert lines, f"{path} marks no line"
    found = findings(path, code, tmp_path)
    got = {d.location.line for d in found if d.location and Path(d.location.path).resolve() == path.resolve()}
    assert got == lines, "\n".join(f"{d.location}: {d.message}" for d in found)
    assert all(d.name == lookup(code).name for d in found)  # type: ignore[union-attr]


@pytest.mark.parametrize("code", sorted(OPTIONS))
def test_good_fixture_is_quiet(code: str, tmp_path: Path) -> None:
    found = findings(RULES / code / "good.urdf", code, tmp_path)
    assert not found, "\n".join(f"{d.location}: {d.message}" for d in found)


def test_repair_reports_numbers_before_and_after(tmp_path: Path) -> None:
    found = findings(RULES / "C002" / "bad.urdf", "C002", tmp_path)
    forearm = next(d for d in found if d.data["link"] == "forearm")
    before, after = forearm.data["before"], forearm.data["after"]
    assert before["inertia"][2][2] == 0.3 and after["inertia"][2][2] < 0.3
    assert after["inertia"][0][0] + after["inertia"][1][1] >= after["inertia"][2][2]
    camera = next(d for d in found if d.data["link"] == "camera")
    assert camera.data["before"]["mass"] == 0.0 and camera.data["after"]["mass"] > 0


def test_transmission_is_carried_with_actuators(tmp_path: Path) -> None:
    robot = read(RULES / "C001" / "bad.urdf")[0].robot
    assert robot is not None
    result = export(robot, tmp_path / "r.xml", ExportOptions(actuators="motor"))
    messages = [d.message for d in result.diagnostics if d.code == "C001"]
    assert len(messages) == 1 and "plugin" in messages[0]
