"""Scale: structural checks stay linear in the number of links; deep models stay bounded.

1. ``check --select S`` (read + structural rules) on generated chains and balanced trees
   of 1k, 10k and 100k links, each size in fresh interpreters (no heap left over from a
   smaller run), as CPU seconds of the check alone, best of two; prints the time per size
   and the 100k/10k ratio (goal: ≤ 11×, i.e. linear with a little slack).
2. A default check of a 1,000-link chain, with ``--no-dynamics`` and with the
   dynamics pass, each in a fresh interpreter, with its peak memory
   (``resource.getrusage``).

Run: ``python benchmarks/bench_scale.py [--quick]`` (``--quick`` stops at 10k links).
Prints figures; asserts nothing.
"""

from __future__ import annotations

import resource
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.scale_models import chain_urdf, tree_urdf  # noqa: E402

SIZES = (1_000, 10_000, 100_000)


_STRUCTURAL = """
import sys, time
sys.path.insert(0, {root!r})
from urdftool.pipeline.check import CheckOptions, check_file
options = CheckOptions(select=("S",))
check_file({warm!r}, options)  # modules and lazy tables loaded before the clock starts
start = time.process_time()
reports = check_file({path!r}, options)
print(time.process_time() - start, sum(len(r.diagnostics) for r in reports))
"""


def structural(folder: Path, sizes: tuple[int, ...], repeat: int = 2) -> None:
    """Each size in fresh interpreters (no heap left over from a smaller run), CPU seconds of the
    check alone (other jobs on a shared machine do not count), best of *repeat*."""
    print(f"check --select S (read + structural rules; CPU time, fresh interpreter, best of {repeat})")
    warm = folder / "warm.urdf"
    warm.write_text(chain_urdf(10, "revolute"))
    for shape, make in (("chain", chain_urdf), ("tree", tree_urdf)):
        times: dict[int, float] = {}
        for n in sizes:
            path = folder / f"{shape}_{n}.urdf"
            path.write_text(make(n, "revolute"))
            code = _STRUCTURAL.format(root=str(ROOT), warm=str(warm), path=str(path))
            runs = []
            for _ in range(repeat):
                done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                                      check=True)
                runs.append(done.stdout.split())
            times[n] = min(float(seconds) for seconds, _ in runs)
            print(f"  {shape:5} {n:>7} links: {times[n]:8.2f} s  ({runs[0][1]} findings)")
        if 100_000 in times and 10_000 in times:
            print(f"  {shape:5} 100k/10k ratio: {times[100_000] / times[10_000]:.1f}x (goal <= 11x)")
        elif 10_000 in times and 1_000 in times:
            print(f"  {shape:5} 10k/1k ratio: {times[10_000] / times[1_000]:.1f}x (goal <= 11x)")


_CHILD = """
import resource, sys, time
sys.path.insert(0, {root!r})
from urdftool.pipeline.check import CheckOptions, check_file
start = time.perf_counter()
reports = check_file({path!r}, CheckOptions(rule_options={{"dynamics": {dynamics}}}))
elapsed = time.perf_counter() - start
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
codes = sorted({{d.code for r in reports for d in r.diagnostics}})
print(f"{{elapsed:.2f}} {{peak:.0f}} {{','.join(codes)}}")
"""


def default_check(folder: Path) -> None:
    path = folder / "chain_1000.urdf"
    path.write_text(chain_urdf(1_000, "revolute"))
    print("default check of a 1,000-link revolute chain (fresh interpreter each)")
    for label, dynamics in (("--no-dynamics", False), ("with dynamics", True)):
        code = _CHILD.format(root=str(ROOT), path=str(path), dynamics=dynamics)
        done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
        if done.returncode != 0:
            print(f"  {label:14}: failed ({done.returncode}): {done.stderr.strip()[-300:]}")
            continue
        elapsed, peak, codes = [*done.stdout.strip().split(" ", 2), ""][:3]
        print(f"  {label:14}: {float(elapsed):6.2f} s, peak {peak} MiB, codes {codes or '-'}")


def main() -> None:
    quick = "--quick" in sys.argv
    with tempfile.TemporaryDirectory(prefix="urdftool-bench-") as tmp:
        default_check(Path(tmp))
        structural(Path(tmp), SIZES[:2] if quick else SIZES)
    children = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    print(f"peak memory of the largest run: {children:.0f} MiB")


if __name__ == "__main__":
    main()
