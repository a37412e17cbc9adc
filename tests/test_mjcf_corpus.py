"""Every robot of the installed corpora converts to MJCF, compiles and verifies against
Pinocchio, or is refused with located diagnostics that name the physical problem; with
--repair-inertia every refused one converts, compiles and verifies.

One test per file (xdist spreads them); the expected refusals are listed by name so the
counts are asserted too. Verification here uses 5 random configurations per file
(``urdftool convert --verify`` uses 20).
"""

from __future__ import annotations

import glob
import os
from pathlib import Path

import pytest

from tests.conftest import ERD, PBD, SEEDS, erd_urdfs, pybullet_robots, seed_standalone_xacros
from urdftool.diagnostics import Severity
from urdftool.export import ExportOptions
from urdftool.export.mjcf import export
from urdftool.export.mjcf_verify import verify_mjcf
from urdftool.parse import read
from urdftool.parse.packages import PackageResolver

CONFIGURATIONS = 5

#: Refused for physically invalid inertia (or a moving body without mass): file name -> count.
ERD_REFUSED = {
    "alex_psyonic_hands.urdf", "allegro_left_hand.urdf", "allegro_right_hand.urdf",
    "anymal-kinova.urdf", "anymal_b_simple_description/robots/anymal.urdf",
    "anymal_c_simple_description/urdf/anymal.urdf", "b1-z1.urdf", "b1.urdf", "bolt.urdf",
    "finger_edu.urdf", "go1.urdf", "human.urdf", "hyq_no_sensors.urdf", "icub.urdf",
    "icub_reduced.urdf", "pr2.urdf", "romeo.urdf", "romeo_laas_small.urdf", "romeo_small.urdf",
    "tiago.urdf", "tiago_dual.urdf", "tiago_no_hand.urdf", "cassie.sdf",
}
#: Not a robot at all: no links (a xacro-generated stub) or a xacro include that cannot work.
ERD_NOT_A_ROBOT = {"ur3.urdf", "quadrotor_base.urdf.xacro", "quadrotor_base.xacro"}
PBD_REFUSED = {
    "TwoJointRobot_w_fixedJoints.urdf", "TwoJointRobot_wo_fixedJoints.urdf", "biped2d_pybullet.urdf",
    "cube_no_rotation.urdf", "franka_panda/panda.urdf", "laikago/laikago.urdf", "laikago_toes.urdf",
    "laikago_toes_limits.urdf", "mini_cheetah.urdf", "spherical_joint_limit.urdf", "xarm6_robot.urdf",
    "xarm6_robot_white.urdf", "xarm6_with_gripper.urdf",
}
#: Seed xacro files that are macro libraries, not robots (uos_tools), or do not expand alone.
SEED_NOT_A_ROBOT_DIR = "uos_tools"


def erd_models() -> list[str]:
    assert ERD is not None
    xacros = sorted(glob.glob(str(ERD / "**" / "*.xacro"), recursive=True))
    sdfs = sorted(glob.glob(str(ERD / "cassie_description" / "**" / "*.sdf"), recursive=True))
    return erd_urdfs() + xacros + sdfs


def _matches(path: str, names: set[str]) -> bool:
    posix = Path(path).as_posix()
    return any(posix.endswith("/" + name) for name in names)


def expected(path: str) -> str:
    if _matches(path, ERD_NOT_A_ROBOT) or f"/{SEED_NOT_A_ROBOT_DIR}/" in Path(path).as_posix():
        return "not-a-robot"
    if _matches(path, ERD_REFUSED | PBD_REFUSED):
        return "refused"
    return "verified"


def outcome(path: str, out: Path) -> tuple[str, str]:
    """("verified" | "refused" | "not-a-robot" | "failed", details)."""
    resolver = PackageResolver.create(None, [str(SEEDS)])
    loaded = read(path, None, resolver)[0]
    if loaded.robot is None or not loaded.robot.links:
        located = [d for d in loaded.diagnostics if d.location is not None]
        return ("not-a-robot" if located or loaded.robot is not None else "failed",
                "; ".join(d.message for d in loaded.diagnostics[:2]))
    robot = loaded.robot
    result = export(robot, out, ExportOptions())
    errors = [d for d in result.diagnostics if d.severity is Severity.ERROR]
    if errors:
        unlocated = [d for d in errors if d.location is None or d.location.line is None]
        if unlocated or any(d.code != "C003" for d in errors):
            return "failed", "; ".join(f"{d.code} {d.location}: {d.message}" for d in errors[:3])
        repaired = _export_and_verify(robot, out, ExportOptions(repair_inertia=True))
        return ("refused", "") if repaired is None else ("failed", f"with --repair-inertia: {repaired}")
    problem = _export_and_verify(robot, out, ExportOptions(), result.files)
    return ("verified", "") if problem is None else ("failed", problem)


def _export_and_verify(robot, out: Path, options: ExportOptions, files: dict | None = None) -> str | None:  # type: ignore[no-untyped-def]
    if files is None:
        result = export(robot, out, options)
        if result.failed:
            return "; ".join(d.message for d in result.diagnostics if d.severity is Severity.ERROR)
        files = result.files
    for rel, data in files.items():
        (out.parent / rel).parent.mkdir(parents=True, exist_ok=True)
        (out.parent / rel).write_bytes(data)
    verdict = verify_mjcf(robot, out, options, configurations=CONFIGURATIONS)
    if verdict.ok:
        return None
    return "; ".join(d.message for d in verdict.diagnostics) or str(verdict.rows)


def _id(path: str) -> str:
    for base in (ERD, PBD, SEEDS):
        if base is not None and path.startswith(str(base)):
            return os.path.relpath(path, base)
    return path


@pytest.mark.parametrize("path", erd_models() + pybullet_robots() + seed_standalone_xacros(), ids=_id)
def test_corpus_model_converts_and_verifies_or_is_refused(path: str, tmp_path: Path) -> None:
    got, details = outcome(path, tmp_path / "robot.xml")
    assert got == expected(path), f"{_id(path)}: {got} (expected {expected(path)}) {details}"


def test_corpus_counts() -> None:
    """The numbers docs/mjcf.md tabulates."""
    erd = erd_models()
    assert len(erd_urdfs()) == 69 and len(erd) == 69 + 2 + 5
    assert sum(expected(p) == "verified" for p in erd) == 76 - len(ERD_REFUSED) - len(ERD_NOT_A_ROBOT) == 50
    pbd = pybullet_robots()
    assert len(pbd) == 45
    assert sum(expected(p) == "refused" for p in pbd) == len(PBD_REFUSED) == 13
    seeds = seed_standalone_xacros()
    assert sum(expected(p) == "verified" for p in seeds) == 10
