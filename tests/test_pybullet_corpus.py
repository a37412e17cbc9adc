"""Every robot of the installed corpora through the PyBullet export, loaded by PyBullet itself.

A model with valid inertia converts and verifies with zero PyBullet warnings;
a model urdftool refuses is refused with located reasons and then converts
and verifies with --repair-inertia. Models that cannot be read, or whose
structure is broken (malformed numbers in pybullet_data), are refused before
export with located diagnostics. One test per file, so ``-n auto`` spreads them.
"""

from __future__ import annotations

import glob
import os
from pathlib import Path

import pytest

from tests.conftest import (
    ERD,
    PBD,
    SEEDS,
    erd_urdfs,
    pybullet_robots,
    relative,
    seed_standalone_xacros,
)
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.export import ExportOptions, export_model, verify_model
from urdftool.export.write import write_bytes_atomic
from urdftool.model import Robot
from urdftool.parse import read
from urdftool.pipeline.check import run_rules
from urdftool.rules import Selection


def seed_robots() -> list[str]:
    """The seed xacros that stand alone, and the seed URDF files."""
    return seed_standalone_xacros() + sorted(
        glob.glob(str(SEEDS / "**" / "*.urdf"), recursive=True)
    )


def _ids(paths: list[str], base: Path | None) -> list[str]:
    return [relative(p, base) for p in paths]


def _errors(diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    return [d for d in diagnostics if d.severity is Severity.ERROR]


def _assert_located(errors: list[Diagnostic]) -> None:
    assert errors
    for d in errors:
        assert d.location is not None and d.location.line, f"{d.code} {d.message} has no location"


def _convert_and_verify(robot: Robot, out: Path, repair: bool) -> list[Diagnostic]:
    """Export, write, verify; returns the export's diagnostics (the export must not be refused)."""
    options = ExportOptions(repair_inertia=repair)
    result = export_model(robot, "pybullet", out, options)
    assert not result.failed, [d.message for d in _errors(result.diagnostics)]
    for rel, data in result.files.items():
        write_bytes_atomic(out.parent / rel, data)
    outcome = verify_model(robot, "pybullet", out, options)
    assert outcome.ok, [d.message for d in outcome.diagnostics]
    assert not outcome.diagnostics  # in particular: no PyBullet warning at all
    assert outcome.rows and all(passed for *_, passed in outcome.rows)
    return result.diagnostics


def _check_file(path: str, tmp_path: Path) -> None:
    loaded = read(path)[0]
    if loaded.robot is None:
        _assert_located(_errors(loaded.diagnostics))
        return
    robot = loaded.robot
    structural = _errors(run_rules(robot, Selection.of(["S", "X"])))
    if structural:
        _assert_located(structural)
        return
    out = tmp_path / "robot.urdf"
    first = export_model(robot, "pybullet", out, ExportOptions())
    if first.failed:
        _assert_located(_errors(first.diagnostics))
        if any(
            d.name == "empty-robot" or d.data.get("reason") == "size" for d in first.diagnostics
        ):
            return  # a macro library, or more joints than PyBullet reports: no repair helps
        repaired = _convert_and_verify(robot, out, repair=True)
        assert any(d.name == "inertia-repaired" for d in repaired)
        return
    _convert_and_verify(robot, out, repair=False)


@pytest.mark.parametrize("path", erd_urdfs(), ids=_ids(erd_urdfs(), ERD))
def test_example_robot_data(path: str, tmp_path: Path) -> None:
    _check_file(path, tmp_path)


@pytest.mark.parametrize("path", pybullet_robots(), ids=_ids(pybullet_robots(), PBD))
def test_pybullet_data(path: str, tmp_path: Path) -> None:
    _check_file(path, tmp_path)


@pytest.mark.parametrize("path", seed_robots(), ids=_ids(seed_robots(), SEEDS))
def test_seed_systems(path: str, tmp_path: Path) -> None:
    _check_file(path, tmp_path)


def test_corpora_are_installed() -> None:
    assert len(erd_urdfs()) == 69
    assert len(pybullet_robots()) == 45
    assert os.path.isdir(SEEDS) and len(seed_robots()) >= 30
