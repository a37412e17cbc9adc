"""The command line through click's CliRunner: check, info, rule; formats and exit codes."""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner, Result

from tests.conftest import FIXTURES, ROOT, SEEDS
from urdftool.cli import main

ARM = FIXTURES / "robots" / "two_link_arm.urdf"
NUMBERS = FIXTURES / "rules" / "S005" / "bad.urdf"  # four invalid-number errors
ATTRIBUTES = FIXTURES / "rules" / "S009" / "bad.urdf"  # two unknown-attribute warnings


def run(*args: str | Path) -> Result:
    result = CliRunner().invoke(main, [str(a) for a in args])
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(
        result.exception
    )
    assert "Traceback" not in result.output
    return result


def json_report(*args: str | Path) -> dict[str, Any]:
    result = run("check", "--format", "json", *args)
    assert result.exit_code in (0, 1), result.output
    return json.loads(result.output)


def codes(report: dict[str, Any]) -> list[str]:
    return [d["code"] for f in report["files"] for d in f["diagnostics"]]


# -- check: exit codes --------------------------------------------------------------------


def test_clean_robot_exits_0() -> None:
    result = run("check", "--select", "S,X", ARM)
    assert result.exit_code == 0, result.output
    assert result.output.strip().endswith("1 file checked: 0 error(s), 0 warning(s), 0 info")


def test_errors_exit_1() -> None:
    assert run("check", NUMBERS).exit_code == 1


