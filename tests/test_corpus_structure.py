"""Every corpus robot gets a report; the known-bad ones get errors at the right lines;
the rest get no structural error."""

from __future__ import annotations

import os

import pytest

from tests.conftest import ERD, PBD, erd_urdfs, pybullet_robots, relative, seed_standalone_xacros
from urdftool.diagnostics import Severity
from urdftool.pipeline.check import CheckOptions, check_file

#: file (relative to its corpus) -> {(rule name, line)} that must be among its errors
EXPECTED_ERRORS: dict[str, set[tuple[str, int]]] = {
    "ur_description/urdf/ur3.urdf": {("robot-name-missing", 6), ("empty-robot", 6)},
    "bicycle/bike.urdf": {("invalid-number", 103), ("invalid-number", 136)},
    "biped/biped2d_pybullet.urdf": {("invalid-number", 115), ("invalid-number", 146)},
    "husky/husky.urdf": {("unexpanded-substitution", 97)},
    "quadruped/microtaur/microtaur.urdf": {("wrong-vector-length", 300)},
    # Its spherical joint is a PyBullet extension (a warning); the error is the neck's
    # inertia, whose moments 0.01, 0.001, 0.001 break the triangle inequality.
    "spherical_joint_limit.urdf": {("inertia-triangle-inequality", 19)},
    # spirit40newer.urdf writes RL_lower_joint's <axis xyz="0 1 0"/> twice, the same both times:
    # a repeated-element warning since 2026-11-26 (docs/realworld.md, eighth batch), no error.
    "racecar/racecar_differential.urdf": {("wrong-vector-length", 16), ("wrong-vector-length", 23)},
}

STRUCTURE = ("S", "X")
OPTIONS = CheckOptions(select=STRUCTURE)


def _corpus() -> list[tuple[str, str]]:
    erd = [(p, relative(p, ERD)) for p in erd_urdfs()]
    pbd = [(p, relative(p, PBD)) for p in pybullet_robots()]
    return erd + pbd


CORPUS = _corpus()


def test_corpus_sizes() -> None:
    assert len(erd_urdfs()) == 69
    assert len(pybullet_robots()) == 45


@pytest.mark.parametrize(("path", "name"), CORPUS, ids=[n for _, n in CORPUS])
def test_structural_findings(path: str, name: str) -> None:
    # Known-bad files are checked with every rule; the rest must have no structural error.
    reports = check_file(path, CheckOptions() if name in EXPECTED_ERRORS else OPTIONS)
    assert reports, "every file gets a report"
    diags = [d for r in reports for d in r.diagnostics]
    assert not [d for d in diags if d.name == "internal-error"]
    errors = {
        (d.name, d.location.line if d.location else None) for d in diags if d.severity is Severity.ERROR
    }
    expected = EXPECTED_ERRORS.get(name)
    if expected is None:
        assert not errors, f"{name}: unexpected structural errors {sorted(errors)}"
    else:
        assert expected <= errors, f"{name}: expected {sorted(expected)}, got {sorted(errors)}"
        for d in diags:
            if d.location is not None and d.code[0] in STRUCTURE:
                assert os.path.samefile(d.location.path, path)
                assert d.location.column is not None


@pytest.mark.parametrize("path", seed_standalone_xacros(), ids=os.path.basename)
def test_seed_xacros_expand_without_ros(path: str) -> None:
    diags = [d for r in check_file(path, CheckOptions(select=("X",))) for d in r.diagnostics]
    failures = [d for d in diags if d.name in ("xacro-error", "package-not-found")]
    if path.endswith("kinect.urdf.xacro"):
        # The file writes name="${camera}" on <robot>, outside the macro that defines
        # `camera`; ROS's xacro rejects it as well.
        assert [(d.name, d.location.line) for d in failures] == [("xacro-error", 7)]
    else:
        assert not failures, [d.message for d in failures]


def test_sixteen_standalone_seed_xacros() -> None:
    assert len(seed_standalone_xacros()) == 16
