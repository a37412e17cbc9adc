"""The mesh backend: exact scaling, the content-hash caches, parallel loading, lazy trimesh."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tests.conftest import ERD, FIXTURES
from urdftool.backends import mesh_cache, meshes
from urdftool.backends.mesh_formats import engines_refusing, sniff

CUBE = FIXTURES / "rules" / "M004" / "meshes" / "cube.stl"
DENSE = FIXTURES / "rules" / "M006" / "meshes" / "dense.obj"


@pytest.fixture
def private_cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A fresh cache folder and empty in-process memory for one test."""
    monkeypatch.setenv("URDFTOOL_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("URDFTOOL_NO_CACHE", raising=False)
    monkeypatch.setattr(meshes, "_FACTS", {})
    monkeypatch.setattr(meshes, "_KEYS", {})
    return tmp_path / "cache"


@pytest.mark.parametrize("scale", [(1.0, 1.0, 1.0), (0.001, 0.001, 0.001), (0.5, 2.0, -1.5)])
def test_scaled_facts_equal_trimesh_on_the_scaled_mesh(private_cache: Path, scale) -> None:
    info = meshes.mesh_info(str(DENSE), scale)
    mesh = meshes.load_trimesh(str(DENSE))
    mesh.apply_transform(np.diag([*scale, 1.0]))
    solid = mesh if mesh.is_watertight else mesh.convex_hull
    sign = 1.0 if solid.volume > 0 else -1.0
    assert info.volume == pytest.approx(abs(solid.volume), rel=1e-9)
    np.testing.assert_allclose(info.center_mass, solid.center_mass, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(
        info.inertia_unit_density,
        sign * solid.moment_inertia,
        rtol=1e-7,
        atol=1e-12 * np.abs(solid.moment_inertia).max(),
    )
    np.testing.assert_allclose(info.bounds_min, mesh.bounds[0], atol=1e-12)


def test_facts_are_stored_on_disk_and_reused_without_reading_the_mesh(
    private_cache: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    first = meshes.facts_for(str(CUBE))
    entries = list(private_cache.rglob("*.json"))
    assert len(entries) == 1 and entries[0].stem == meshes.content_key(str(CUBE))
    monkeypatch.setattr(meshes, "_FACTS", {})

    def refuse(path: str) -> meshes.MeshFacts:
        raise AssertionError("the mesh was read again instead of coming from the cache")

    monkeypatch.setattr(meshes, "read_facts", refuse)
    assert meshes.facts_for(str(CUBE)) == first


def test_the_same_bytes_under_another_name_are_read_once(
    private_cache: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    copy = tmp_path / "renamed.stl"
    copy.write_bytes(CUBE.read_bytes())
    reads: list[str] = []
    original = meshes.read_facts
    monkeypatch.setattr(meshes, "read_facts", lambda p: reads.append(p) or original(p))
    assert meshes.facts_for(str(CUBE)) == meshes.facts_for(str(copy))
    assert len(reads) == 1


def test_no_cache_leaves_no_files(private_cache: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("URDFTOOL_NO_CACHE", "1")
    meshes.facts_for(str(CUBE))
    assert not private_cache.exists()
    assert mesh_cache.cache_root() is None


def test_cache_folder_names_the_trimesh_version(private_cache: Path) -> None:
    import trimesh

    root = mesh_cache.cache_root()
    assert root is not None and root.name.endswith(f"trimesh{trimesh.__version__}")


def test_parallel_loading_matches_one_by_one(
    private_cache: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    paths = sorted(str(p) for p in (FIXTURES / "rules").glob("M00*/meshes/*") if p.stat().st_size)
    together = meshes.load_many(paths, jobs=2)
    monkeypatch.setattr(meshes, "_FACTS", {})
    monkeypatch.setenv("URDFTOOL_NO_CACHE", "1")
    alone = {p: _result(p) for p in paths}
    assert {p: _describe(v) for p, v in together.items()} == {
        p: _describe(v) for p, v in alone.items()
    }


def _result(path: str) -> meshes.MeshFacts | meshes.MeshError:
    try:
        return meshes.read_facts(path)
    except meshes.MeshError as exc:
        return exc


def _describe(value: object) -> object:
    return ("error", str(value)) if isinstance(value, meshes.MeshError) else value


def test_collada_unit_is_applied(private_cache: Path, tmp_path: Path) -> None:
    source = (FIXTURES / "rules" / "M004" / "meshes" / "cube.dae").read_text()
    millimetres = source.replace("<asset>", '<asset><unit name="millimeter" meter="0.001"/>', 1)
    path = tmp_path / "cube_mm.dae"
    path.write_text(millimetres)
    metres = meshes.mesh_info(str(FIXTURES / "rules" / "M004" / "meshes" / "cube.dae"))
    scaled = meshes.mesh_info(str(path))
    assert scaled.unit == 0.001
    assert scaled.diagonal == pytest.approx(metres.diagonal * 0.001)


def test_collada_with_entities_is_refused(private_cache: Path, tmp_path: Path) -> None:
    path = tmp_path / "evil.dae"
    path.write_text(
        '<?xml version="1.0"?><!DOCTYPE c [<!ENTITY x SYSTEM "file:///etc/passwd">]>'
        "<COLLADA>&x;</COLLADA>"
    )
    with pytest.raises(meshes.MeshError, match="entities"):
        meshes.facts_for(str(path))


@pytest.mark.skipif(ERD is None, reason="example-robot-data is a test dependency")
def test_collada_with_a_broken_material_keeps_its_geometry(private_cache: Path) -> None:
    assert ERD is not None
    foot = ERD / "anymal_b_simple_description" / "meshes" / "foot" / "anymal_foot.dae"
    facts = meshes.facts_for(str(foot))
    assert facts.faces == 4604


def test_binary_stl_with_a_solid_header_is_sniffed_as_binary(tmp_path: Path) -> None:
    data = bytearray(CUBE.read_bytes())
    data[:5] = b"solid"
    path = tmp_path / "solidworks.stl"
    path.write_bytes(bytes(data))
    fmt = sniff(str(path))
    assert (fmt.kind, fmt.faces) == ("stl-binary", 12)
    assert engines_refusing(fmt) == {}


def test_huge_binary_stl_is_refused_by_mujoco_only(tmp_path: Path) -> None:
    path = tmp_path / "scan.stl"
    faces = 200_001
    path.write_bytes(b"\0" * 80 + faces.to_bytes(4, "little") + b"\0" * (50 * faces))
    assert set(engines_refusing(sniff(str(path)))) == {"mujoco"}


def _imports_trimesh(path: Path, select: str, cache: Path) -> bool:
    code = (
        "import sys\n"
        "from urdftool.pipeline.check import CheckOptions, check_file\n"
        f"check_file({str(path)!r}, CheckOptions(select=({select!r},)))\n"
        "print('trimesh' in sys.modules)\n"
    )
    env = {**os.environ, "URDFTOOL_CACHE_DIR": str(cache)}
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env
    )
    return out.stdout.strip() == "True"


def test_checking_a_urdf_without_meshes_does_not_import_trimesh(tmp_path: Path) -> None:
    assert not _imports_trimesh(FIXTURES / "robots" / "two_link_arm.urdf", "M", tmp_path)
    assert not _imports_trimesh(FIXTURES / "rules" / "G004" / "bad.urdf", "G", tmp_path)


def test_meshes_load_trimesh_once_then_come_from_the_cache(tmp_path: Path) -> None:
    robot = FIXTURES / "rules" / "M006" / "bad.urdf"
    assert _imports_trimesh(robot, "M006", tmp_path)
    assert not _imports_trimesh(robot, "M006", tmp_path), "a warm run needs no mesh library"
