"""``urdftool graph`` and ``urdftool.to_dot`` end to end, with the real Graphviz."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner, Result

import urdftool
from tests.conftest import SEEDS
from tests.test_graph_readers import SIGNATURE, first_page_png, read_png, svg_nodes
from urdftool.cli import main
from urdftool.export.graph import GraphvizFailed, render_files

RRBOT = SEEDS / "gazebo_ros_demos" / "rrbot_description" / "urdf" / "rrbot.xacro"
ROBOT = """<robot name="two_link">
  <link name="base"><inertial><mass value="2"/>
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <link name="arm"><inertial><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.5"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
</robot>
"""


@pytest.fixture
def robot_file(tmp_path: Path) -> Path:
    path = tmp_path / "two_link.urdf"
    path.write_text(ROBOT)
    return path


def graph(*args: str | Path) -> Result:
    return CliRunner().invoke(main, ["graph", *map(str, args)])


def leftovers(folder: Path) -> list[str]:
    """Temporary files an atomic write would leave behind if it went wrong."""
    return sorted(p.name for p in folder.iterdir() if p.name.endswith(".tmp"))


def test_dot_output_needs_no_graphviz(
    robot_file: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    out = tmp_path / "tree.dot"
    result = graph(robot_file, "-o", out)
    assert result.exit_code == 0, result.output
    text = out.read_text()
    assert text.startswith('digraph "two_link" {') and '"joint:shoulder"' in text
    assert f"wrote {out}" in result.output


@pytest.mark.parametrize("suffix", [".svg", ".pdf", ".png"])
def test_rendered_outputs_are_real_and_byte_identical_on_rerun(
    robot_file: Path, tmp_path: Path, suffix: str
) -> None:
    out = tmp_path / f"tree{suffix}"
    assert graph(robot_file, "-o", out).exit_code == 0
    first = out.read_bytes()
    assert graph(robot_file, "-o", out).exit_code == 0
    assert out.read_bytes() == first
    if suffix == ".svg":
        assert set(svg_nodes(first)) == {"link:base", "link:arm", "joint:shoulder"}
    elif suffix == ".png":
        assert first.startswith(SIGNATURE) and read_png(first).ink() > 0.001
    else:
        assert first.startswith(b"%PDF-") and first_page_png(out, tmp_path).ink() > 0.001
    assert leftovers(tmp_path) == []
    assert oct(out.stat().st_mode & 0o777) != oct(0o600)  # shareable like any other file


def test_xacro_seed_with_options(tmp_path: Path) -> None:
    out = tmp_path / "rrbot.svg"
    result = graph(
        RRBOT,
        "-o",
        out,
        "--rankdir",
        "LR",
        "--collapse-fixed",
        "--keep-dot",
        "--package-path",
        SEEDS,
    )
    assert result.exit_code == 0, result.output
    dot = (tmp_path / "rrbot.dot").read_text()
    assert 'rankdir="LR"' in dot
    # fixed joints merged: world+link1 and link3+sensors are one box each
    assert set(svg_nodes(out.read_bytes())) == {
        "link:world",
        "joint:joint1",
        "link:link2",
        "joint:joint2",
        "link:link3",
    }
    assert f"wrote {tmp_path / 'rrbot.dot'}, {out}" in result.output


def test_missing_graphviz_is_a_usage_error_with_install_hints(
    robot_file: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    out = tmp_path / "tree.pdf"
    result = graph(robot_file, "-o", out)
    assert result.exit_code == 2
    assert "apt-get install graphviz" in result.output and "brew install graphviz" in result.output
    assert not out.exists() and "wrote" not in result.output
    kept = graph(robot_file, "-o", out, "--keep-dot")
    assert kept.exit_code == 2
    assert not out.exists() and (tmp_path / "tree.dot").exists()
    assert f"DOT text was written to {tmp_path / 'tree.dot'}" in kept.output
    assert leftovers(tmp_path) == []


def test_findings_are_marked_but_do_not_fail_the_drawing(tmp_path: Path) -> None:
    source = tmp_path / "massless.urdf"
    source.write_text(ROBOT.replace('<axis xyz="0 0 1"/>', '<axis xyz="0 0 1" rpy="0 0 0"/>'))
    out = tmp_path / "tree.dot"
    result = graph(source, "-o", out)
    assert result.exit_code == 0
    assert "1 warnings marked" in result.output and "S009" in out.read_text()
    quiet = graph(source, "-o", out, "--no-diagnostics", "-q")
    assert quiet.exit_code == 0 and quiet.output == "" and "S009" not in out.read_text()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["-o", "tree.txt"], "cannot write a graph as '.txt'"),
        (["-o", "tree.svg", "--rankdir", "UP"], "Invalid value for '--rankdir'"),
        (["-o", "tree.svg", "--select", "NOPE"], "matches no rule"),
    ],
)
def test_usage_errors_exit_2(
    robot_file: Path, tmp_path: Path, args: list[str], message: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    result = graph(robot_file, *args)
    assert result.exit_code == 2 and message in result.output
    assert [p.name for p in tmp_path.iterdir()] == ["two_link.urdf"]


def test_unreadable_inputs(tmp_path: Path) -> None:
    missing = graph(tmp_path / "nope.urdf", "-o", tmp_path / "t.dot")
    assert missing.exit_code == 2 and "no such file" in missing.output
    broken = tmp_path / "broken.urdf"
    broken.write_text("<robot name='x'><link name='a'>")
    result = graph(broken, "-o", tmp_path / "t.dot")
    assert result.exit_code == 1 and "no robot to draw" in result.output
    assert not (tmp_path / "t.dot").exists()


def test_never_writes_over_the_input(tmp_path: Path) -> None:
    source = tmp_path / "robot.dot"  # a URDF with an unlucky name
    source.write_text(ROBOT)
    result = graph(source, "-o", source)
    assert result.exit_code == 2 and "refusing to write over the input" in result.output
    assert source.read_text() == ROBOT


def test_convert_to_dot_matches_graph(robot_file: Path, tmp_path: Path) -> None:
    via_graph, via_convert = tmp_path / "a.dot", tmp_path / "b.gv"
    assert graph(robot_file, "-o", via_graph).exit_code == 0
    result = CliRunner().invoke(main, ["convert", str(robot_file), "-o", str(via_convert)])
    assert result.exit_code == 0, result.output
    assert via_convert.read_bytes() == via_graph.read_bytes()


def test_to_dot_api(robot_file: Path, tmp_path: Path) -> None:
    text = urdftool.to_dot(robot_file)
    assert '"link:base" -> "joint:shoulder" [label="xyz 0 0 0.5"];' in text
    robot = urdftool.load(robot_file)
    out = tmp_path / "tree.svg"
    assert urdftool.to_dot(robot, out, rankdir="LR", keep_dot=True) == urdftool.to_dot(
        robot, rankdir="LR"
    )
    assert set(svg_nodes(out.read_bytes())) == {"link:base", "link:arm", "joint:shoulder"}
    assert (tmp_path / "tree.dot").read_text() == urdftool.to_dot(robot, rankdir="LR")
    with pytest.raises(ValueError, match="rankdir"):
        urdftool.to_dot(robot, rankdir="sideways")
    with pytest.raises(ValueError, match="cannot write a graph"):
        urdftool.to_dot(robot, tmp_path / "tree.jpg")


FOURBAR_SDF = """<?xml version="1.0"?>
<sdf version="1.7">
  <model name="fourbar">
    <link name="ground"/>
    <link name="crank"><pose>0 0 0.1 0 0 0</pose></link>
    <link name="coupler"><pose>0.1 0 0.1 0 0 0</pose></link>
    <link name="rocker"><pose>0.4 0 0 0 0 0</pose></link>
    <joint name="a" type="revolute"><parent>ground</parent><child>crank</child></joint>
    <joint name="b" type="revolute"><parent>crank</parent><child>coupler</child></joint>
    <joint name="c" type="revolute"><parent>ground</parent><child>rocker</child></joint>
    <joint name="d" type="revolute"><parent>coupler</parent><child>rocker</child></joint>
  </model>
