"""MJCF conversion time against MuJoCo's own URDF import, and what each one loads.

For every URDF of example-robot-data (corpus A) and the pybullet_data robots:

* MuJoCo as shipped: ``mujoco.MjModel.from_xml_path(urdf)``;
* MuJoCo from an absolute-path URDF: a copy with every ``package://`` URI
  rewritten to the file it names (MuJoCo cannot resolve packages);
* urdftool: read the file and export MJCF (assets converted in memory, nothing
  written), best of three runs with mesh conversion caches cleared.

Prints the load counts and, over the files both load, the ratio of urdftool's
conversion time to MuJoCo's compile time (the anchor). Run:
``python benchmarks/bench_mjcf.py``.
"""

from __future__ import annotations

import glob
import re
import sys
import tempfile
import time
from pathlib import Path

import mujoco

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from tests.conftest import ERD, pybullet_robots
from urdftool.export import ExportOptions
from urdftool.export.mjcf import build
from urdftool.export.mjcf_assets import _convert_cached
from urdftool.parse import read

_PACKAGE = re.compile(r"package://([^/\"']+)/")


def mujoco_loads(path: str) -> tuple[bool, float]:
    start = time.perf_counter()
    try:
        mujoco.MjModel.from_xml_path(path)
    except Exception:
        return False, time.perf_counter() - start
    return True, time.perf_counter() - start


def absolute_copy(path: str, folder: str) -> str:
    """A copy of *path* beside the original with ``package://NAME/`` made absolute (cmeel share)."""
    share = ERD.parent.parent if ERD is not None else Path("/")
    text = Path(path).read_text(encoding="utf-8", errors="replace")
    text = _PACKAGE.sub(lambda m: f"{share / m.group(1)}/", text)
    out = Path(folder) / (Path(path).stem + "_abs.urdf")
    # MuJoCo resolves relative mesh paths against the model's folder: keep the original's.
    text = re.sub(r'filename="(?!/)([^"]+)"', lambda m: f'filename="{Path(path).parent / m.group(1)}"', text)
    out.write_text(text)
    return str(out)


def urdftool_time(path: str) -> tuple[bool, float]:
    best = float("inf")
    ok = False
    for _ in range(3):
        _convert_cached.cache_clear()
        start = time.perf_counter()
        loaded = read(path)[0]
        if loaded.robot is None or not loaded.robot.links:
            return False, time.perf_counter() - start
        _, _, diagnostics = build(loaded.robot, None, ExportOptions(repair_inertia=True))
        best = min(best, time.perf_counter() - start)
        ok = not any(d.severity.value == "error" for d in diagnostics)
    return ok, best


def run(name: str, files: list[str]) -> None:
    shipped = absolute = ours = 0
    ours_time = mujoco_time = 0.0
    with tempfile.TemporaryDirectory() as folder:
        for path in files:
            shipped += mujoco_loads(path)[0]
            loads, mj_seconds = mujoco_loads(absolute_copy(path, folder))
            absolute += loads
            converted, seconds = urdftool_time(path)
            ours += converted
            if loads and converted:
                ours_time += seconds
                mujoco_time += mj_seconds
    print(f"{name}: {len(files)} URDF files")
    print(f"  MuJoCo loads as shipped:            {shipped}")
    print(f"  MuJoCo loads with absolute paths:   {absolute}")
    print(f"  urdftool converts (--repair-inertia): {ours}")
    if mujoco_time > 0:
        print(f"  conversion time / MuJoCo compile time (files both load): "
              f"{ours_time:.2f} s / {mujoco_time:.2f} s = {ours_time / mujoco_time:.2f}")


def main() -> None:
    assert ERD is not None, "example-robot-data is needed"
    run("example-robot-data (corpus A)", sorted(glob.glob(str(ERD / "**" / "*.urdf"), recursive=True)))
    run("pybullet_data robots", pybullet_robots())


if __name__ == "__main__":
    main()
