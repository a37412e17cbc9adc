"""The meshes-and-geometry and Gazebo rules on the real corpora (the issue's done-when facts).

Mesh loading goes through the user's persistent mesh cache, as in real use;
the cache's own behaviour is tested in test_meshes.py with a private folder.
"""

from __future__ import annotations

import json
import os
from collections import Counter
from pathlib import Path

import pytest
from click.testing import CliRunner

from tests.conftest import ERD, SEEDS, erd_urdfs, pybullet_robots
from urdftool.cli import main
from urdftool.diagnostics import Diagnostic
from urdftool.pipeline.check import CheckOptions, check_file, check_files

TURTLEBOT = SEEDS / "turtlebot3" / "turtlebot3_description"
MY_ROBOT = SEEDS / "go_chase_it" / "my_robot" / "urdf" / "my_robot.xacro"
M_ROBOT = SEEDS / "hyundai_ngv" / "m_robot_description" / "urdf" / "m_robot.xacro"
DIFFBOT = (
    Path(__file__).resolve().parent.parent
    / "urdftool"
    / "examples"
    / "diffbot"
    / "urdf"
    / "diffbot.urdf.xacro"
)


def findings(path: Path, select: str) -> list[Diagnostic]:
    return [d for r in check_file(str(path), CheckOptions(select=(select,))) for d in r.diagnostics]


# -- seed corpus --------------------------------------------------------------------------


def test_turtlebot_absent_meshes_are_reported_with_the_paths_tried() -> None:
    absent = {"burger_base.stl", "waffle_base.stl", "waffle_pi_base.stl"}
    reported: dict[str, Diagnostic] = {}
    for urdf in sorted((TURTLEBOT / "urdf").glob("turtlebot3_*.urdf")):
        for d in findings(urdf, "M"):
            if d.name == "mesh-not-found":
                reported[os.path.basename(d.data["path"])] = d
    # The three base meshes the URDFs use are absent; the fourth absent file
    # (meshes/sensors/astra.dae) is used by none of the three URDFs.
    assert set(reported) == absent
    for name, d in reported.items():
        expected = os.path.realpath(TURTLEBOT / "meshes" / "bases" / name)
        # Compare real paths: the corpus may be reached through a symbolic link.
        assert os.path.realpath(d.data["path"]) == expected and d.data["path"] in d.help
        assert d.data["tried"] and "turtlebot3_description" in d.help
        assert d.location is not None and d.location.line


def test_turtlebot_existing_meshes_raise_no_mesh_errors() -> None:
    for urdf in sorted((TURTLEBOT / "urdf").glob("turtlebot3_*.urdf")):
        codes = Counter(d.name for d in findings(urdf, "M"))
        assert codes["mesh-not-found"] == 1, urdf.name
        assert not codes["mesh-unreadable"] and not codes["unresolved-package"]
        assert not codes["mesh-units-suspect"], (
            "TurtleBot's scale 0.001 meshes are in millimetres, correctly"
        )


def test_my_robot_drive_plugin_separation_is_reported() -> None:
    found = [d for d in findings(MY_ROBOT, "G004")]
    assert len(found) == 1
    d = found[0]
    assert d.data["declared_m"] == pytest.approx(0.4)
    assert d.data["measured_m"] == pytest.approx(0.3)
    assert d.location is not None and d.location.path.endswith("my_robot.gazebo")
    assert "0.3" in d.help


def test_m_robot_skid_steer_matches_its_wheels() -> None:
    assert findings(M_ROBOT, "G004") == []


def test_diffbot_example_separation_is_reported() -> None:
    found = findings(DIFFBOT, "G004")
    assert [round(d.data["measured_m"], 3) for d in found] == [0.34]
    assert found[0].data["declared_m"] == pytest.approx(0.30)


@pytest.mark.parametrize(("path", "link"), [(MY_ROBOT, "chassis"), (M_ROBOT, "base_frame")])
def test_pose_inside_a_urdf_link_is_reported(path: Path, link: str) -> None:
    found = [d for d in findings(path, "G005") if d.data.get("element") == "pose"]
    assert [d.element for d in found] == [f"link[{link}]/pose"]
    assert found[0].data["pose"] == ["0", "0", "0.1", "0", "0", "0"]


