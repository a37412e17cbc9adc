"""Configuration discovery, inline suppressions (URDF and xacro), unused suppressions, baselines."""

from __future__ import annotations

from pathlib import Path

import pytest

from urdftool.diagnostics import Report, Severity
from urdftool.parse import read
from urdftool.pipeline.baseline import apply_baseline, read_baseline, write_baseline
from urdftool.pipeline.check import CheckOptions, check_file
from urdftool.pipeline.settings import Overrides, SettingsError, find_config, resolve

#: A link with zero mass on a moving joint (I002 zero-mass, error), and an axis with an unknown
#: attribute (S009 unknown-attribute, warning).
ROBOT = """<?xml version="1.0"?>
<robot name="arm">
  <link name="base"/>
  {comment_link}<link name="tip"><inertial><mass value="0"/>
    <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="tip"/>
    {comment_axis}<axis xyz="0 0 1" rpy="0 0 0"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>
"""


def robot(tmp_path: Path, name: str = "arm.urdf", comment_link: str = "", comment_axis: str = "",
          above: int = 0) -> Path:
    path = tmp_path / name
    text = ROBOT.format(comment_link=comment_link, comment_axis=comment_axis)
    if above:  # lines inserted above everything: findings move, fingerprints must not
        text = text.replace("<robot", "\n" * above + "<robot", 1)
    path.write_text(text)
    return path


def codes(path: Path, **options: object) -> list[str]:
    report = check_file(str(path), CheckOptions(select=("S", "I", "J"), **options))  # type: ignore[arg-type]
    return [d.code for r in report for d in r.diagnostics]


def test_config_is_discovered_upward_and_nearest_wins(tmp_path: Path) -> None:
    (tmp_path / "pyproject.toml").write_text('[tool.urdftool]\nignore = ["I002"]\nstrict = true\n')
    nested = tmp_path / "robots" / "arm"
    nested.mkdir(parents=True)
    path = robot(nested)
    settings = resolve(path)
    assert settings.ignore == ("I002",) and settings.strict
    assert settings.sources["ignore"].endswith("pyproject.toml [tool.urdftool]")
    (nested.parent / "urdftool.toml").write_text('select = ["S"]\n[severity]\nunknown-attribute = "error"\n')
    nearer = resolve(path)
    assert nearer.select == ("S",) and nearer.ignore == () and not nearer.strict
    assert nearer.severity == {"unknown-attribute": Severity.ERROR}
    # A pyproject.toml without the table is passed over.
    (nested / "pyproject.toml").write_text("[project]\nname = 'x'\n")
    assert find_config(path).path == nested.parent / "urdftool.toml"


def test_command_line_wins_and_sources_are_named(tmp_path: Path) -> None:
    (tmp_path / "urdftool.toml").write_text('select = ["S"]\nignore = ["S009"]\n')
    settings = resolve(robot(tmp_path), Overrides(select=("I",), ignore=("I002",)))
    assert settings.select == ("I",) and settings.ignore == ("S009", "I002")
    assert settings.sources["select"] == "command line"
    lines = {line.split("=")[0].strip(): line for line in settings.describe().splitlines()}
    assert lines["select"].endswith("= ['I']  # command line")
    assert lines["strict"].endswith("= False  # default")
    assert resolve(robot(tmp_path), Overrides(isolated=True)).config is None


def test_per_file_ignores_and_xacro_args_follow_patterns(tmp_path: Path) -> None:
    (tmp_path / "urdftool.toml").write_text(
        '[per-file-ignores]\n"legacy/*.urdf" = ["I002"]\n[xacro-args."*.xacro"]\nprefix = "left_"\n'
    )
    (tmp_path / "legacy").mkdir()
    assert resolve(robot(tmp_path / "legacy")).ignore == ("I002",)
    assert resolve(robot(tmp_path)).ignore == ()
    assert resolve(tmp_path / "arm.urdf.xacro").xacro_args == {"prefix": "left_"}


def test_unknown_keys_and_wrong_types_are_errors_with_did_you_mean(tmp_path: Path) -> None:
    (tmp_path / "urdftool.toml").write_text('ignor = ["I002"]\n')
    with pytest.raises(SettingsError, match="unknown key 'ignor'; did you mean 'ignore'"):
        resolve(robot(tmp_path))
    (tmp_path / "urdftool.toml").write_text('strict = "yes"\n')
    with pytest.raises(SettingsError, match="'strict' must be true or false"):
        resolve(robot(tmp_path))


