"""What the kinematic-tree diagram says: labels, units, escaping, merging, loops, findings."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import urdftool
from tests.test_graph_readers import svg_node_text
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.export.graph import GraphOptions, GraphSettings, build_dot, dot_text, render_files
from urdftool.export.graph.dot import esc_string, html_text, quote_id
from urdftool.export.graph.findings import Findings, element_target
from urdftool.export.graph.labels import angle, number, origin_text, significant
from urdftool.model import Inertial, Joint, JointType, Link, LoopClosure, Pose, Robot
from urdftool.model.robot import Limit, Mimic

INERTIA = Inertial.tensor(0.01, 0, 0, 0.01, 0, 0.01)


def link(name: str, mass: float | None = 1.0) -> Link:
    return Link(name, Inertial(mass, INERTIA) if mass is not None else None)


def joint(
    name: str, parent: str, child: str, kind: JointType = JointType.REVOLUTE, **kw: object
) -> Joint:
    return Joint(name, kind, parent, child, **kw)  # type: ignore[arg-type]


def arm() -> Robot:
    """base -fixed- mount -shoulder- upper -slide- tool; a camera fixed to upper."""
    return Robot(
        "arm",
        links=(
            link("base", 2.0),
            link("mount", 0.5),
            link("upper", 1.25),
            link("tool", None),
            link("camera", 0.1),
        ),
        joints=(
            joint("mount_joint", "base", "mount", JointType.FIXED, origin=Pose((0, 0, 0.1))),
            joint(
                "shoulder",
                "mount",
                "upper",
                origin=Pose((0, 0, 0.2), (0, 0, math.pi / 2)),
                axis=(0, 0, 1),
                limit=Limit(-1.5708, 1.5708, 30.0, 2.0),
            ),
            joint(
                "slide",
                "upper",
                "tool",
                JointType.PRISMATIC,
                origin=Pose((0.3, 0, 0)),
                limit=Limit(0.0, 0.25, 100.0, 0.5),
            ),
            joint("camera_joint", "upper", "camera", JointType.FIXED, origin=Pose((0.05, 0, 0))),
        ),
    )


def render_svg(text: str, tmp_path: Path) -> dict[str, str]:
    out = tmp_path / "g.svg"
    render_files(text, {out: "svg"})
    return svg_node_text(out.read_bytes())


# -- numbers and units --------------------------------------------------------


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (0.1, "0.1"),
        (-2.0, "-2"),
        (1e-12, "1e-12"),
        (-0.00001, "-1e-05"),
        (0.123456, "0.1235"),
        (-0.0, "0"),
    ],
)
def test_lengths_are_rounded_to_a_tenth_of_a_millimetre(value: float, text: str) -> None:
    assert number(value) == text


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (math.pi / 2, "π/2"),
        (-3 * math.pi / 4, "-3π/4"),
        (1.5708, "π/2"),
        (math.pi, "π"),
        (1.57, "1.57"),
        (2 * math.pi / 3, "2π/3"),
        (0.3, "0.3"),
    ],
)
def test_angles_that_are_fractions_of_pi_read_as_such(value: float, text: str) -> None:
    assert angle(value) == text


def test_significant_figures_for_masses_and_limits() -> None:
    assert [significant(v) for v in (102.4312, 0.5, 1e-5, 2.5e7, 0)] == [
        "102.4",
        "0.5",
        "1e-05",
        "2.5e+07",
        "0",
    ]


def test_origin_text_omits_what_is_zero() -> None:
    assert origin_text(Pose()) == ""
    assert origin_text(Pose((0.1, 0, 0))) == "xyz 0.1 0 0"
    assert origin_text(Pose((0, 0, 0), (0, 0, -math.pi / 2))) == "rpy 0 0 -π/2"


def test_joint_labels_carry_type_axis_limits_and_units(tmp_path: Path) -> None:
    nodes = render_svg(dot_text(arm(), GraphOptions(diagnostics=False)), tmp_path)
    assert (
        nodes["joint:shoulder"]
        == "shoulder revolute · axis 0 0 1 [-1.571, 1.571] rad 30 N·m · 2 rad/s"
    )
    assert nodes["joint:slide"] == "slide prismatic · axis 1 0 0 [0, 0.25] m 100 N · 0.5 m/s"
    assert nodes["joint:mount_joint"] == "mount_joint fixed"
    assert nodes["link:upper"] == "upper 1.25 kg"
    assert nodes["link:tool"] == "tool no inertial"


def test_mimic_and_continuous_joints() -> None:
    robot = Robot(
        "g",
        links=(link("a"), link("b"), link("c")),
        joints=(
            joint("wheel", "a", "b", JointType.CONTINUOUS, limit=Limit(effort=5.0, velocity=10.0)),
            joint("finger", "a", "c", mimic=Mimic("wheel", -1.0, 0.5), limit=Limit(0, 1, 1, 1)),
        ),
    )
    text = dot_text(robot, GraphOptions(diagnostics=False))
    assert 'continuous · axis 1 0 0</FONT><BR/><FONT POINT-SIZE="9">5 N·m · 10 rad/s' in text
    assert "mimics wheel ×-1 +0.5" in text


def test_title_has_name_dof_and_total_mass() -> None:
    text = dot_text(arm(), GraphOptions(diagnostics=False))
    assert "<B>arm</B>" in text
    assert "2 DOF · 3.85 kg · 5 links · 4 joints" in text


# -- structure -----------------------------------------------------------------


def test_edges_carry_origins_and_follow_the_tree() -> None:
    text = dot_text(arm(), GraphOptions(diagnostics=False))
    assert '"link:mount" -> "joint:shoulder" [label="xyz 0 0 0.2\\nrpy 0 0 π/2"];' in text
    assert '"joint:shoulder" -> "link:upper";' in text
    assert 'rankdir="TB"' in text


def test_rankdir_is_validated_and_normalised() -> None:
    assert 'rankdir="LR"' in dot_text(arm(), GraphOptions(rankdir="lr", diagnostics=False))
    with pytest.raises(ValueError, match="rankdir"):
        GraphOptions(rankdir="up")


def test_collapse_fixed_merges_chains_and_composes_origins(tmp_path: Path) -> None:
    text = dot_text(arm(), GraphOptions(collapse_fixed=True, diagnostics=False))
    nodes = render_svg(text, tmp_path)
    assert set(nodes) == {"link:base", "joint:shoulder", "link:upper", "joint:slide", "link:tool"}
    assert nodes["link:base"] == "base 2.5 kg + mount"
    assert nodes["link:upper"] == "upper 1.35 kg + camera"
    # shoulder sits 0.2 above mount, which sits 0.1 above base: 0.3 in base's frame.
    assert '"link:base" -> "joint:shoulder" [label="xyz 0 0 0.3\\nrpy 0 0 π/2"];' in text


def test_loop_closures_are_dashed_and_do_not_constrain_the_layout() -> None:
    robot = Robot(
        "fourbar",
        links=(link("ground"), link("crank"), link("coupler"), link("rocker")),
        joints=(
            joint("a", "ground", "crank"),
            joint("b", "crank", "coupler"),
            joint("c", "ground", "rocker"),
        ),
        loop_closures=(LoopClosure(joint("d", "coupler", "rocker"), Pose((0.4, 0, 0)), Pose()),),
    )
    text = dot_text(robot, GraphOptions(diagnostics=False))
    assert '"joint:d" [shape="ellipse", style="filled,dashed"' in text
    assert "loop closure" in text
    assert '"link:coupler" -> "joint:d" [label="xyz 0.4 0 0", style="dashed"];' in text
    assert '"joint:d" -> "link:rocker" [style="dashed", constraint=false];' in text
    assert "3 DOF" in text and "· 1 loop closure<" in text


def test_joints_off_the_tree_and_missing_links_are_drawn_not_dropped() -> None:
    robot = Robot(
        "odd",
        links=(link("a"), link("b"), link("a")),
        joints=(joint("j1", "a", "b"), joint("j2", "b", "a"), joint("j3", "b", "ghost")),
    )
    text = dot_text(robot, GraphOptions(diagnostics=False))
    assert '"link:a#2"' in text  # the repeated link gets its own box
    assert '"joint:j2" -> "link:a" [style="dashed", constraint=false];' in text
    assert '"missing:ghost" [shape="box", style="dashed"' in text and "no such link" in text


# -- escaping --------------------------------------------------------------------

NASTY = ['say "hi"', "back\\slash\\", "ns::arm::link", "Ωμέγα_関節", "<&>", "x]y"]


def test_escaping_primitives() -> None:
    assert quote_id('a"b\\') == '"a\\"b\\\\"'
    assert esc_string("a\nb") == '"a\\nb"'
    assert html_text('<a & "b">') == "&lt;a &amp; &quot;b&quot;&gt;"
    assert html_text("bell\x07") == "bell\\x07"  # XML cannot carry control characters


def test_nasty_names_survive_graphviz(tmp_path: Path) -> None:
    links = tuple(link(name) for name in ["root", *NASTY])
    joints = tuple(joint(f"j {name}", "root", name) for name in NASTY)
    nodes = render_svg(
        dot_text(Robot('r"::', links=links, joints=joints), GraphOptions(diagnostics=False)),
        tmp_path,
    )
    for name in NASTY:
        # Graphviz keeps the identifier as written between the quotes: backslashes doubled.
        assert nodes[f"link:{name}".replace("\\", "\\\\")] == f"{name} 1 kg"
        assert nodes[f"joint:j {name}".replace("\\", "\\\\")].startswith(f"j {name} revolute")


def test_text_is_deterministic() -> None:
    assert dot_text(arm()) == dot_text(arm())
    assert build_dot(arm(), GraphSettings()) == build_dot(arm(), GraphSettings())


# -- findings ----------------------------------------------------------------------


def finding(code: str, severity: Severity, element: str | None) -> Diagnostic:
    return Diagnostic(code, "some-rule", severity, f"{code} message", element=element)


def test_element_paths_map_to_links_and_joints() -> None:
    names = {"link": {"forearm", "a]b"}, "joint": {"elbow"}}
    assert element_target("link[forearm]/inertial", names) == ("link", "forearm")
    assert element_target("link[a]b]/visual/material", names) == ("link", "a]b")
    assert element_target("joint[elbow]", names) == ("joint", "elbow")
    assert element_target("joint[knee]", names) is None
    assert element_target("robot", names) is None and element_target(None, names) is None


def test_findings_colour_nodes_and_list_codes(tmp_path: Path) -> None:
    found = [
        finding("I003", Severity.ERROR, "link[upper]/inertial"),
        finding("J005", Severity.WARNING, "joint[slide]/limit"),
        finding("M001", Severity.INFO, "link[base]"),
        finding("S003", Severity.WARNING, "robot"),
    ]
    text = build_dot(arm(), GraphSettings(), found)
    nodes = render_svg(text, tmp_path)
    assert nodes["link:upper"] == "upper 1.25 kg error: I003"
    assert nodes["joint:slide"].endswith("warning: J005")
    assert "info" not in nodes["link:base"]
    assert (
        'fillcolor="#fde0dd", color="#d62728", penwidth=2, tooltip="I003 some-rule: I003 message"'
        in text
    )
    assert "robot warning: S003" in text
    assert Findings.of(arm(), found).other[0].code == "S003"


def test_real_rules_mark_a_real_file(tmp_path: Path) -> None:
    source = tmp_path / "bad.urdf"
    source.write_text(
        '<robot name="bad"><link name="a"/><link name="b"/>'
        '<joint name="j" type="revolute"><parent link="a"/><child link="b"/>'
        '<axis xyz="0 0 1" rpy="0 0 0"/>'
        '<limit lower="0" upper="1" effort="1" velocity="1"/></joint></robot>'
    )
    from urdftool import load
    from urdftool.pipeline.convert import graph_findings

    def drawn(options: GraphOptions) -> str:
        return dot_text(robot, options, graph_findings(robot, options))

    robot = load(source)
    assert "S009" in drawn(GraphOptions())  # <axis rpy=...> is an unknown attribute
    only = drawn(GraphOptions(select=("S009",)))
    joint_line = next(line for line in only.splitlines() if line.startswith('  "joint:j" ['))
    assert 'color="#e08000"' in joint_line and "warning: S009" in joint_line
    assert "S009" not in drawn(GraphOptions(diagnostics=False))
    assert "S009" not in drawn(GraphOptions(ignore=("S009",)))
    assert "S009" in urdftool.to_dot(robot)
