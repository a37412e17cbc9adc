"""check --fix / --diff: byte edits in the file the user edits, idempotent, applying with git apply."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest
from click.testing import CliRunner

from tests.conftest import ROOT
from urdftool.cli import main
from urdftool.diagnostics import Applicability
from urdftool.pipeline.check import CheckOptions, check_files
from urdftool.pipeline.fix import apply_edits, fix_files
from urdftool.pipeline.fixes import repair_number

FIX = ROOT / "fixtures" / "fix"
OPTIONS = CheckOptions(rule_options={"dynamics": False})
SAFE = {"S005", "S007", "S008", "S009", "J007"}
UNSAFE = {"J004", "I003"}


def _copy(tmp_path: Path, name: str) -> Path:
    target = tmp_path / name
    shutil.copyfile(FIX / name, target)
    return target


def _codes(path: Path) -> list[str]:
    return [d.code for d in check_files([str(path)], OPTIONS).diagnostics]


@pytest.mark.parametrize(("value", "expected"), [
    ("2,", "2"), ("0 0.07, 0", "0 0.07 0"), ("0 -1.57. 0", "0 -1.57 0"), ("2.O", "2.0"),
    ("1..5", None), ("NaN", None), ("abc", None), ("1,5", None),
])
def test_number_repairs_only_where_the_intent_is_clear(value: str, expected: str | None) -> None:
    assert repair_number(value) == expected


def test_fix_mends_every_fixable_rule_and_leaves_other_bytes(tmp_path: Path) -> None:
    path = _copy(tmp_path, "arm.urdf")
    before = path.read_bytes()
    assert set(_codes(path)) >= SAFE | UNSAFE
    result = fix_files([str(path)], OPTIONS, unsafe=True)
    after = path.read_bytes()
    assert not (SAFE | UNSAFE) & set(_codes(path))
    # byte-identical outside the edited spans: the recorded edits turn the old bytes into the new
    edits = [e for d in result.fixed for e in d.fix.edits]  # type: ignore[union-attr]
    assert result.rounds == 1
    assert apply_edits(before, edits)[0] == after
    assert b"<!-- invalid-number: a stray comma -->" in after
    assert b"<axis xyz='0 0 1'/>" in after  # quoting kept
    assert b'<limit lower="-1.5" upper="1.5"\n           effort="40"' in after  # layout kept
    # a second run changes nothing
    again = fix_files([str(path)], OPTIONS, unsafe=True)
    assert not again.changes and path.read_bytes() == after


def test_safe_fixes_leave_unsafe_ones(tmp_path: Path) -> None:
    path = _copy(tmp_path, "arm.urdf")
    fix_files([str(path)], OPTIONS)
    codes = set(_codes(path))
    assert not SAFE & codes
    assert codes >= UNSAFE


def test_line_endings_are_kept(tmp_path: Path) -> None:
    path = tmp_path / "crlf.urdf"
    path.write_bytes((FIX / "arm.urdf").read_bytes().replace(b"\n", b"\r\n"))
    fix_files([str(path)], OPTIONS)
    data = path.read_bytes()
    assert data.count(b"\r\n") == data.count(b"\n")
    assert b"<axis xyz='0 0 1'/>\r\n" in data


def test_xacro_literal_fixed_in_the_macro_expression_display_only(tmp_path: Path) -> None:
    path = _copy(tmp_path, "fingers.urdf.xacro")
    report = check_files([str(path)], OPTIONS)
    axis = next(d for d in report.diagnostics if d.code == "J007")
    assert axis.fix is not None and axis.fix.applicability is Applicability.DISPLAY_ONLY
    assert "expression" in axis.fix.message
    fix_files([str(path)], OPTIONS, unsafe=True)
    text = path.read_text()
    assert '<limit lower="-1" upper="1"' in text  # the macro body, once for both fingers
    assert '<mass value="0.1"/>' in text
    assert 'axis="${tilt}"' in text and 'value="0 0 2"' in text  # the expression is left alone
    assert set(_codes(path)) & {"S005", "S009"} == set()


def test_nothing_is_written_when_the_result_would_not_parse(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = _copy(tmp_path, "arm.urdf")
    before = path.read_bytes()
    monkeypatch.setattr("urdftool.pipeline.fix.apply_edits",
                        lambda data, edits: (data + b"<broken", list(edits)))
    result = fix_files([str(path)], OPTIONS)
    assert result.refused == [str(path)]
    assert path.read_bytes() == before


def test_diff_applies_with_git_apply(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    _copy(tmp_path, "arm.urdf")
    _copy(tmp_path, "fingers.urdf.xacro")
    monkeypatch.chdir(tmp_path)
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    result = CliRunner().invoke(main, ["check", ".", "--diff", "--no-dynamics"])
    assert result.exit_code == 1, result.output
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before  # --diff writes nothing
    assert result.stdout.startswith("--- arm.urdf\n+++ arm.urdf\n")
    (tmp_path / "fix.diff").write_text(result.stdout)
    subprocess.run(["git", "init", "-q", "."], check=True)
    subprocess.run(["git", "apply", "-p0", "fix.diff"], check=True)
    applied = (tmp_path / "arm.urdf").read_bytes()
    expected = tmp_path / "expected"
    expected.mkdir()
    shutil.copyfile(FIX / "arm.urdf", expected / "arm.urdf")
    fix_files([str(expected / "arm.urdf")], OPTIONS)
    assert applied == (expected / "arm.urdf").read_bytes()


def test_fix_only_reports_what_it_fixed(tmp_path: Path) -> None:
    path = _copy(tmp_path, "arm.urdf")
    result = CliRunner().invoke(main, ["check", str(path), "--fix-only", "--no-dynamics"])
    assert result.exit_code == 0, result.output
    assert "S009 [unknown-attribute] rename attribute 'xzy' to 'xyz'" in result.stdout
    again = CliRunner().invoke(main, ["check", str(path), "--fix", "--no-dynamics"])
    assert "fixed 0 finding(s)" in again.stderr


def test_several_findings_on_one_tag_each_get_their_own_fix(tmp_path: Path) -> None:
    """A CAD export misspells the same attributes on every joint: the tag is read once for all
    the findings on it, and each finding's fix still renames its own attribute."""
    path = tmp_path / "arm.urdf"
    joints = "".join(
        f'  <joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/>\n'
        f'    <limit lowr="-1" uper="1" effort="1" velocity="1"/></joint>\n' for i in range(3))
    links = "".join(f'  <link name="l{i}"/>\n' for i in range(4))
    path.write_text(f'<?xml version="1.0"?>\n<!-- provenance: hand-written for urdftool -->\n'
                    f'<robot name="arm">\n{links}{joints}</robot>\n')
    [report] = check_files([str(path)], CheckOptions(select=("S009",))).files
    fixes = {(d.location.line, d.fix.edits[0].content) for d in report.diagnostics
             if d.location and d.fix}
    assert fixes == {(line, name) for line in (9, 11, 13) for name in ("lower", "upper")}
    fix_files([str(path)], CheckOptions(select=("S009",)))
    assert path.read_text().count('<limit lower="-1" upper="1"') == 3
