"""Intent rules (N): the corpus review, default-off selection, options and pairing.

Every warning the intent rules raise on the valid robots of the corpora
(example-robot-data, pybullet_data, the seed xacros) is listed in REVIEWED and
explained in docs/intent.md; a new finding there fails this test until it is
reviewed, and no intent rule may raise an error there at all.
"""

from __future__ import annotations

import glob
from pathlib import Path

import pytest

from tests.conftest import (
    ERD,
    FIXTURES,
    PBD,
    SEEDS,
    erd_urdfs,
    pybullet_robots,
    relative,
    seed_standalone_xacros,
)
from urdftool.diagnostics import Severity
from urdftool.pipeline.check import CheckOptions, check_file
from urdftool.pipeline.settings import Overrides, resolve
from urdftool.rules import Selection, all_rules, lookup
from urdftool.rules.mirror_names import mirror_names, pairs

INTENT = tuple(r.code for r in all_rules() if r.code.startswith("N"))

#: corpus file -> sorted (code, line) of every intent warning, each reviewed in docs/intent.md
REVIEWED: dict[str, list[tuple[str, int]]] = {
    "alex_description/urdf/alex_nub_hands.urdf": [("N202", 626), ("N202", 634), ("N202", 642), ("N202", 650)],
    "alex_description/urdf/alex_psyonic_hands.urdf": [
        ("N202", 626), ("N202", 634), ("N202", 642), ("N202", 650), ("N203", 1341)],
    "alex_description/urdf/alex_sake_hands.urdf": [
        ("N202", 626), ("N202", 634), ("N202", 642), ("N202", 650)],
    "alexander_description/urdf/alexander_v1.lowerBodyOnly.urdf": [
        ("N104", 308), ("N104", 314), ("N104", 332), ("N104", 338)],
    "human_description/robots/human.urdf": [
        ("N201", 359), ("N202", 458), ("N202", 496), ("N202", 504), ("N202", 561)],
    "pr2_description/urdf/pr2.urdf": [("N303", 1851), ("N303", 2715)],
    "biped/biped2d_pybullet.urdf": [("N202", 146), ("N204", 191), ("N305", 238)],
    "humanoid/humanoid.urdf": [("N305", 97), ("N305", 153), ("N305", 209), ("N305", 265)],
    "husky/husky.urdf": [("N302", 115), ("N302", 166), ("N302", 217), ("N302", 268)],
    "aliengo/aliengo.urdf": [("N304", 85), ("N304", 194), ("N304", 302), ("N304", 411)],
    "r2d2.urdf": [("N103", 96), ("N103", 123), ("N103", 201), ("N103", 228)],
    "racecar/racecar.urdf": [("N105", 457), ("N202", 174)],
    "hyundai_ngv/m_robot_description/urdf/m_robot.xacro": [("N105", 70)],
    "learning_ros/mobot_urdf/urdf/mobot_w_lidar_and_camera.xacro": [("N105", 75)],
    "learning_ros/mobot_urdf/urdf/mobot_w_lidar_and_kinect.xacro": [("N105", 75)],
    "go_chase_it/my_robot/urdf/my_robot.xacro": [("N105", 51)],
    "racecar/racecar_differential.urdf": [("N202", 146)],
}


def _corpus() -> list[tuple[str, str]]:
    out = [(p, relative(p, ERD)) for p in erd_urdfs()] + [(p, relative(p, PBD)) for p in pybullet_robots()]
    out += [(p, relative(p, SEEDS)) for p in seed_standalone_xacros()]
    seeds = sorted(glob.glob(str(SEEDS / "**" / "*.urdf"), recursive=True))
    out += [(p, relative(p, SEEDS)) for p in seeds if p not in {q for q, _ in out}]
    return out


CORPUS = _corpus()


def _intent(path: str, **options: object) -> list:
    reports = check_file(path, CheckOptions(select=INTENT, **options))  # type: ignore[arg-type]
    return [d for r in reports for d in r.diagnostics if d.code.startswith("N")]


@pytest.mark.parametrize(("path", "name"), CORPUS, ids=[n for _, n in CORPUS])
def test_corpus_findings_are_reviewed(path: str, name: str) -> None:
    found = _intent(path)
    assert not [d for d in found if d.severity is Severity.ERROR]
    got = sorted((d.code, d.location.line) for d in found)
    assert got == REVIEWED.get(name, []), "\n".join(d.message for d in found)


def test_default_off_rules_need_their_exact_name() -> None:
    wheel = lookup("wheel-axis-not-lateral")
    assert wheel is not None and not wheel.default_enabled
    assert not Selection.of().enabled(wheel)
    assert not Selection.of(["N"]).enabled(wheel)
    assert Selection.of(["N103"]).enabled(wheel)
    assert Selection.of(["wheel-axis-not-lateral"]).enabled(wheel)
    assert not Selection.of(["N103"], ["N103"]).enabled(wheel)
    on = lookup("N201")
    assert on is not None and Selection.of().enabled(on) and Selection.of(["N"]).enabled(on)


def test_extend_select_adds_a_default_off_rule_to_the_default_set() -> None:
    settings = resolve(str(FIXTURES / "rules" / "N103" / "bad.urdf"), Overrides(extend_select=("N103",)))
    selection = Selection.of(settings.select, settings.ignore)
    assert selection.enabled(lookup("N103"))  # type: ignore[arg-type]
    assert selection.enabled(lookup("J001"))  # type: ignore[arg-type]
    assert not selection.enabled(lookup("N104"))  # type: ignore[arg-type]


