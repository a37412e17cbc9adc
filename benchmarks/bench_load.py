"""Load + structural check speed against the anchors of issue 2.

1. In-process, per file of corpus A (example-robot-data's 69 URDFs): urdftool's
   read + structural rules, as a ratio to yourdfpy's ``URDF.load`` without meshes
   (goal: ≤ 1.0×).
2. Cold start: ``urdftool check FILE`` in a fresh interpreter, as a ratio to
   ``python -c pass`` (goal: ≤ 6×).

Run: ``python benchmarks/bench_load.py``. Prints figures; asserts nothing.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from tests.conftest import erd_urdfs
from urdftool.pipeline.check import CheckOptions, check_file

REPEAT = 3


def best_of(func, repeat: int = REPEAT) -> float:  # type: ignore[no-untyped-def]
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        func()
        times.append(time.perf_counter() - start)
    return min(times)


def in_process() -> None:
    import yourdfpy

    files = erd_urdfs()
    options = CheckOptions(select=("S", "X"))
    ours, theirs = [], []
    failed = []
    for path in files:
        def load(p: str = path) -> None:
            yourdfpy.URDF.load(p, build_scene_graph=False, load_meshes=False,
                               build_collision_scene_graph=False, load_collision_meshes=False)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                theirs_time = best_of(load)
        except Exception:  # yourdfpy raises on some files (e.g. a robot without a name)
            failed.append(path)
            continue
        theirs.append(theirs_time)
        ours.append(best_of(lambda p=path: check_file(p, options)))
    ratios = [a / b for a, b in zip(ours, theirs, strict=True)]
    print(f"corpus A: {len(files)} files ({len(failed)} that yourdfpy cannot load left out)")
    print(f"  urdftool load+structural check: total {sum(ours) * 1e3:.1f} ms")
    print(f"  yourdfpy URDF.load (no meshes): total {sum(theirs) * 1e3:.1f} ms")
    print(f"  ratio of totals: {sum(ours) / sum(theirs):.2f}x   (goal <= 1.0x)")
    print(f"  per-file ratio: median {statistics.median(ratios):.2f}x, max {max(ratios):.2f}x")


def cold_start() -> None:
    target = erd_urdfs()[0]
    urdftool = [sys.executable, "-m", "urdftool", "check", "--select", "S", target]
    baseline = [sys.executable, "-c", "pass"]
    ours = best_of(lambda: subprocess.run(urdftool, capture_output=True), 5)
    base = best_of(lambda: subprocess.run(baseline, capture_output=True), 5)
    print("cold start, one file:")
    print(f"  urdftool check: {ours * 1e3:.0f} ms; python -c pass: {base * 1e3:.0f} ms")
    print(f"  ratio: {ours / base:.1f}x   (goal <= 6x)")


if __name__ == "__main__":
    in_process()
    cold_start()
