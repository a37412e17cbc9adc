"""``check --format json`` output validates against schemas/report.schema.json, which
matches the report shape of CONTRACTS.md."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner
from jsonschema import Draft202012Validator

from tests.conftest import ERD, FIXTURES, PBD, ROOT, SEEDS
from urdftool.cli import main

SCHEMA = json.loads((ROOT / "schemas" / "report.schema.json").read_text(encoding="utf-8"))
CONTRACTS = ROOT / "fixtures" / "contracts" / "CONTRACTS.md"
VALIDATOR = Draft202012Validator(SCHEMA)


def _report(*args: str) -> dict[str, Any]:
    result = CliRunner().invoke(main, ["check", "--format", "json", *args])
    assert result.exit_code in (0, 1), result.output
    return json.loads(result.output)


def _errors(document: dict[str, Any]) -> list[str]:
    return [
        f"{'/'.join(map(str, e.absolute_path))}: {e.message}"
        for e in VALIDATOR.iter_errors(document)
    ]


def test_schema_is_a_valid_draft_2020_12_schema() -> None:
    Draft202012Validator.check_schema(SCHEMA)


def test_contract_example_validates() -> None:
    """The example report in CONTRACTS.md, with each `a|b|c` alternative taken in turn."""
    text = CONTRACTS.read_text(encoding="utf-8")
    block = re.search(r"## JSON report.*?```json\n(.*?)```", text, re.DOTALL)
    assert block, "CONTRACTS.md has no JSON report example"
    example = block.group(1)
    for fmt, severity in (("urdf", "error"), ("xacro", "warning"), ("sdf", "info")):
        document = json.loads(
            example.replace("urdf|xacro|sdf", fmt).replace("error|warning|info", severity)
        )
        assert not _errors(document)


#: (label, command-line arguments) of real runs to validate
RUNS: list[tuple[str, list[str]]] = [
    ("rule-fixtures", [str(FIXTURES / "rules")]),
    ("two-link-arm", [str(FIXTURES / "robots" / "two_link_arm.urdf")]),
    ("seed-xacros", sorted(str(p) for p in SEEDS.rglob("*.urdf.xacro"))),
    ("seed-turtlebot3", [str(SEEDS / "turtlebot3")]),
    ("erd-ur5", [str(ERD / "ur_description" / "urdf" / "ur5_robot.urdf")] if ERD else []),
    ("erd-ur3-nameless", [str(ERD / "ur_description" / "urdf" / "ur3.urdf")] if ERD else []),
    ("erd-talos", [str(ERD / "talos_data" / "robots" / "talos_reduced.urdf")] if ERD else []),
    # read with its SRDF (the report's "srdf"), and with its controllers YAML ("controllers")
    ("erd-panda-srdf", [str(ERD / "panda_description" / "urdf" / "panda.urdf")] if ERD else []),
    ("ros2-control-arm", [str(FIXTURES / "ros2_control" / "arm_control" / "urdf" / "arm.urdf.xacro"),
                          "--package-path", str(FIXTURES / "ros2_control")]),
    ("pybullet-husky", [str(PBD / "husky" / "husky.urdf")] if PBD else []),
    ("pybullet-racecar", [str(PBD / "racecar" / "racecar_differential.urdf")] if PBD else []),
    ("pybullet-minitaur", [str(PBD / "quadruped" / "minitaur.urdf")] if PBD else []),
]


@pytest.mark.parametrize("args", [args for _, args in RUNS], ids=[label for label, _ in RUNS])
def test_real_report_validates(args: list[str]) -> None:
    assert args and Path(args[0]).exists(), f"corpus file missing: {args}"
    document = _report(*args)
    assert document["files"], "the run checked nothing"
    assert not _errors(document), "\n".join(_errors(document))


def test_report_with_null_location_and_robot_validates(tmp_path: Path) -> None:
    """A file that cannot be read has robot null; its finding still validates."""
    bad = tmp_path / "not_xml.urdf"
    bad.write_bytes(b"")
    document = _report(str(bad))
    assert document["files"][0]["robot"] is None
    assert not _errors(document)


@pytest.mark.parametrize(
    "mutation",
    [
        ("schema_version", 2),
        ("extra", True),
        ("files.0.format", "mjcf"),
        ("files.0.diagnostics.0.severity", "fatal"),
        ("files.0.diagnostics.0.code", "bad"),
        ("files.0.diagnostics.0.location.line", 0),
    ],
    ids=lambda m: m[0],
)
def test_schema_rejects_reports_that_break_the_contract(mutation: tuple[str, Any]) -> None:
    document = _report(str(FIXTURES / "rules" / "S005" / "bad.urdf"))
    assert not _errors(document)
    key, value = mutation
    *parents, last = key.split(".")
    target: Any = document
    for part in parents:
        target = target[int(part)] if part.isdigit() else target[part]
    target[last] = value
    assert _errors(document)
