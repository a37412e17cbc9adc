"""Mesh and include URIs resolved as the simulators resolve them (urdftool/parse/packages.py).

Both cases come from a sweep of real repositories: PX4-SITL_gazebo-classic's ocean model writes
`model://ocean//media/…`, and osrf/vrx's boats write `file://roboboat01/meshes/…`, relative to
the resource paths its ament hooks export."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from urdftool.parse.packages import PackageResolver
from urdftool.pipeline.check import CheckOptions, check_file

#: a closed mesh of four triangles (m), so the mesh rules have something valid to read
_FACES = (("0 0 0", "0 0.1 0", "0.1 0 0"), ("0 0 0", "0.1 0 0", "0 0 0.1"),
          ("0 0 0", "0 0 0.1", "0 0.1 0"), ("0.1 0 0", "0 0.1 0", "0 0 0.1"))
TETRAHEDRON = "solid t\n" + "".join(
    "facet normal 0 0 0\nouter loop\n" + "".join(f"vertex {v}\n" for v in face) + "endloop\nendfacet\n"
    for face in _FACES
) + "endsolid t\n"


def _model(root: Path, name: str, uri: str) -> Path:
    folder = root / "models" / name
    (folder / "meshes").mkdir(parents=True)
    (folder / "meshes" / "hull.stl").write_text(TETRAHEDRON)
    (folder / "model.config").write_text(f"<model><name>{name}</name><sdf>model.sdf</sdf></model>")
    sdf = folder / "model.sdf"
    sdf.write_text(f'<sdf version="1.9"><model name="{name}"><static>true</static><link name="l">'
                   f'<visual name="v"><geometry><mesh><uri>{uri}</uri></mesh></geometry></visual>'
                   '</link></model></sdf>')
    return sdf


@pytest.mark.parametrize("uri", ["model://boat//meshes/hull.stl", "model://boat/meshes//hull.stl"])
def test_a_doubled_slash_stays_inside_the_model(tmp_path: Path, uri: str) -> None:
    sdf = _model(tmp_path, "boat", uri)
    found = PackageResolver.create(package_paths=[tmp_path / "models"], environ={}).resolve_uri(uri, sdf)
    assert found.path is not None
    assert os.path.normpath(found.path) == str(sdf.parent / "meshes" / "hull.stl")


def test_a_doubled_slash_after_a_package(tmp_path: Path) -> None:
    (tmp_path / "pkg" / "meshes").mkdir(parents=True)
    (tmp_path / "pkg" / "package.xml").write_text("<package><name>pkg</name></package>")
    resolver = PackageResolver.create(package_paths=[tmp_path], environ={})
    found = resolver.resolution("package://pkg//meshes/a.stl", str(tmp_path / "robot.urdf"))
    assert os.path.normpath(found.path or "") == str(tmp_path / "pkg" / "meshes" / "a.stl")


def test_a_relative_file_uri_is_found_in_the_resource_paths(tmp_path: Path,
                                                            monkeypatch: pytest.MonkeyPatch) -> None:
    sdf = _model(tmp_path / "share", "boat", "file://boat/meshes/hull.stl")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)  # the verdict no longer depends on where urdftool runs
    env = {"GZ_SIM_RESOURCE_PATH": str(tmp_path / "share" / "models")}
    found = PackageResolver.create(environ=env).resolve_uri("file://boat/meshes/hull.stl", sdf)
    assert found.path == str(tmp_path / "share" / "models" / "boat" / "meshes" / "hull.stl")
    # found from the model's own folders too, as a project's models folder sits above its models
    alone = PackageResolver.create(environ={}).resolve_uri("file://boat/meshes/hull.stl", sdf)
    assert alone.path == found.path
    codes = [d.code for r in check_file(str(sdf), CheckOptions()) for d in r.diagnostics
             if d.severity.value == "error"]
    assert codes == []


def test_a_relative_file_uri_found_nowhere_is_still_missing(tmp_path: Path) -> None:
    sdf = _model(tmp_path, "boat", "file://other_boat/meshes/hull.stl")
    codes = [d.code for r in check_file(str(sdf), CheckOptions()) for d in r.diagnostics
             if d.severity.value == "error"]
    assert codes == ["M002"]