</sdf>
"""


def test_sdf_closed_chain_draws_its_loop_closure(tmp_path: Path) -> None:
    source = tmp_path / "fourbar.sdf"
    source.write_text(FOURBAR_SDF)
    out = tmp_path / "fourbar.svg"
    result = graph(source, "-o", out, "--keep-dot")
    assert result.exit_code == 0, result.output
    nodes = svg_nodes(out.read_bytes())
    assert {"link:ground", "link:crank", "link:coupler", "link:rocker"} <= set(nodes)
    assert {"joint:a", "joint:b", "joint:c", "joint:d"} <= set(nodes)
    dot = (tmp_path / "fourbar.dot").read_text()
    joints = [
        line for line in dot.splitlines() if line.startswith('  "joint:') and "label=" in line
    ]
    closures = [line for line in joints if "loop closure" in line]
    assert len(closures) == 1 and 'style="filled,dashed"' in closures[0]
    assert "constraint=false" in dot


def test_pdf_dates_are_fixed_for_reproducible_output(
    robot_file: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    out = tmp_path / "tree.pdf"
    assert graph(robot_file, "-o", out).exit_code == 0
    assert b"/CreationDate (D:19700101000000" in out.read_bytes()
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "86400")
    assert graph(robot_file, "-o", out).exit_code == 0
    assert b"/CreationDate (D:19700102000000" in out.read_bytes()
    assert first_page_png(out, tmp_path).ink() > 0.001  # same-length stamp: still a valid PDF


def test_a_failed_render_leaves_the_old_output(tmp_path: Path) -> None:
    out = tmp_path / "tree.svg"
    out.write_text("previous diagram")
    with pytest.raises(GraphvizFailed, match="syntax error"):
        render_files("digraph { a -> }", {out: "svg"})
    assert out.read_text() == "previous diagram"
    assert leftovers(tmp_path) == []


# provenance: reduced from neo_simulation2 worlds/neo_workshop.world (MIT), written anew: a world
# of several models, where `graph` drew the first one alone and said nothing of the others
WORLD = """<sdf version="1.6"><world name="workshop">
  <model name="wall"><static>1</static><link name="wall_link"/></model>
  <model name="cone"><link name="link"><inertial><mass>1</mass></inertial></link></model>
</world></sdf>
"""


def test_a_world_asks_which_model_to_draw_as_convert_does(tmp_path: Path) -> None:
    world = tmp_path / "workshop.world"
    world.write_text(WORLD)
    refused = graph(world, "-o", tmp_path / "w.dot")
    assert refused.exit_code == 2
    assert "holds 2 models (wall, cone)" in refused.output and "--all-models" in refused.output
    assert not (tmp_path / "w.dot").exists()
    one = graph(world, "-o", tmp_path / "cone.dot", "--model", "cone")
    assert one.exit_code == 0, one.output
    assert (tmp_path / "cone.dot").read_text().startswith('digraph "cone"')
    every = graph(world, "-o", tmp_path / "w.dot", "--all-models")
    assert every.exit_code == 0, every.output
    assert (tmp_path / "w_wall.dot").read_text().startswith('digraph "wall"')
    assert (tmp_path / "w_cone.dot").read_text().startswith('digraph "cone"')
    missing = graph(world, "-o", tmp_path / "x.dot", "--model", "nope")
    assert missing.exit_code == 2 and "no model named 'nope'" in missing.output
