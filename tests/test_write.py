"""Outputs are written atomically, with ordinary permissions, and never over an input."""

from __future__ import annotations

import os
import stat

import pytest

from urdftool.export.write import OutputError, is_stale, write_bytes_atomic


def test_atomic_write_replaces_and_uses_umask(tmp_path) -> None:
    target = tmp_path / "out" / "robot.xml"
    write_bytes_atomic(target, b"one")
    write_bytes_atomic(target, b"two")
    assert target.read_bytes() == b"two"
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE(target.stat().st_mode) == 0o666 & ~mask
    assert [p.name for p in target.parent.iterdir()] == ["robot.xml"]  # no temporary left


def test_never_over_an_input(tmp_path) -> None:
    source = tmp_path / "robot.urdf"
    source.write_text("<robot/>")
    with pytest.raises(OutputError):
        write_bytes_atomic(source, b"x", inputs=[source])
    assert source.read_text() == "<robot/>"


def test_stale_detection(tmp_path) -> None:
    target = tmp_path / "a.xml"
    assert is_stale(target, b"x")
    target.write_bytes(b"x")
    assert not is_stale(target, b"x")
    assert is_stale(target, b"y")


def test_unwritable_folder_is_an_output_error(tmp_path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    with pytest.raises(OutputError, match="cannot write"):
        write_bytes_atomic(blocker / "robot.xml", b"x")


@pytest.mark.parametrize(
    ("command", "name"),
    [("check", "report.txt"), ("convert", "robot.xml"), ("graph", "tree.dot"), ("graph", "tree.svg")],
)
def test_cli_unwritable_output_exits_2_without_traceback(tmp_path, command, name) -> None:
    from click.testing import CliRunner

    from tests.conftest import FIXTURES
    from urdftool.cli import main

    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    out = str(blocker / name)
    result = CliRunner().invoke(main, [command, str(FIXTURES / "robots" / "two_link_arm.urdf"), "-o", out])
    assert result.exit_code == 2, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    assert "cannot write" in result.output