def test_inline_suppression_on_the_line_and_the_line_before(tmp_path: Path) -> None:
    assert {"I002", "S009"} <= set(codes(robot(tmp_path)))
    before = robot(tmp_path, comment_link="<!-- urdftool: ignore[zero-mass] -->\n  ")
    assert "I002" not in codes(before) and "S009" in codes(before)
    same_line = robot(tmp_path, comment_axis="<!-- urdftool: ignore[S009] --> ")
    assert "S009" not in codes(same_line) and "I002" in codes(same_line)
    assert {"I002", "S009"} <= set(codes(before, suppressions=False))


def test_file_level_suppression(tmp_path: Path) -> None:
    path = robot(tmp_path, comment_link="<!-- urdftool: ignore-file[I002, unknown-attribute] -->\n  ")
    found = codes(path)
    assert "I002" not in found and "S009" not in found and "S024" not in found


def test_unused_and_unknown_suppressions_are_reported(tmp_path: Path) -> None:
    path = robot(tmp_path, comment_link="<!-- urdftool: ignore[zero-mass,J001,no-such-rule] -->\n  ")
    report = check_file(str(path), CheckOptions(select=("S", "I", "J")))
    unused = [d for r in report for d in r.diagnostics if d.code == "S024"]
    assert sorted(d.data["selector"] for d in unused) == ["J001", "no-such-rule"]
    assert all(d.location and d.location.line == 4 for d in unused)  # the comment's line
    # A suppression of a rule that is not selected in this run is not judged.
    only_s = check_file(str(path), CheckOptions(select=("S",)))
    assert [d.data["selector"] for r in only_s for d in r.diagnostics if d.code == "S024"] == ["no-such-rule"]


def test_suppression_in_a_xacro_macro_covers_every_expansion(tmp_path: Path) -> None:
    (tmp_path / "arm.urdf.xacro").write_text("""<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="finger" params="name">
    <link name="${name}"/>
    <joint name="${name}_joint" type="revolute"><parent link="base"/><child link="${name}"/>
      <!-- urdftool: ignore[unknown-attribute] -->
      <axis xyz="0 0 1" rpy="0 0 0"/>
      <limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
  </xacro:macro>
  <link name="base"/>
  <xacro:finger name="left"/>
  <xacro:finger name="right"/>
</robot>
""")
    path = tmp_path / "arm.urdf.xacro"
    assert "S009" not in codes(path)
    assert codes(path, suppressions=False).count("S009") == 2


def test_severity_overrides_from_options(tmp_path: Path) -> None:
    report = check_file(str(robot(tmp_path)), CheckOptions(severity={"S009": Severity.ERROR}))
    levels = {d.code: d.severity for r in report for d in r.diagnostics}
    assert levels["S009"] is Severity.ERROR


def test_baseline_survives_ten_lines_inserted_above_a_finding(tmp_path: Path) -> None:
    path = robot(tmp_path)
    before = Report(tuple(check_file(str(path), CheckOptions())))
    baseline = tmp_path / "urdftool-baseline.json"
    recorded = write_baseline(before, baseline)
    assert recorded == len([d for f in before.files for d in f.diagnostics]) > 0
    moved = robot(tmp_path, above=10)
    after = Report(tuple(check_file(str(moved), CheckOptions())))
    assert [d.location.line for f in after.files for d in f.diagnostics if d.location] != \
        [d.location.line for f in before.files for d in f.diagnostics if d.location]
    result = apply_baseline(after, read_baseline(baseline), baseline)
    assert not [d for f in result.report.files for d in f.diagnostics]
    assert result.known == recorded and result.fixed == 0


def test_baseline_reports_new_findings_and_counts_fixed_ones(tmp_path: Path) -> None:
    path = robot(tmp_path)
    baseline = tmp_path / "baseline.json"
    write_baseline(Report(tuple(check_file(str(path), CheckOptions()))), baseline)
    # Fix the zero mass, add a new problem (an unknown attribute on the limit).
    text = path.read_text().replace('<mass value="0"/>', '<mass value="1"/>')
    text = text.replace('<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>',
                        '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>')
    path.write_text(text.replace('velocity="1"/>', 'velocity="1" soft="1"/>'))
    result = apply_baseline(Report(tuple(check_file(str(path), CheckOptions()))), read_baseline(baseline),
                            baseline)
    new = [d for f in result.report.files for d in f.diagnostics]
    assert [d.code for d in new] == ["S009"] and "soft" in new[0].message
    assert result.fixed >= 1


