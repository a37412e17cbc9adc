"""What the dynamics pass adds to ``urdftool check`` on corpus A (goal: ≤ 20 %).

Corpus A is example-robot-data's 69 URDFs. Two measurements, each the best of
``REPEAT`` runs:

1. In-process: ``check_file`` on every file with every rule, with the dynamics
   pass off and on (Pinocchio imported beforehand, as in a long-lived process).
2. Command line: ``urdftool check DIR`` in a fresh interpreter, with
   ``--no-dynamics`` and without; this includes the cost of importing Pinocchio.

Run: ``python benchmarks/bench_dynamics.py``. Prints figures; asserts nothing.
"""

from __future__ import annotations

import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from tests.conftest import ERD, erd_urdfs
from urdftool.pipeline.check import CheckOptions, check_file

REPEAT = 3
GOAL = 1.20


def best_of(func: Callable[[], object], repeat: int = REPEAT) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        func()
        times.append(time.perf_counter() - start)
    return min(times)


def in_process(files: list[str]) -> tuple[float, float]:
    import pinocchio  # noqa: F401  (a long-lived process has paid for it already)

    def run(dynamics: bool) -> None:
        options = CheckOptions(rule_options={"dynamics": dynamics})
        for path in files:
            check_file(path, options)

    return best_of(lambda: run(False)), best_of(lambda: run(True))


def command_line(files: list[str]) -> tuple[float, float]:
    def run(*extra: str) -> None:
        subprocess.run([sys.executable, "-m", "urdftool", "check", "-q", *extra, *files],
                       capture_output=True, check=False)

    return best_of(lambda: run("--no-dynamics")), best_of(lambda: run())


def report(label: str, static: float, dynamic: float) -> None:
    ratio = dynamic / static
    verdict = "meets" if ratio <= GOAL else "misses"
    print(f"{label}: static {static:.2f} s, with dynamics {dynamic:.2f} s, "
          f"ratio {ratio:.3f} ({verdict} the goal of {GOAL:.2f})")


def main() -> None:
    files = erd_urdfs()
    print(f"corpus A: {len(files)} URDFs from {ERD}")
    report("in-process   ", *in_process(files))
    report("command line ", *command_line(files))


if __name__ == "__main__":
    main()
