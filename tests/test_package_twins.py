"""Two folders under one search folder whose ``package.xml`` give the same name: the first in
name order is taken, silently when it does not matter, and a mesh that only the other one holds
is ``mesh-not-found`` with help that names the other folder (new-user report of 2026-11-26:
duplicate packages were resolved without a word). Layout reduced from icub-models, whose
``iCub`` and ``iCub_manual`` both declare ``<name>iCub</name>``."""

from __future__ import annotations

import shutil
from pathlib import Path

from tests.conftest import FIXTURES
from urdftool.parse.packages import PackageResolver
from urdftool.pipeline.check import CheckOptions, check_file

MESH = FIXTURES / "rules" / "M009" / "meshes" / "link0.stl"
URDF = """<robot name="arm">
  <link name="base">
    <visual><geometry><mesh filename="package://arm_description/meshes/base.stl"/></geometry></visual>
  </link>
</robot>
"""


def _package(folder: Path, mesh: bool) -> None:
    folder.mkdir(parents=True)
    (folder / "package.xml").write_text(
        '<?xml version="1.0"?>\n<package format="3"><name>arm_description</name></package>\n')
    if mesh:
        (folder / "meshes").mkdir()
        shutil.copy(MESH, folder / "meshes" / "base.stl")


def _findings(tmp_path: Path) -> list:
    model = tmp_path / "arm.urdf"
    model.write_text(URDF)
    options = CheckOptions(package_paths=(str(tmp_path / "ws"),), select=("M002",))
    return [d for report in check_file(str(model), options) for d in report.diagnostics]


def test_a_mesh_only_the_second_twin_holds_names_it(tmp_path: Path) -> None:
    _package(tmp_path / "ws" / "a_vendored_copy", mesh=False)  # first in name order, taken
    _package(tmp_path / "ws" / "arm_description", mesh=True)
    [found] = _findings(tmp_path)
    assert found.code == "M002"
    assert (f"package 'arm_description' is also at {tmp_path / 'ws' / 'arm_description'}, where this "
            "file exists") in (found.help or "")


def test_twins_that_both_hold_the_mesh_are_not_reported(tmp_path: Path) -> None:
    _package(tmp_path / "ws" / "a_vendored_copy", mesh=True)
    _package(tmp_path / "ws" / "arm_description", mesh=True)
    assert _findings(tmp_path) == []


def test_an_overlay_of_two_search_paths_is_not_a_twin(tmp_path: Path) -> None:
    _package(tmp_path / "underlay" / "arm_description", mesh=True)
    _package(tmp_path / "overlay" / "arm_description", mesh=True)
    resolver = PackageResolver.create(package_paths=[tmp_path / "overlay", tmp_path / "underlay"])
    found = resolver.find_package("arm_description")
    assert found.path == str(tmp_path / "overlay" / "arm_description")  # the first path wins
    assert found.path is not None and resolver.twins(found.path) == []
    # under one root, the later folder is the taken one's twin
    _package(tmp_path / "overlay" / "b_copy", mesh=False)
    again = PackageResolver.create(package_paths=[tmp_path / "overlay"])
    taken = again.find_package("arm_description").path
    assert taken is not None and again.twins(taken) == [str(tmp_path / "overlay" / "b_copy")]
