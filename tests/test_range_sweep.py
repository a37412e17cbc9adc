"""range-passes-through-parent (N305): the sweep's numbers, its thresholds and what it leaves out.

The fixtures of fixtures/rules/N305 show where the rule fires; here a rod
turning into a slab checks the angle and depth it reports against the
geometry worked out by hand, and the corpus review lives in tests/test_intent.py.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from urdftool.facts.collisions import available
from urdftool.facts.context import CheckContext
from urdftool.facts.range_sweep import range_sweeps
from urdftool.model import KinematicTree
from urdftool.parse import read
from urdftool.pipeline.check import CheckOptions, check_file

pytest.importorskip("pinocchio")

#: A rod 0.4 m long, 0.02 m square, its bottom face 0.1 m above a slab, turning about y at the
#: slab's surface: positive angles dip it into the slab (R_y(θ) takes +x towards −z).
ROD = """<?xml version="1.0"?>
<robot name="rod">
  <link name="slab">
    <collision><origin xyz="0 0 -1"/><geometry><box size="4 4 2"/></geometry></collision>
  </link>
  <link name="rod">
    <collision><origin xyz="0.2 0 0.11"/><geometry><box size="0.4 0.02 0.02"/></geometry></collision>
  </link>
  <joint name="hinge" type="{kind}">
    <parent link="slab"/><child link="rod"/><axis xyz="{axis}"/>
    <limit lower="{lower}" upper="{upper}" effort="1" velocity="1"/>{extra}
  </joint>
</robot>
"""


def _rod(tmp_path: Path, kind: str = "revolute", lower: float = 0.0, upper: float = 1.2,
         extra: str = "", axis: str = "0 1 0") -> Path:
    path = tmp_path / "rod.urdf"
    path.write_text(ROD.format(kind=kind, lower=lower, upper=upper, extra=extra, axis=axis), encoding="utf-8")
    return path


def _findings(path: Path, **intent: float) -> list:
    options = CheckOptions(select=("N305",), rule_options={"intent": intent} if intent else {})
    return [d for r in check_file(str(path), options) for d in r.diagnostics]


def test_the_angle_and_depth_are_the_geometry_s(tmp_path: Path) -> None:
    [finding] = _findings(_rod(tmp_path))
    data = finding.data
    # A point s along the rod's mid-line sinks below the surface when s > 0.11 / tan θ, so the
    # share of the rod inside the slab is 1 − 0.11 / (0.4 tan θ): 30 % at θ = atan(0.11 / 0.28).
    passing = math.atan(0.11 / 0.28)
    assert data["side"] == "upper" and data["limit"] == pytest.approx(1.2)
    # the first sample past it, or the next: the points filling the rod are 7 mm apart
    assert passing <= data["start"] <= passing + 2 * data["step"]
    # Deepest and fullest at the limit: the rod's far bottom edge is 0.4 sin θ − 0.1 cos θ below
    # the surface (the hull depth of a box is exact).
    assert data["fullest"] == pytest.approx(1.2)
    assert data["depth"] == pytest.approx(0.4 * math.sin(1.2) - 0.1 * math.cos(1.2), abs=1e-3)
    assert data["share"] == pytest.approx(1 - 0.11 / (0.4 * math.tan(1.2)), abs=0.03)
    assert data["home_share"] == 0.0
    assert "range [0, 1.2] rad: beyond 0.411 rad the link 'rod' passes 337 mm into 'slab'" in finding.message


def test_a_range_that_stops_before_the_passing_is_quiet(tmp_path: Path) -> None:
    # the rod touches the slab from atan(0.1/0.4) = 0.245 rad, but only its tip: not a passing
    assert not _findings(_rod(tmp_path, upper=0.35))


def test_a_limit_just_past_the_start_is_within_the_margin(tmp_path: Path) -> None:
    passing = math.atan(0.11 / 0.28)
    assert not _findings(_rod(tmp_path, upper=passing + math.radians(4)))
    assert _findings(_rod(tmp_path, upper=passing + math.radians(4)), sweep_margin_deg=0)


def test_thresholds_are_intent_options(tmp_path: Path) -> None:
    path = _rod(tmp_path)
    assert not _findings(path, sweep_share=0.95)
    assert not _findings(path, sweep_depth_min=0.5)
    [coarse] = _findings(path, sweep_step_deg=10)
    assert coarse.data["step"] == pytest.approx(1.2 / math.ceil(1.2 / math.radians(10)), abs=1e-6)


def test_the_lower_limit_is_judged_on_its_own(tmp_path: Path) -> None:
    assert not _findings(_rod(tmp_path, lower=-1.2, upper=0.0))  # negative angles lift the rod
    [finding] = _findings(_rod(tmp_path, lower=-1.2, upper=0.0, axis="0 -1 0"))
    assert finding.data["side"] == "lower" and finding.data["start"] == pytest.approx(-0.411, abs=0.035)


def test_prismatic_continuous_and_mimic_joints_are_not_swept(tmp_path: Path) -> None:
    assert not _findings(_rod(tmp_path, kind="prismatic"))
    assert not _findings(_rod(tmp_path, kind="continuous"))
    # a follower moves only with its leader (here, itself: any mimic makes a follower)
    assert not _findings(_rod(tmp_path, extra='<mimic joint="hinge" multiplier="1"/>'))


def test_the_step_widens_to_fit_the_budget(tmp_path: Path) -> None:
    [loaded] = read(str(_rod(tmp_path)))
    assert loaded.robot is not None
    ctx = CheckContext(loaded.robot, KinematicTree.of(loaded.robot))
    if not available(ctx):
        pytest.skip("coal is not installed")
    [fine] = range_sweeps(ctx)  # type: ignore[misc]
    [coarse] = range_sweeps(ctx, budget=10)  # type: ignore[misc]
    # 35 pairs' queries of 2° fit the default budget; a budget of 10 queries widens the step to fit
    assert len(fine.angles) == 36 and len(coarse.angles) == 11 and coarse.step == pytest.approx(0.12)


def test_the_finding_points_at_the_limit_attribute() -> None:
    path = Path(__file__).parent.parent / "fixtures" / "rules" / "N305" / "bad_upper.urdf"
    [finding] = _findings(path)
    assert (finding.location.line, finding.location.column) == (28, 25)  # upper="…"
    assert finding.element == "joint[elbow_joint]/limit/upper"
    assert [r.label for r in finding.related] == ["the collision of link 'upper_arm_link'"]


def test_an_attribute_on_a_later_line_of_the_tag_is_reported_at_the_limit(tmp_path: Path) -> None:
    path = _rod(tmp_path)
    text = path.read_text(encoding="utf-8").replace(' upper="1.2"', '\n           upper="1.2"')
    path.write_text(text, encoding="utf-8")
    [finding] = _findings(path)
    limit_line = next(n for n, line in enumerate(text.splitlines(), 1) if "<limit" in line)
    assert (finding.location.line, finding.location.column) == (limit_line, 5)
    # so the comment before the <limit> silences it
    ignored = text.replace("    <limit", "    <!-- urdftool: ignore[N305] -->\n    <limit")
    path.write_text(ignored, encoding="utf-8")
    assert not _findings(path)
