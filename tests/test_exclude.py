"""``check --exclude`` and the ``exclude`` setting: exports written into a source tree are left
out of a directory check (new-user report of 2026-11-26); a file named on the command line is
checked anyway."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

from tests.conftest import FIXTURES
from urdftool.cli import main
from urdftool.pipeline.discover import excluded


@pytest.mark.parametrize("relative, patterns, expected", [
    ("exports/arm_pb.urdf", ["exports"], True),
    ("robots/exports/arm.urdf", ["exports"], True),  # a folder name anywhere on the path
    ("robots/arm_pb.urdf", ["*_pb.urdf"], True),
    ("robots/old/arm.urdf", ["robots/old"], True),  # a folder at the start, with a slash
    ("robots/old/arm.urdf", ["robots/old/*"], True),
    ("lab/robots/old/arm.urdf", ["robots/old"], False),  # a slash anchors at the start
    ("robots/arm.urdf", ["exports", "*_pb.urdf", "robots/old"], False),
    ("robots/arm.urdf", ["", "/"], False),
])
def test_patterns_match_as_gitignore_lines(relative: str, patterns: list[str], expected: bool) -> None:
    assert excluded(relative, patterns) is expected


def _tree(tmp_path: Path) -> Path:
    robot = FIXTURES / "rules" / "S001" / "good.urdf"
    for place in ("robots/arm.urdf", "exports/arm_pb.urdf", "robots/old/arm.urdf"):
        (tmp_path / place).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(robot, tmp_path / place)
    return tmp_path


def _checked(args: list[str]) -> str:
    result = CliRunner().invoke(main, ["check", "--no-dynamics", *args])
    assert result.exit_code == 0, result.output
    return result.output.strip().splitlines()[-1]


def test_exclude_flag_leaves_walked_files_out(tmp_path: Path) -> None:
    tree = _tree(tmp_path)
    assert _checked([str(tree)]).startswith("3 files checked")
    assert _checked([str(tree), "--exclude", "exports,robots/old"]).startswith("1 file checked")
    # named on the command line: checked whatever the patterns say
    assert _checked([str(tree), str(tree / "exports" / "arm_pb.urdf"),
                     "--exclude", "exports,robots/old"]).startswith("2 files checked")


def test_exclude_setting_is_relative_to_its_configuration(tmp_path: Path) -> None:
    tree = _tree(tmp_path)
    (tree / "pyproject.toml").write_text('[tool.urdftool]\nexclude = ["exports", "robots/old"]\n')
    assert _checked([str(tree)]).startswith("1 file checked")
    assert _checked([str(tree / "exports" / "arm_pb.urdf")]).startswith("1 file checked")
    (tree / "pyproject.toml").write_text('[tool.urdftool]\nexclude = "exports"\n')
    wrong = CliRunner().invoke(main, ["check", str(tree)])
    assert wrong.exit_code == 2
    assert "'exclude' must be a list of file or folder patterns" in wrong.output