def _cli(*args: object) -> tuple[int, str, str]:
    from click.testing import CliRunner

    from urdftool.cli import main

    result = CliRunner().invoke(main, [str(a) for a in args])
    return result.exit_code, result.stdout, result.stderr


def test_cli_reads_the_config_and_shows_where_each_setting_came_from(tmp_path: Path) -> None:
    path = robot(tmp_path)
    assert _cli("check", "--no-dynamics", path)[0] == 1  # zero mass is an error
    (tmp_path / "pyproject.toml").write_text('[tool.urdftool]\nignore = ["zero-mass", "S009"]\n')
    code, out, _ = _cli("check", "--no-dynamics", path)
    assert code == 0, out
    code, out, _ = _cli("check", "--show-settings", path)
    assert code == 0 and "pyproject.toml [tool.urdftool]" in out and "ignore" in out
    assert _cli("check", "--no-dynamics", "--isolated", path)[0] == 1
    (tmp_path / "pyproject.toml").write_text('[tool.urdftool]\nignroe = ["I002"]\n')
    code, _, err = _cli("check", path)
    assert code == 2 and "did you mean 'ignore'" in err


def test_cli_suppressions_and_baseline(tmp_path: Path) -> None:
    path = robot(tmp_path, comment_link="<!-- urdftool: ignore[zero-mass] -->\n  ")
    code, out, _ = _cli("check", "--no-dynamics", "--select", "I002", path)
    assert code == 0, out
    assert _cli("check", "--no-dynamics", "--select", "I002", "--no-suppressions", path)[0] == 1
    plain = robot(tmp_path, name="plain.urdf")
    baseline = tmp_path / "baseline.json"
    code, _, err = _cli("check", "--no-dynamics", "--write-baseline", baseline, plain)
    assert code == 0 and "recorded" in err and baseline.is_file()
    code, out, err = _cli("check", "--no-dynamics", "--baseline", baseline, plain)
    assert code == 0 and "known finding(s) hidden" in err, out


@pytest.mark.parametrize("text", [
    "[tool.urdftool]\nselect = ['S']\n",
    "[ tool . \"urdftool\" ]\nselect = ['S']\n",
    "tool.urdftool.select = ['S']\n",
    "[tool]\nurdftool = { select = ['S'] }\n",
    "[tool]\nurdftool.select = ['S']\n",
    "tool = { urdftool = { select = ['S'] } }\n",
])
def test_every_spelling_of_the_tool_table_is_found(tmp_path: Path, text: str) -> None:
    (tmp_path / "pyproject.toml").write_text(text + "[project]\nname = 'arm'\n")
    config = find_config(tmp_path / "robot.urdf")
    assert config is not None and config.table == {"select": ["S"]}


def test_a_project_naming_urdftool_only_as_a_dependency_is_passed_over(tmp_path: Path) -> None:
    """No table to read: discovery goes on upward (and a cold start need not import a TOML parser)."""
    (tmp_path / "urdftool.toml").write_text("select = ['X']\n")
    project = tmp_path / "arm"
    project.mkdir()
    (project / "pyproject.toml").write_text(
        "[project]\nname = 'arm'\ndependencies = ['urdftool>=0.1']\n"
        "[project.scripts]\nurdftool-arm = 'arm.cli:main'\n[tool.ruff]\nline-length = 100\n")
    config = find_config(project / "robot.urdf")
    assert config is not None and config.path == tmp_path / "urdftool.toml"


def test_a_file_without_a_suppression_comment_is_read_once(tmp_path: Path) -> None:
    """The reader notes whether the text names ``urdftool:`` at all; the suppression pass reads
    again only the files that do (the URDF as read, and the SRDF beside it)."""
    [plain] = read(str(robot(tmp_path)))
    assert plain.without_suppressions == (plain.path,)
    commented = robot(tmp_path, name="commented.urdf",
                      comment_link="<!-- urdftool: ignore[zero-mass] -->\n  ")
    [loaded] = read(str(commented))
    assert loaded.without_suppressions == ()
    assert "I002" not in codes(commented) and "I002" in codes(robot(tmp_path, name="plain.urdf"))
