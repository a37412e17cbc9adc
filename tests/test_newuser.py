"""What tripped a new user on real robot files (2026-11-25), each reduced to a fixture.

The corpus runs behind these are in docs/ci.md ("Tried as a new user").
"""

from __future__ import annotations

import builtins
from pathlib import Path

import pytest
from click.testing import CliRunner, Result

from tests.conftest import FIXTURES
from urdftool.cli import main

HERE = FIXTURES / "newuser"
WORLD = FIXTURES / "sdf-conformance" / "valid" / "world_several_models.sdf"  # models a, b


def run(*args: str | Path) -> Result:
    result = CliRunner().invoke(main, [str(a) for a in args])
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
    assert "Traceback" not in result.output
    return result


def test_check_help_names_a_schema_the_user_can_reach() -> None:
    # CONTRACTS.md lives in the test fixtures, not in an installed package
    result = run("check", "--help")
    assert "CONTRACTS.md" not in result.output
    assert "`urdftool schema`" in " ".join(result.output.split())


def test_the_summary_counts_files_not_models_for_a_world() -> None:
    result = run("check", WORLD, "--no-dynamics")
    assert "1 file checked (2 models):" in result.output, result.output
    github = run("check", WORLD, "--no-dynamics", "--format", "github")
    assert "1 file(s) checked (2 models):" in github.output, github.output


def test_a_typo_in_select_or_rule_suggests_the_rule() -> None:
    arm = FIXTURES / "robots" / "two_link_arm.urdf"
    result = run("check", arm, "--select", "I04")
    assert result.exit_code == 2 and "did you mean 'I004'?" in result.output, result.output
    result = run("check", arm, "--ignore", "inertia-not-positiv")
    assert result.exit_code == 2 and "did you mean 'inertia-not-positive-definite'?" in result.output
    result = run("rule", "inertia-not-positiv")
    assert result.exit_code == 2 and "did you mean 'inertia-not-positive-definite'?" in result.output


def test_a_refused_model_of_a_world_is_named(tmp_path: Path) -> None:
    world = tmp_path / "w.sdf"
    world.write_text(
        '<sdf version="1.8"><world name="w">'
        '<model name="ok"><link name="l"><inertial><mass>1</mass></inertial></link></model>'
        '<model name="ball"><link name="a"><inertial><mass>1</mass></inertial></link>'
        '<link name="b"><inertial><mass>1</mass></inertial></link>'
        '<joint name="j" type="ball"><parent>a</parent><child>b</child></joint></model>'
        "</world></sdf>"
    )
    result = run("convert", world, "-o", tmp_path / "out.urdf", "--all-models")
    assert result.exit_code == 1
    assert "model 'ball' not converted" in result.output, result.output
    assert (tmp_path / "out_ok.urdf").is_file() and not (tmp_path / "out_ball.urdf").exists()


def test_a_macro_called_three_times_reports_its_dropped_element_once(tmp_path: Path) -> None:
    for out in ("r.xml", "r.sdf"):
        result = run("convert", HERE / "repeated_gazebo.urdf.xacro", "-o", tmp_path / out)
        assert result.exit_code == 0, result.output
        assert result.output.count("warning[C001") == 1, result.output


def test_sim_says_why_it_fails_when_the_findings_are_only_warnings() -> None:
    # a weak arm held at its start pose (--hold) sags: the verdict fails on a warning
    weak = FIXTURES / "rules" / "D003" / "bad.urdf"
    result = run("sim", weak, "--engine", "pybullet", "--hold", "--duration", "0.5")
    assert result.exit_code == 1
    assert "0 error(s), 1 warning(s)" in result.output
    assert "exit 1: PyBullet: failed (not settled)" in result.output, result.output
    assert "verdict" in run("sim", "--help").output.split("Options:")[0].replace("\n", " ")


def test_an_overlap_pybullet_does_not_simulate_does_not_fail_the_run() -> None:
    # franka panda (gazebo:=true) and solo12: PyBullet loads without self-collision, so two
    # links overlapping at the start are no contact of its run (2026-11-26 walkthrough, problem 10)
    result = run("sim", HERE / "overlap_arm.urdf", "--engine", "pybullet", "--duration", "0.05")
    assert result.exit_code == 0, result.output
    assert "info[R002 sim-initial-penetration]" in result.output and "not simulated" in result.output
    assert "PyBullet: passed" in result.output


def test_every_command_lists_the_models_when_model_names_none(tmp_path: Path) -> None:
    commands = {
        "check": ["check", WORLD, "--no-dynamics"],
        "info": ["info", WORLD],
        "sim": ["sim", WORLD, "--engine", "mujoco", "--duration", "0.01"],
        "graph": ["graph", WORLD, "-o", tmp_path / "w.dot"],
        "convert": ["convert", WORLD, "-o", tmp_path / "w.xml"],
    }
    for name, args in commands.items():
        result = run(*args, "--model", "nope")
        assert result.exit_code == 2, (name, result.output)
        assert "no model named 'nope'" in result.output and "(it has: a, b)" in result.output, (
            name, result.output)


