"""``check --target``: each fixture of fixtures/targets/ gives exactly the marked findings per target.

Marks: ``<!-- expect[t1,t2]: CODE -->`` on the line where the finding is
expected for those targets, ``<!-- expect-file[t]: CODE -->`` for a finding
without a line. For every target, the T findings on each fixture must be
exactly the marked ones, and every target has at least three fixtures where
it reports something.
"""

from __future__ import annotations

import re
from collections import Counter
from pathlib import Path

import pytest
from click.testing import CliRunner

from tests.conftest import FIXTURES
from urdftool.cli import main
from urdftool.pipeline.check import CheckOptions, check_file
from urdftool.targets import TARGETS, UnknownTarget, parse_targets

TARGET_FIXTURES = sorted((FIXTURES / "targets").glob("*.urdf"))
_MARK = re.compile(r"<!--\s*expect(-file)?\[([a-z,\- ]+)\]:\s*([A-Z0-9, ]+?)\s*-->")


def marks(path: Path, target: str) -> Counter[tuple[int | None, str]]:
    found: Counter[tuple[int | None, str]] = Counter()
    for number, text in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        for match in _MARK.finditer(text):
            if target in [t.strip() for t in match.group(2).split(",")]:
                for code in match.group(3).split(","):
                    found[(None if match.group(1) else number, code.strip())] += 1
    return found


def target_findings(path: Path, target: str) -> list:
    options = CheckOptions(select=("T",), rule_options={"targets": (target,)})
    return [d for r in check_file(str(path), options) for d in r.diagnostics]


@pytest.mark.parametrize("target", sorted(TARGETS))
@pytest.mark.parametrize("path", TARGET_FIXTURES, ids=lambda p: p.stem)
def test_fixture_findings_match_marks(path: Path, target: str) -> None:
    found = target_findings(path, target)
    assert all(d.data.get("target") == target for d in found), [d.message for d in found]
    assert all(TARGETS[target].label in d.message for d in found), [d.message for d in found]
    got = Counter((d.location.line if d.location else None, d.code) for d in found)
    expected = marks(path, target)
    assert set(got) == set(expected), "\n".join(f"{d.location}: {d.code} {d.message}" for d in found)


@pytest.mark.parametrize("target", sorted(TARGETS))
def test_every_target_has_three_fixtures(target: str) -> None:
    with_findings = [p for p in TARGET_FIXTURES if any(c != "T009" for _, c in marks(p, target))]
    if target == "moveit":  # every fixture lacks an SRDF; the budget fixture adds T007
        with_findings = [p for p in TARGET_FIXTURES if marks(p, target)]
    assert len(with_findings) >= 3, with_findings


def test_no_target_no_findings() -> None:
    options = CheckOptions(select=("T",))
    for path in TARGET_FIXTURES:
        assert not [d for r in check_file(str(path), options) for d in r.diagnostics]


def test_parse_targets() -> None:
    assert [t.name for t in parse_targets(["mujoco,pybullet", "mujoco"])] == ["mujoco", "pybullet"]
    assert len(parse_targets(["all"])) == len(TARGETS)
    with pytest.raises(UnknownTarget, match="known: mujoco"):
        parse_targets(["bullet"])


def test_cli_target_option() -> None:
    path = str(FIXTURES / "targets" / "no_inertial.urdf")
    result = CliRunner().invoke(main, ["check", path, "--target", "pybullet", "--select", "T"])
    assert "PyBullet will give link 'arm' mass 1 kg" in result.output
    bad = CliRunner().invoke(main, ["check", path, "--target", "bullet"])
    assert bad.exit_code == 2 and "unknown target 'bullet'" in bad.output


def test_config_target_key(tmp_path: Path) -> None:
    source = (FIXTURES / "targets" / "mimic.urdf").read_text(encoding="utf-8")
    (tmp_path / "mimic.urdf").write_text(source, encoding="utf-8")
    (tmp_path / "urdftool.toml").write_text('target = ["kdl"]\nselect = ["T"]\n', encoding="utf-8")
    result = CliRunner().invoke(main, ["check", str(tmp_path / "mimic.urdf")])
    assert "KDL will ignore the <mimic> of joint 'right_slide'" in result.output


@pytest.mark.slow
def test_heavy_collision_meshes_of_a_real_robot() -> None:
    """UR3 from example-robot-data: CAD-resolution collision meshes, with the convert option to use."""
    from tests.conftest import ERD

    if ERD is None:
        pytest.skip("example-robot-data not installed")
    path = ERD / "ur_description" / "urdf" / "ur3_robot.urdf"
    options = CheckOptions(
        select=("T007",), package_paths=(str(ERD.parent), str(ERD)), rule_options={"targets": ("moveit",)}
    )
    found = [d for r in check_file(str(path), options) for d in r.diagnostics]
    by_mesh = {d.data["uri"].rsplit("/", 1)[-1]: d for d in found}
    assert {"base.stl", "shoulder.stl", "upperarm.stl"} <= set(by_mesh)
    assert by_mesh["upperarm.stl"].data["faces"] > 10_000
    assert by_mesh["shoulder.stl"].data["suggest"] == "hull"  # convex already
    assert by_mesh["base.stl"].data["suggest"] == "decompose"  # fills 67 % of its hull
    assert all("--collision" in (d.help or "") for d in found)
