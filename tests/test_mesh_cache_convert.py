"""convert reuses the disk mesh cache across processes: COLLADA meshes are converted once."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from tests.conftest import SEEDS

RRBOT = SEEDS / "gazebo_ros_demos" / "rrbot_description" / "urdf" / "rrbot.xacro"  # a COLLADA Hokuyo


def convert(out: Path, cache: Path) -> None:
    env = dict(os.environ, URDFTOOL_CACHE_DIR=str(cache))
    result = subprocess.run([sys.executable, "-m", "urdftool", "convert", str(RRBOT), "-o", str(out), "-q"],
                            capture_output=True, text=True, env=env, timeout=300, check=False)
    assert result.returncode == 0, result.stderr


def test_a_second_convert_reads_the_converted_mesh_from_the_cache(tmp_path: Path) -> None:
    cache = tmp_path / "cache"
    convert(tmp_path / "first" / "rrbot.xml", cache)
    blobs = [p for p in cache.rglob("*") if p.is_file() and "converted" in p.parts]
    assert blobs, "the COLLADA conversion was not stored"
    written = {p.name: p.read_bytes() for p in (tmp_path / "first" / "assets").iterdir()}
    assert any(data == blobs[0].read_bytes() for data in written.values())
    # Replace the stored conversion: a second run in a new process must use it as it is.
    marker = b"\0" * 80 + (0).to_bytes(4, "little")  # a valid, empty binary STL
    blobs[0].write_bytes(marker)
    convert(tmp_path / "second" / "rrbot.xml", cache)
    again = [p.read_bytes() for p in (tmp_path / "second" / "assets").iterdir()]
    assert marker in again
