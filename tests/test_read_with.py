"""A check says which files it read beside the model: the SRDF found next to it (or given with
``--srdf``) and the controllers YAML its ros2_control plugin names (or ``--controllers``), in the
text summary and as ``srdf``/``controllers`` in ``--format json`` (new-user report of 2026-11-26:
an SRDF was checked without a word)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

from tests.conftest import ERD, FIXTURES
from urdftool.cli import main
from urdftool.render.text import display_path

ARM_PACKAGES = FIXTURES / "ros2_control"
ARM = ARM_PACKAGES / "arm_control" / "urdf" / "arm.urdf.xacro"


def _run(*args: str) -> str:
    result = CliRunner().invoke(main, ["check", *args])
    assert result.exit_code in (0, 1), result.output
    return result.output


def _files(*args: str) -> list[dict[str, object]]:
    return json.loads(_run("--format", "json", *args))["files"]  # type: ignore[no-any-return]


@pytest.mark.skipif(ERD is None, reason="example-robot-data is a test dependency")
def test_the_srdf_beside_the_model_is_named(tmp_path: Path) -> None:
    assert ERD is not None
    robot = tmp_path / "panda_description"
    shutil.copytree(ERD / "panda_description" / "urdf", robot / "urdf")
    shutil.copytree(ERD / "panda_description" / "srdf", robot / "srdf")
    urdf, srdf = robot / "urdf" / "panda.urdf", robot / "srdf" / "panda.srdf"
    assert f"also read: {srdf} (SRDF)\n" in _run(str(urdf))
    assert _files(str(urdf))[0]["srdf"] == str(srdf)
    # --no-srdf reads none, and the report has neither the line nor the key
    assert "also read" not in _run("--no-srdf", str(urdf))
    assert "srdf" not in _files("--no-srdf", str(urdf))[0]
    # --quiet keeps to the summary line and the errors
    assert "also read" not in _run("--quiet", str(urdf))


def test_the_controllers_yaml_of_the_plugin_is_named() -> None:
    args = ("--package-path", str(ARM_PACKAGES), str(ARM))
    yaml = ARM_PACKAGES / "arm_control" / "config" / "arm_controllers.yaml"
    # below the working folder, so named relative to it
    assert f"also read: {display_path(str(yaml))} (controllers)\n" in _run(*args)
    assert _files(*args)[0]["controllers"] == [display_path(str(yaml))]


def test_many_files_are_counted_not_listed(tmp_path: Path) -> None:
    models = []
    for index in range(4):
        package = tmp_path / f"arm{index}"
        shutil.copytree(ARM_PACKAGES / "arm_control", package / "arm_control")
        models.append(str(package / "arm_control" / "urdf" / "arm.urdf.xacro"))
    folders = [arg for index in range(4) for arg in ("--package-path", str(tmp_path / f"arm{index}"))]
    output = _run(*folders, *models)
    assert "also read: the controllers of 4 of the 4 files (--format json names each)\n" in output
