"""Mesh-check speed against the anchor of issue 3: Pinocchio's ``buildGeomFromUrdf``.

On example-robot-data's URDFs that Pinocchio can load (67 of 69), each timed as
a fresh process, wall clock, including interpreter start-up:

* anchor: ``pinocchio.buildModelFromUrdf`` + ``buildGeomFromUrdf`` for the
  collision and the visual geometry of every file (it loads every mesh with
  assimp and builds its collision structure);
* cold: ``urdftool check --select M`` on all the files in one call, with an
  empty mesh cache (every mesh is read with trimesh; goal ≤ 0.5×);
* warm: the same call again, the persistent mesh cache filled (goal ≤ 0.1×).

Run: ``python benchmarks/bench_meshes.py``. Prints figures; asserts nothing.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.conftest import ERD, erd_urdfs  # noqa: E402

PINOCCHIO = """
import sys
import pinocchio as pin
package_dir = sys.argv[1]
for path in sys.argv[2:]:
    model = pin.buildModelFromUrdf(path)
    for kind in (pin.GeometryType.COLLISION, pin.GeometryType.VISUAL):
        pin.buildGeomFromUrdf(model, path, kind, package_dirs=[package_dir])
"""

PINOCCHIO_PROBE = """
import sys
import pinocchio as pin
for path in sys.argv[2:]:
    try:
        model = pin.buildModelFromUrdf(path)
        for kind in (pin.GeometryType.COLLISION, pin.GeometryType.VISUAL):
            pin.buildGeomFromUrdf(model, path, kind, package_dirs=[sys.argv[1]])
        print(path)
    except Exception:
        pass
"""


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def timed(
    command: list[str], env: dict[str, str] | None = None
) -> tuple[float, float, subprocess.CompletedProcess[str]]:
    """Wall-clock and CPU seconds (the process and its workers) of *command*.

    CPU time is printed too because the machine may be shared: wall clock then
    measures the other load as much as the work.
    """
    cpu = _children_cpu()
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True, env=env)
    return time.perf_counter() - start, _children_cpu() - cpu, done


def main() -> None:
    assert ERD is not None, "example-robot-data is needed"
    package_dir = str(ERD.parent.parent)
    probe = subprocess.run(
        [sys.executable, "-c", PINOCCHIO_PROBE, package_dir, *erd_urdfs()],
        capture_output=True,
        text=True,
        check=True,
    )
    files = probe.stdout.split()
    print(f"example-robot-data: {len(files)} of {len(erd_urdfs())} URDFs load in Pinocchio")

    anchor, anchor_cpu, done = timed([sys.executable, "-c", PINOCCHIO, package_dir, *files])
    assert done.returncode == 0, done.stderr[-2000:]
    print(
        f"  Pinocchio buildGeomFromUrdf (collision + visual): {anchor:.2f} s wall, "
        f"{anchor_cpu:.2f} s CPU"
    )

    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "URDFTOOL_CACHE_DIR": cache}
        env.pop("URDFTOOL_NO_CACHE", None)
        command = [sys.executable, "-m", "urdftool", "check", "--select", "M", "-q", *files]
        cold, cold_cpu, done = timed(command, env)
        assert done.returncode in (0, 1), done.stderr[-2000:]
        warm, warm_cpu, _ = timed(command, env)
        entries = sum(1 for _ in Path(cache).rglob("*.json"))
    print(
        f"  urdftool check --select M, cold cache: {cold:.2f} s wall, {cold_cpu:.2f} s CPU "
        f"({entries} mesh files cached)"
    )
    print(f"  urdftool check --select M, warm cache: {warm:.2f} s wall, {warm_cpu:.2f} s CPU")
    print(
        f"  cold ratio: {cold / anchor:.3f}x wall, {cold_cpu / anchor_cpu:.3f}x CPU"
        "   (goal <= 0.5x)"
    )
    print(
        f"  warm ratio: {warm / anchor:.3f}x wall, {warm_cpu / anchor_cpu:.3f}x CPU"
        "   (goal <= 0.1x)"
    )
    print(
        f"  ({os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}; mesh files are read in "
        "parallel worker processes)"
    )


if __name__ == "__main__":
    main()
