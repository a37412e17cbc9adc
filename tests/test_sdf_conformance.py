"""SDFormat conformance: spec-valid files load without structural errors, spec-invalid ones get one.

The cases live in ``fixtures/sdf-conformance/{valid,invalid}``; each starts with
a comment naming the clause of the SDFormat specification (or libsdformat's
behaviour, see docs/sdf.md) it exercises.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from urdftool.diagnostics import Diagnostic
from urdftool.pipeline.check import CheckOptions, check_file

ROOT = Path(__file__).resolve().parent.parent / "fixtures" / "sdf-conformance"
VALID = sorted((ROOT / "valid").glob("*.sdf"))
INVALID = sorted((ROOT / "invalid").glob("*.sdf"))


#: invalid cases whose error belongs to a rule of another family, by that rule's name
OTHER_FAMILY = {"joint_axis_zero": "zero-axis"}


def _findings(path: Path) -> list[Diagnostic]:
    return [d for report in check_file(str(path), CheckOptions()) for d in report.diagnostics]


def _structural_errors(path: Path) -> list[str]:
    return [f"{d.code} {d.message}" for d in _findings(path)
            if d.severity.value == "error" and d.code[0] in "SL"]


def test_there_are_cases() -> None:
    assert len(VALID) >= 20
    assert len(INVALID) >= 40


@pytest.mark.parametrize("path", VALID + INVALID, ids=lambda p: f"{p.parent.name}/{p.stem}")
def test_case_names_its_clause(path: Path) -> None:
    assert path.read_text(encoding="utf-8").startswith("<!-- spec: ")


@pytest.mark.parametrize("path", VALID, ids=lambda p: p.stem)
def test_valid_case_has_no_structural_error(path: Path) -> None:
    assert _structural_errors(path) == []


@pytest.mark.parametrize("path", INVALID, ids=lambda p: p.stem)
def test_invalid_case_has_a_structural_error(path: Path) -> None:
    if path.stem in OTHER_FAMILY:
        errors = [d.name for d in _findings(path) if d.severity.value == "error"]
        assert OTHER_FAMILY[path.stem] in errors
        return
    assert _structural_errors(path), "no S*/L* error reported"


def test_newer_element_names_its_version() -> None:
    messages = [d.message for d in _findings(ROOT / "valid" / "newer_element_warns.sdf") if d.code == "S008"]
    assert any("enable_wind" in m and "1.6" in m for m in messages), messages


def test_free_bodies_are_named_not_errors() -> None:
    findings = _findings(ROOT / "valid" / "free_bodies.sdf")
    roots = [d for d in findings if d.name == "multiple-roots"]
    assert [d.severity.value for d in roots] == ["info"]
    assert "ball" in roots[0].message and "box" in roots[0].message


def test_closed_chain_is_reported_as_a_loop() -> None:
    findings = _findings(ROOT / "valid" / "closed_chain_two_parents.sdf")
    assert any(d.name == "closed-chain" for d in findings)
    assert not any(d.name == "multiple-roots" for d in findings)