# -- example-robot-data: every URDF in one `urdftool check` call ----------------------------


@pytest.fixture(scope="module")
def erd_report() -> dict:
    runner = CliRunner()
    result = runner.invoke(main, ["check", "--select", "M", "--format", "json", *erd_urdfs()])
    assert result.exit_code in (0, 1), result.output
    return json.loads(result.output)


def _by_rule(report: dict) -> dict[str, list[tuple[str, dict]]]:
    out: dict[str, list[tuple[str, dict]]] = {}
    for entry in report["files"]:
        for d in entry["diagnostics"]:
            out.setdefault(d["name"], []).append((entry["path"], d))
    return out


def test_erd_mesh_checks_cover_all_69_urdfs_in_one_call(erd_report: dict) -> None:
    assert len(erd_report["files"]) == 69


def test_erd_every_mesh_resolves_except_romeos_absolute_sdk_paths(erd_report: dict) -> None:
    rules = _by_rule(erd_report)
    assert "unresolved-package" not in rules, "package://example-robot-data and package:/// resolve"
    missing = rules.get("mesh-not-found", [])
    assert missing and all(d["data"]["uri"].startswith("file:///usr/Romeo/") for _, d in missing)
    assert {os.path.basename(p) for p, _ in missing} == {"romeo_laas_small.urdf"}


def test_erd_talos_triple_slash_uris_resolve() -> None:
    talos = [p for p in erd_urdfs() if os.path.basename(p) == "talos_full_v2.urdf"]
    text = Path(talos[0]).read_text()
    assert "package:///example-robot-data/" in text
    assert not [d for d in findings(Path(talos[0]), "M00") if d.code in ("M001", "M002")]


def test_erd_meshes_are_all_readable_and_plausibly_sized(erd_report: dict) -> None:
    rules = _by_rule(erd_report)
    assert "mesh-unreadable" not in rules  # anymal_foot.dae needs the COLLADA material fallback
    assert "mesh-units-suspect" not in rules
    assert "degenerate-geometry" not in rules


def test_erd_simple_humanoid_ascii_stl_is_unsupported_by_both_engines(erd_report: dict) -> None:
    warnings = [
        (p, d)
        for p, d in _by_rule(erd_report)["mesh-format-unsupported"]
        if d["severity"] == "warning"
    ]
    assert [(os.path.basename(p), d["data"]["format"]) for p, d in warnings] == [
        ("simple_humanoid.urdf", "stl-ascii")
    ]
    assert warnings[0][1]["data"]["engines"] == ["mujoco", "pybullet"]


# -- pybullet_data --------------------------------------------------------------------------


def test_pybullet_robots_mesh_findings() -> None:
    report = check_files(pybullet_robots(), CheckOptions(select=("M",)))
    rules = Counter(d.name for d in report.diagnostics)
    assert rules["mesh-units-suspect"] == 0
    assert rules["mesh-unreadable"] == 0
    degenerate = {d.message for d in report.diagnostics if d.name == "degenerate-geometry"}
    # laikago_toes*: zero-radius visual spheres marking the toes (warnings, not errors).
    assert degenerate and all("visual sphere has radius 0 m" in m for m in degenerate)
    unresolved = [d for d in report.diagnostics if d.name == "unresolved-package"]
    assert {d.data["package"] for d in unresolved} == {"meshes", "xarm_description", "xarm_gripper"}
    assert all("PyBullet finds it" in (d.help or "") for d in unresolved)


def test_erd_location_of_a_mesh_finding_is_the_mesh_element() -> None:
    assert ERD is not None
    romeo = next(p for p in erd_urdfs() if p.endswith("romeo_laas_small.urdf"))
    first = findings(Path(romeo), "M002")[0]
    line = Path(romeo).read_text().splitlines()[first.location.line - 1]
    assert "<mesh" in line and "Torso.mesh" in line