def test_a_misspelt_xacro_argument_is_reported_with_the_one_meant() -> None:
    # xacro ignores an argument no file uses: `-a gazbo:=true` left the Panda without inertia
    bad = FIXTURES / "rules" / "X007" / "bad.urdf.xacro"
    result = run("check", bad, "-a", "gazbo:=true", "--no-dynamics")
    assert "warning[X007 misspelt-xacro-argument]" in result.output, result.output
    assert "did you mean 'gazebo'" in result.output and "default 'false'" in result.output
    quiet = run("check", bad, "-a", "gazebo:=true", "-a", "use_lidar:=false", "--no-dynamics")
    assert "X007" not in quiet.output


def test_convert_and_info_say_when_a_xacro_argument_was_ignored(tmp_path: Path) -> None:
    # rosbot: `convert rosbot.urdf.xacro -a use_sims:=true` wrote the robot without its sim parts,
    # silently; only `check` said the argument was misspelt (2026-11-26 walkthrough, problem 7)
    bad = FIXTURES / "rules" / "X007" / "bad.urdf.xacro"
    for command in (["convert", bad, "-o", tmp_path / "arm.urdf"], ["info", bad]):
        result = run(*command, "-a", "gazbo:=true")
        assert result.exit_code == 0, result.output
        assert "warning[X007 misspelt-xacro-argument]" in result.stderr, (command, result.stderr)
        assert "did you mean 'gazebo'" in result.stderr
        spelt = run(*command, "-a", "gazebo:=true")
        assert spelt.exit_code == 0 and spelt.stderr == "", (command, spelt.stderr)
    quiet = run("convert", bad, "-o", tmp_path / "arm.urdf", "-a", "gazbo:=true", "-q")
    assert quiet.stderr == ""
    as_json = run("info", bad, "-a", "gazbo:=true", "--format", "json")
    assert as_json.stdout.lstrip().startswith("{") and "X007" in as_json.stderr


def test_a_xacro_type_error_names_the_property_that_is_text() -> None:
    # xacro fails where the expression is evaluated; the typo is in the property, in another file
    result = run("check", HERE / "text_property" / "robot.urdf.xacro", "--no-dynamics")
    assert result.exit_code == 1
    assert "error[X001 xacro-error]" in result.output
    assert "help: property 'base_mass' is '0.3,' (props.xacro:4), text, not a number; did you mean 0.3?" in (
        result.output), result.output


def test_an_unused_suppression_points_at_the_finding_it_missed(tmp_path: Path) -> None:
    # the comment went before <inertial>; the finding is on <inertia>, two lines further down
    text = (FIXTURES / "rules" / "I004" / "bad.urdf").read_text()
    robot = tmp_path / "robot.urdf"
    trunk = '  <link name="trunk">\n'
    comment = "    <!-- urdftool: ignore[I004] -->\n"
    robot.write_text(text.replace(f"{trunk}    <inertial>", f"{trunk}{comment}    <inertial>"))
    result = run("check", robot, "--no-dynamics", "--select", "I004,S024")
    assert "warning[S024 unused-suppression]" in result.output, result.output
    assert "help: the nearest I004 finding is on line 15" in result.output, result.output
    robot.write_text(text.replace(trunk, f"<!-- urdftool: ignore[I04] -->{trunk}"))
    result = run("check", robot, "--no-dynamics", "--select", "I004,S024")
    assert "'I04' is no rule code or name; did you mean 'I004'?" in result.output, result.output


def test_targets_describe_urdf_readers_and_say_nothing_about_an_sdf_file() -> None:
    # gz-sim reads SDF natively: no URDF-to-SDF conversion drops a link without <inertial>
    # (SDFormat gives it 1 kg) or lumps a fixed joint; the tables are about URDF readers
    world = HERE / "sdf_link_without_inertial.sdf"
    result = run("check", world, "--no-dynamics", "--target", "all", "--select", "T")
    assert result.exit_code == 0, result.output
    assert "[T0" not in result.output, result.output


def test_a_suppression_used_by_one_model_of_a_world_is_not_unused_for_the_others() -> None:
    result = run("check", HERE / "world_suppression.sdf", "--no-dynamics")
    assert result.exit_code == 0, result.output
    assert "S024" not in result.output and "I004" not in result.output, result.output
    # and without the comment the finding is there
    bare = run("check", HERE / "world_suppression.sdf", "--no-dynamics", "--no-suppressions")
    assert "error[I004" in bare.output


def test_a_world_of_many_models_reads_its_text_once(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # gz-sim's 3k_shapes.sdf (3004 models, 2.8 MB) took 82 s: each model re-read and split the
    # whole file to locate attributes, and the suppression scan read it again per model
    model = ('<model name="m{i}"><pose>{i} 0 0 0 0 0</pose><link name="l">'
             "<inertial><mass>1</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz></inertia>"
             "</inertial></link></model>\n")
    world = tmp_path / "many.sdf"
    world.write_text('<sdf version="1.8"><world name="w">\n' + "".join(model.format(i=i) for i in range(300))
                     + "</world></sdf>\n")
    reads: list[str] = []
    real_open = open

    def counting_open(file: object, *args: object, **kwargs: object) -> object:
        if str(file) == str(world):
            reads.append(str(file))
        return real_open(file, *args, **kwargs)  # type: ignore[call-overload]

    monkeypatch.setattr(builtins, "open", counting_open)
    result = run("check", world, "--no-dynamics")
    monkeypatch.undo()
    assert result.exit_code == 0, result.output
    assert "(300 models)" in result.output
    assert len(reads) < 10, len(reads)