def test_thresholds_are_rule_options() -> None:
    good = str(FIXTURES / "rules" / "N001" / "good.urdf")
    assert not [d for d in _intent(good) if d.code == "N001"]
    # read to four decimals, radians written to a few decimals are "degree" numbers; placeholders stay quiet
    strict = _intent(good, rule_options={"intent": {"degree_step": 0.0001}})
    assert [d.data["upper"] for d in strict if d.code == "N001"] == [25.1327, 9.42, 6.2832]
    bad = str(FIXTURES / "rules" / "N001" / "bad.urdf")
    lenient = _intent(bad, rule_options={"intent": {"degree_turns": 3}})
    assert [d.data["upper"] for d in lenient if d.code == "N001"] == [90.0, 180.0, 170.0, 166.0, 215.0]


def test_symmetry_findings_carry_the_other_member() -> None:
    found = [d for d in _intent(str(FIXTURES / "rules" / "N201" / "bad.urdf")) if d.code == "N201"]
    assert len(found) == 2
    for d in found:
        assert d.related and "mirrored joint" in d.related[0].label
        assert d.related[0].span.line != d.location.line
    assert "same side" in found[1].message


@pytest.mark.parametrize(
    ("name", "mirror"),
    [
        ("left_knee", "right_knee"),
        ("arm_left_2_joint", "arm_right_2_joint"),
        ("l_elbow", "r_elbow"),
        ("hip_R", "hip_L"),
        ("FL_HAA", "FR_HAA"),
        ("RL_calf", "RR_calf"),
        ("LH_KFE", "RH_KFE"),
        ("panda_leftfinger", "panda_rightfinger"),
        ("motor_front_leftL_joint", "motor_front_rightR_joint"),
        ("r_gripper_l_finger", "l_gripper_r_finger"),
    ],
)
def test_mirror_names(name: str, mirror: str) -> None:
    assert mirror_names(name)[0] == mirror


def test_pairs_are_found_once() -> None:
    assert pairs(["left_hip", "right_hip", "torso"]) == [("left_hip", "right_hip")]
    assert pairs(["bright", "torso"]) == []


def test_intent_rules_report_the_unit_they_suspect() -> None:
    [deg] = [d for d in _intent(str(FIXTURES / "rules" / "N001" / "bad.urdf")) if "-90" in d.message]
    assert "look like degrees" in deg.message and "1.5708 rad" in deg.message
    [grams] = _intent(str(FIXTURES / "rules" / "N004" / "bad.urdf"))
    assert "1200 → 1.2 kg" in grams.message
    assert Path(grams.location.path).name == "bad.urdf"


def test_provenance_of_a_property_a_macro_argument_and_a_yaml_value() -> None:
    path = FIXTURES / "intent" / "provenance" / "robot.urdf.xacro"
    findings = _intent(str(path))
    assert sorted(d.code for d in findings) == ["N001", "N001", "N202"]
    neck = next(d for d in findings if d.code == "N001" and "'neck'" in d.message)
    assert Path(neck.location.path).name == "robot.urdf.xacro" and neck.location.line == 13
    [prop] = [r for r in neck.related if "property" in r.label]
    assert "`neck_max`" in prop.label
    assert (Path(prop.span.path).name, prop.span.line) == ("robot.urdf.xacro", 6)
    knee = next(d for d in findings if d.code == "N202")
    assert (Path(knee.location.path).name, knee.location.line) == ("legs.xacro", 8)
    [call] = [r for r in knee.related if "macro" in r.label]
    assert '`upper="0.24"`' in call.label
    assert (Path(call.span.path).name, call.span.line) == ("robot.urdf.xacro", 19)
    # the jaw's limits are read from limits.yaml by key, in both spellings xacro accepts
    jaw = next(d for d in findings if d.code == "N001" and "'jaw'" in d.message)
    assert jaw.location.line == 23
    yaml_origins = {
        (r.label.split("`")[1], Path(r.span.path).name, r.span.line, r.span.column)
        for r in jaw.related
        if ".yaml" in r.span.path
    }
    assert yaml_origins == {("jaw.lower", "limits.yaml", 6, 3), ("jaw.upper", "limits.yaml", 7, 3)}
    assert any("`joint_limits`" in r.label for r in jaw.related)


def test_text_output_prints_origins_as_notes() -> None:
    from urdftool.render.text import render_diagnostic
    from urdftool.source import SourceIndex

    path = FIXTURES / "intent" / "provenance" / "robot.urdf.xacro"
    [neck] = [d for d in _intent(str(path)) if d.code == "N001" and "'neck'" in d.message]
    text = render_diagnostic(neck, SourceIndex(), excerpt=False)
    assert "note: the value comes from property `neck_max` at" in text


def test_serial_axes_named_by_letter_are_not_a_mirrored_pair() -> None:
    """Motoman names its axes S, L, E, U, R, B, T: `joint_l`/`joint_r` and `link_l`/`link_r` lie on
    one chain, so no symmetry rule compares them (a real-world false warning before)."""
    path = FIXTURES / "rules" / "N202" / "good_serial_axes.urdf"
    reports = check_file(str(path), CheckOptions(select=("N201", "N202", "N203", "N204")))
    assert [d.code for r in reports for d in r.diagnostics] == []
