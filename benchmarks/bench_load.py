"""Load + structural check speed against the anchors of issues 2 and 22.

1. In-process, per file of corpus A (example-robot-data's 69 URDFs): urdftool's
   read + structural rules, as a ratio to yourdfpy's ``URDF.load`` without meshes
   (goal: ≤ 1.0×), the two alternating seven times per file and the best of each taken;
   and a default check (every default rule, meshes read through
   the warm disk cache), without and with the dynamics pass, as a ratio to the
   same (goal: ≤ 2× without). The figure without the dynamics pass is taken before the first
   dynamics pass of the run, as a ``check --no-dynamics`` never loads Pinocchio.
2. Cold start: ``urdftool check --select S FILE`` in a fresh interpreter, as a
   ratio to ``python -c pass`` (goal: ≤ 4×). Measured as installed, with the
   modules' bytecode cached (a pip install compiles it); when the environment
   sets ``PYTHONDONTWRITEBYTECODE`` every urdftool module is compiled again in
   every run, which is printed too.
3. ``urdftool convert`` of the Panda (ten COLLADA visuals) to MJCF, twice, each in
   a new process with the same empty disk cache: the second run reads every
   converted mesh from the cache.

Run: ``python benchmarks/bench_load.py`` (``... cold`` for the cold start alone, ``... inprocess``
for the in-process figures alone). Prints figures;
asserts nothing. On a shared machine take the figures of a quiet moment: each is the best of a few
runs; the cold start is the median of five rounds.
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.conftest import ERD, erd_urdfs  # noqa: E402
from urdftool.pipeline.check import CheckOptions, check_file  # noqa: E402

REPEAT = 3
#: rounds of yourdfpy's load and urdftool's structural check, alternating, per file
INTERLEAVED = 7


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
    default = CheckOptions()
    static = CheckOptions(rule_options={"dynamics": False})
    ours, theirs, full, nodyn = [], [], [], []
    failed = []
    for path in files:
        def load(p: str = path) -> None:
            yourdfpy.URDF.load(p, build_scene_graph=False, load_meshes=False,
                               build_collision_scene_graph=False, load_collision_meshes=False)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                load()
        except Exception:  # yourdfpy raises on some files (e.g. a robot without a name)
            failed.append(path)
            continue
        # the two loads alternate, so that what else runs on the machine falls on both alike
        theirs_time = ours_time = float("inf")
        for _ in range(INTERLEAVED):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                theirs_time = min(theirs_time, best_of(load, 1))
            ours_time = min(ours_time, best_of(lambda p=path: check_file(p, options), 1))
        theirs.append(theirs_time)
        ours.append(ours_time)
        check_file(path, static)  # fills the mesh cache
        # the best of as many runs as yourdfpy's load had: the same estimator on both sides
        nodyn.append(best_of(lambda p=path: check_file(p, static), INTERLEAVED))
    # The dynamics pass in a loop of its own, after every other figure: a `check --no-dynamics`
    # never loads Pinocchio, and a file checked right after the dynamics pass of another ran
    # 5-10 % slower (the heap and caches that pass leaves), which no such run pays.
    for path in files:
        if path in failed:
            continue
        check_file(path, default)
        full.append(best_of(lambda p=path: check_file(p, default)))
    ratios = [a / b for a, b in zip(ours, theirs, strict=True)]
    print(f"corpus A: {len(files)} files ({len(failed)} that yourdfpy cannot load left out)")
    print(f"  urdftool load+structural check: total {sum(ours) * 1e3:.1f} ms")
    print(f"  yourdfpy URDF.load (no meshes): total {sum(theirs) * 1e3:.1f} ms")
    print(f"  ratio of totals: {sum(ours) / sum(theirs):.2f}x   (goal <= 1.0x)")
    print(f"  per-file ratio: median {statistics.median(ratios):.2f}x, max {max(ratios):.2f}x")
    for label, times in (("--no-dynamics", nodyn), ("with dynamics", full)):
        goal = "   (goal <= 2x)" if label == "--no-dynamics" else ""
        print(f"  default check, {label}, warm mesh cache: total {sum(times) * 1e3:.1f} ms, "
              f"{sum(times) / sum(theirs):.2f}x yourdfpy{goal}")


def _run(command: list[str], env: dict[str, str]) -> None:
    subprocess.run(command, capture_output=True, env=env)


def cold_start(rounds: int = 5) -> None:
    """The cold-start ratio, *rounds* times: each round is the best of 15 runs of each command, the
    two commands alternating so that load from other jobs falls on both; the median is the figure."""
    target = erd_urdfs()[0]
    urdftool = [sys.executable, "-m", "urdftool", "check", "--select", "S", target]
    baseline = [sys.executable, "-c", "pass"]
    print(f"cold start, one file (urdftool check --select S {os.path.basename(target)}):")
    with tempfile.TemporaryDirectory(prefix="urdftool-pyc-") as pyc:
        installed = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
        installed["PYTHONPYCACHEPREFIX"] = pyc
        for label, env in (("bytecode cached", installed),
                           ("no bytecode", {**os.environ, "PYTHONDONTWRITEBYTECODE": "1"})):
            subprocess.run(urdftool, capture_output=True, env=env)  # writes the bytecode
            ratios = []
            for _ in range(rounds):
                ours = base = float("inf")
                for _ in range(15):
                    ours = min(ours, best_of(lambda e=env: _run(urdftool, e), 1))
                    base = min(base, best_of(lambda e=env: _run(baseline, e), 1))
                ratios.append(ours / base)
                print(f"  {label:15}: urdftool check {ours * 1e3:.0f} ms; "
                      f"python -c pass {base * 1e3:.0f} ms; ratio {ours / base:.2f}x", flush=True)
            goal = "   (goal <= 4x)" if label == "bytecode cached" else ""
            print(f"  {label:15}: median of {rounds} rounds {statistics.median(ratios):.2f}x{goal}")


def convert_twice() -> None:
    assert ERD is not None, "example-robot-data is needed"
    panda = ERD / "panda_description" / "urdf" / "panda.urdf"
    with tempfile.TemporaryDirectory(prefix="urdftool-convert-") as tmp:
        env = {**os.environ, "URDFTOOL_CACHE_DIR": os.path.join(tmp, "cache")}
        times = []
        for run in range(3):
            command = [sys.executable, "-m", "urdftool", "convert", str(panda), "-q",
                       "-o", os.path.join(tmp, f"out{run}", "panda.xml")]
            start = time.perf_counter()
            subprocess.run(command, capture_output=True, env=env, check=True)
            times.append(time.perf_counter() - start)
    print("urdftool convert of the Panda (10 COLLADA meshes) to MJCF, a new process each time:")
    print(f"  empty cache {times[0]:.2f} s; then {times[1]:.2f} s and {times[2]:.2f} s "
          f"(cache hits: {times[0] / min(times[1:]):.1f}x faster)")


if __name__ == "__main__":
    if sys.argv[1:] == ["cold"]:  # only the cold-start figure: python benchmarks/bench_load.py cold
        cold_start()
    elif sys.argv[1:] == ["inprocess"]:  # only the in-process figures
        in_process()
    else:
        in_process()
        cold_start()
        convert_twice()
