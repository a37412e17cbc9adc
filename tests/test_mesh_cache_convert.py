"""convert reuses the disk mesh cache across processes: COLLADA meshes are converted once."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import ERD, SEEDS
from urdftool.export.mjcf_assets import PARTS_KIND, _pack_parts, _unpack_parts

RRBOT = SEEDS / "gazebo_ros_demos" / "rrbot_description" / "urdf" / "rrbot.xacro"  # a COLLADA Hokuyo


def convert(out: Path, cache: Path) -> None:
    env = dict(os.environ, URDFTOOL_CACHE_DIR=str(cache))
    result = subprocess.run([sys.executable, "-m", "urdftool", "convert", str(RRBOT), "-o", str(out), "-q"],
                            capture_output=True, text=True, env=env, timeout=300, check=False)
    assert result.returncode == 0, result.stderr


def test_a_second_convert_reads_the_converted_mesh_from_the_cache(tmp_path: Path) -> None:
    cache = tmp_path / "cache"
    convert(tmp_path / "first" / "rrbot.xml", cache)
    # the Hokuyo is a visual of two colours: stored once as its colour split (docs/mjcf.md)
    blobs = [p for p in cache.rglob("*") if p.is_file() and PARTS_KIND in p.parts]
    assert len(blobs) == 1, "the COLLADA conversion was not stored"
    written = {p.name: p.read_bytes() for p in (tmp_path / "first" / "assets").iterdir()}
    parts = _unpack_parts(blobs[0].read_bytes())
    assert len(parts) == 2 and sorted(data for _, data, _ in parts) == sorted(written.values())
    # Replace the stored conversion: a second run in a new process must use it as it is.
    marker = b"\0" * 80 + (0).to_bytes(4, "little")  # a valid, empty binary STL
    blobs[0].write_bytes(_pack_parts(((None, marker, ".stl"), ((1, 2, 3, 255), marker + b"\0", ".stl"))))
    convert(tmp_path / "second" / "rrbot.xml", cache)
    again = [p.read_bytes() for p in (tmp_path / "second" / "assets").iterdir()]
    assert marker in again and marker + b"\0" in again


def _convert_in_new_process(model: Path, out: Path, cache: Path) -> list[str]:
    """``urdftool convert`` in a fresh interpreter; the heavy modules it imported."""
    script = (
        "import json, sys\n"
        "from urdftool.cli import main\n"
        "try:\n"
        f"    main(['convert', {str(model)!r}, '-o', {str(out)!r}, '-q'])\n"
        "except SystemExit as exc:\n"
        "    assert exc.code == 0, exc.code\n"
        "print(json.dumps(sorted(m for m in ('trimesh', 'collada', 'scipy') if m in sys.modules)))\n"
    )
    env = dict(os.environ, URDFTOOL_CACHE_DIR=str(cache))
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env,
                          timeout=300, check=False)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.mark.skipif(ERD is None, reason="example-robot-data is a test dependency")
def test_a_second_convert_of_the_panda_converts_no_collada_mesh(tmp_path: Path) -> None:
    """The Panda's ten COLLADA visuals are converted by the first process only (split by colour;
    a file of one colour as the whole mesh): the second reads every one from the disk cache, so
    it never even imports the mesh library, and writes the same bytes."""
    assert ERD is not None
    panda = ERD / "panda_description" / "urdf" / "panda.urdf"
    cache = tmp_path / "cache"
    first = _convert_in_new_process(panda, tmp_path / "first" / "panda.xml", cache)
    assert "trimesh" in first
    stored = [p for p in cache.rglob("*") if p.is_file() and "converted" in p.parts]
    assert len([p for p in stored if PARTS_KIND in p.parts]) == 10
    assert len([p for p in stored if "mjcf.stl" in p.parts]) == 2  # link1 and link2: one colour each
    second = _convert_in_new_process(panda, tmp_path / "second" / "panda.xml", cache)
    assert second == []
    for name in ("first", "second"):
        assert (tmp_path / name / "panda.xml").is_file()
    assert (tmp_path / "first" / "panda.xml").read_text() == (tmp_path / "second" / "panda.xml").read_text()
    written = {p.name: p.read_bytes() for p in (tmp_path / "first" / "assets").iterdir()}
    again = {p.name: p.read_bytes() for p in (tmp_path / "second" / "assets").iterdir()}
    assert written == again
    assert len(written) >= 10