def test_warnings_fail_only_with_strict() -> None:
    assert run("check", "--select", "S", ATTRIBUTES).exit_code == 0
    assert run("check", "--select", "S", "--strict", ATTRIBUTES).exit_code == 1


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["check", "no/such/robot.urdf"], "no such file"),
        (["check", "README.md"], "unknown format"),
        (["check", "--select", "Q999", str(ARM)], "matches no rule"),
        (["check", "--ignore", "not-a-rule-name", str(ARM)], "matches no rule"),
        (["check", "--format", "yaml", str(ARM)], "yaml"),
        (["check", "--package", "no_equals_sign", str(ARM)], "NAME=DIR"),
        (["check"], "PATHS"),
        (["info", "no/such/robot.urdf"], "no such file"),
        (["rule", "Z999"], "no rule"),
        (["rule", "not-a-rule"], "no rule"),
    ],
    ids=[
        "missing-file",
        "unknown-format",
        "unknown-select",
        "unknown-ignore",
        "unknown-output-format",
        "bad-package",
        "no-paths",
        "info-missing-file",
        "rule-unknown-code",
        "rule-unknown-name",
    ],
)
def test_usage_errors_exit_2(
    args: list[str], fragment: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(ROOT)
    result = run(*args)
    assert result.exit_code == 2, result.output
    assert fragment.lower() in result.output.lower()


def test_directory_without_robots_exits_2(tmp_path: Path) -> None:
    (tmp_path / "notes.txt").write_text("no robots here", encoding="utf-8")
    result = run("check", tmp_path)
    assert result.exit_code == 2 and "no robot descriptions" in result.output


# -- check: selection ---------------------------------------------------------------------


@pytest.mark.parametrize(
    "selector, expected",
    [
        ("S005", {"S005"}),
        ("invalid-number", {"S005"}),
        ("S00", {"S005"}),
        ("S", {"S005"}),
        ("X", set()),
        ("S005,X", {"S005"}),
    ],
)
def test_select(selector: str, expected: set[str]) -> None:
    assert set(codes(json_report("--select", selector, NUMBERS))) == expected


@pytest.mark.parametrize("selector", ["S005", "invalid-number", "S00", "S"])
def test_ignore(selector: str) -> None:
    assert "S005" in codes(json_report(NUMBERS))
    assert "S005" not in codes(json_report("--ignore", selector, NUMBERS))


def test_ignored_errors_no_longer_fail() -> None:
    assert run("check", "--select", "S", "--ignore", "invalid-number", NUMBERS).exit_code == 0


def test_most_specific_selector_wins() -> None:
    """--select S --ignore S0 --select S005: the exact code beats the longer prefix."""
    found = set(
        codes(
            json_report("--select", "S", "--ignore", "S0", "--select", "S005", FIXTURES / "rules")
        )
    )
    assert {c for c in found if c.startswith("S0")} == {"S005"}
    assert not {c for c in found if not c.startswith("S")}


# -- check: text format -------------------------------------------------------------------


def test_text_format_is_compiler_style(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    result = run("check", "fixtures/rules/S005/bad.urdf")
    lines = result.output.splitlines()
    head = (
        "fixtures/rules/S005/bad.urdf:19:13: error[S005 invalid-number] "
        "joint[shoulder]/origin: xyz=\"0 0.07, 0\" is not a number ('0.07,')"
    )
    at = lines.index(head)
    assert (
        lines[at + 1]
        == '   19 |     <origin xyz="0 0.07, 0" rpy="0 -1.57. 0"/> <!-- expect: S005 -->'
    )
    assert lines[at + 2] == "      |             ^"
    assert lines[at + 3] == "  help: did you mean 0.07? (stray ',')"
    assert lines[-1] == "1 file checked: 4 error(s), 0 warning(s), 0 info"


def test_quiet_prints_errors_only() -> None:
    loud = run("check", "--select", "S", ATTRIBUTES).output
    quiet = run("check", "--select", "S", "-q", ATTRIBUTES).output
    assert "unknown-attribute" in loud and "unknown-attribute" not in quiet
    assert "2 warning(s)" in quiet


# -- check: JSON, directories, jobs, output -----------------------------------------------


def test_json_report_shape() -> None:
    report = json_report(NUMBERS)
    assert report["schema_version"] == 1 and report["tool"]["name"] == "urdftool"
    (file_report,) = report["files"]
    assert file_report["format"] == "urdf" and file_report["robot"] == "two_link_arm"
    first = file_report["diagnostics"][0]
    assert first["location"] == {"path": str(NUMBERS), "line": 6, "column": 13}
    assert first["element"] == "link[base]/inertial/mass" and first["data"]["value"] == "2.O"
    assert report["summary"]["errors"] == sum(1 for c in codes(report) if c == "S005")


def test_directory_is_walked_recursively() -> None:
    report = json_report("--select", "S,X", FIXTURES / "rules")
    checked = {Path(f["path"]).relative_to(FIXTURES / "rules").as_posix() for f in report["files"]}
    assert {"S001/bad.urdf", "S005/good.urdf", "X005/bad.urdf.xacro"} <= checked
    # the moved-include fixture's wheel.xacro is a fragment: read through its includers only
    assert "X003/urdf/wheel.xacro" not in checked


def test_several_paths_in_order() -> None:
    report = json_report(ARM, NUMBERS)
    assert [f["path"] for f in report["files"]] == [str(ARM), str(NUMBERS)]


def test_parallel_jobs_give_the_same_report(tmp_path: Path) -> None:
    # Deep enough that the fixture packages inside stay out of sibling tests' ancestor scans.
    copy = tmp_path / "a" / "b" / "rules"
    shutil.copytree(FIXTURES / "rules", copy)
    one = run("check", "--format", "json", "--select", "S,X", "-j", "1", copy)
    two = run("check", "--format", "json", "--select", "S,X", "-j", "2", copy)
    assert one.exit_code == two.exit_code == 1
    assert one.output == two.output


def test_output_file_is_written_atomically_and_identically(tmp_path: Path) -> None:
    out = tmp_path / "reports" / "report.json"
    result = run("check", "--format", "json", "-o", out, NUMBERS)
    assert result.exit_code == 1 and result.output == ""
    first = out.read_bytes()
    assert first == run("check", "--format", "json", NUMBERS).output.encode("utf-8")
    assert run("check", "--format", "json", "-o", out, NUMBERS).exit_code == 1
    assert out.read_bytes() == first
    assert sorted(p.name for p in out.parent.iterdir()) == [
        "report.json"
    ]  # no temporary left behind


def test_output_never_replaces_an_input(tmp_path: Path) -> None:
    robot = tmp_path / "arm.urdf"
    shutil.copy(ARM, robot)
    before = robot.read_bytes()
    result = run("check", "-o", robot, robot)
    assert result.exit_code == 2 and "input" in result.output
    assert robot.read_bytes() == before


def test_xacro_options_reach_check() -> None:
    fixture = FIXTURES / "rules" / "X002" / "good.urdf.xacro"
    assert run("check", "--select", "X", fixture).exit_code == 0
    elsewhere = FIXTURES / "rules" / "X002"
    result = run(
        "check", "--select", "X", "--package", f"x002_cart_description={elsewhere}", fixture
    )
    assert result.exit_code == 0


# -- info ---------------------------------------------------------------------------------


def test_info_text() -> None:
    result = run("info", ARM)
    assert result.exit_code == 0
    lines = result.output.splitlines()
    assert lines[0].split() == ["robot:", "two_link_arm"]
    assert "joints:      2 (2 revolute)" in lines
    assert "DOF:         2" in lines and "total mass:  4 kg" in lines
    assert lines[-3:] == [
        "  base [2 kg]",
        "    upper_arm [1 kg]  <- shoulder (revolute)",
        "      forearm [1 kg]  <- elbow (revolute)",
    ]


def test_info_json() -> None:
    result = run("info", "--format", "json", ARM)
    assert result.exit_code == 0
    summary = json.loads(result.output)
    assert summary["robot"] == "two_link_arm" and summary["root"] == "base"
    assert summary["links"] == 3 and summary["joints"] == 2 and summary["dof"] == 2
    assert summary["joints_by_type"] == {"revolute": 2}
    assert summary["total_mass"] == pytest.approx(4.0)
    assert [(row["depth"], row["link"], row["joint"]) for row in summary["tree"]] == [
        (0, "base", None),
        (1, "upper_arm", "shoulder"),
        (2, "forearm", "elbow"),
    ]


def test_info_of_a_seed_xacro() -> None:
    result = run(
        "info", "--format", "json", SEEDS / "gazebo_ros_demos/rrbot_description/urdf/rrbot.xacro"
    )
    assert result.exit_code == 0
    assert json.loads(result.output)["robot"] == "rrbot"


def test_info_on_a_broken_file_exits_1_with_the_finding() -> None:
    result = run("info", FIXTURES / "rules" / "S001" / "bad.urdf")
    assert result.exit_code == 1 and "xml-syntax" in result.output


# -- rule ---------------------------------------------------------------------------------


@pytest.mark.parametrize("key", ["S005", "s005", "invalid-number"])
def test_rule_by_code_or_name(key: str) -> None:
    result = run("rule", key)
    assert result.exit_code == 0
    assert result.output.startswith("# S005 invalid-number")
    for section in ("## What it does", "## Why it matters", "## Example", "## Fix"):
        assert section in result.output


def test_rule_catalogue() -> None:
    result = run("rule", "--all")
    assert result.exit_code == 0
    assert any(
        line.startswith("X005") and "macros-only" in line for line in result.output.splitlines()
    )


def test_convert_quiet_prints_errors_only(tmp_path) -> None:
    """`convert -q` keeps the loss report's warnings out of CI logs; without -q they are printed."""
    from click.testing import CliRunner

    from urdftool.cli import main

    source = FIXTURES / "robots" / "two_link_arm.urdf"
    text = source.read_text().replace(
        "</robot>", '<gazebo><plugin name="p" filename="libp.so"/></gazebo></robot>'
    )
    robot = tmp_path / "arm.urdf"
    robot.write_text(text)
    loud = CliRunner().invoke(main, ["convert", str(robot), "-o", str(tmp_path / "a.xml")])
    quiet = CliRunner().invoke(main, ["convert", str(robot), "-o", str(tmp_path / "b.xml"), "-q"])
    assert loud.exit_code == quiet.exit_code == 0
    assert "conversion-dropped" in loud.output
    assert "conversion-dropped" not in quiet.output


def test_json_locations_in_included_files_are_relative_like_the_text_report(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A finding in a file the checked xacro includes names it relative to the working folder,
    as the text and SARIF reports do, not by this machine's absolute path; one in the checked
    file names it as the file entry does."""
    monkeypatch.chdir(ROOT)
    model = "fixtures/seeds/learning_ros/mobot_urdf/urdf/mobot_w_arm.xacro"
    report = json_report("--no-dynamics", model)
    (file_report,) = report["files"]
    paths = {d["location"]["path"] for d in file_report["diagnostics"] if d["location"]}
    assert "fixtures/seeds/learning_ros/mobot_urdf/urdf/mobot2.xacro" in paths, paths
    assert not [p for p in paths if Path(p).is_absolute()], paths
    absolute = json_report("--no-dynamics", "--select", "S", str(ROOT / "fixtures/rules/S005/bad.urdf"))
    located = {d["location"]["path"] for f in absolute["files"] for d in f["diagnostics"]}
    assert located == {str(ROOT / "fixtures/rules/S005/bad.urdf")}
