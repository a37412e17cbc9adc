"""Running one fuzz case in-process: check and convert, and the invariants that must hold.

Invariants: no exception escapes, no ``internal-error`` (S000) diagnostic, each
run ends within its time budget, and nothing outside the case's temporary
folder changes (the seed's folder is fingerprinted before and after).
"""

from __future__ import annotations

import contextlib
import os
import shutil
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from tests.fuzz.mutations import Case

#: seconds a single case may take (check + two conversions)
TIME_BUDGET = 20.0
#: Wall-clock ceiling, as a multiple of TIME_BUDGET. The budget is CPU time: a long run niced
#: beside other work waits for a core for minutes without any case being slow (the 100k run of
#: 2026-11-25 saw 150 s of wall time for a 0.35 s case); a case that blocks without computing
#: (a FIFO read) still trips this ceiling.
WALL_FACTOR = 10.0


def fingerprint(folder: Path) -> dict[str, tuple[int, int]]:
    return {
        str(p): (p.stat().st_size, p.stat().st_mtime_ns) for p in sorted(folder.rglob("*")) if p.is_file()
    }


def stage(case: Case, workdir: Path) -> Path:
    """Copy the seed's folder (meshes, includes) into *workdir* and write the mutated input there."""
    for sibling in case.seed.parent.iterdir():
        if sibling.is_file() and sibling.stat().st_size < 2_000_000:
            shutil.copy2(sibling, workdir / sibling.name)
    target = workdir / case.seed.name
    target.write_bytes(case.data)
    return target


def run_case(case: Case, workdir: Path) -> list[str]:
    """Check and convert *case*; return the broken invariants (empty when all hold)."""
    from urdftool.api import ConversionRefused, LoadError, load, to_mjcf, to_urdf
    from urdftool.export.write import OutputError
    from urdftool.parse import InputError
    from urdftool.pipeline.check import CheckOptions, check_file

    problems: list[str] = []
    before = fingerprint(case.seed.parent)
    path = stage(case, workdir)
    start, cpu_start = time.monotonic(), time.process_time()
    try:
        reports = check_file(str(path), CheckOptions(rule_options={"dynamics": False}))
        for report in reports:
            for d in report.diagnostics:
                if d.code == "S000":
                    problems.append(f"internal error: {d.message}")
    except InputError:
        pass
    except BaseException as exc:
        problems.append(f"check raised {type(exc).__name__}: {exc}")
    try:
        robot = load(str(path))
    except LoadError as exc:  # a world of several models asks for one: convert its first
        robot = _first_of(exc.models, path, load, LoadError)
    except (ValueError, FileNotFoundError):
        robot = None
    except BaseException as exc:
        problems.append(f"load raised {type(exc).__name__}: {exc}")
        robot = None
    if robot is not None:
        for convert, out in ((to_mjcf, "out.xml"), (to_urdf, "out.urdf")):
            try:
                convert(robot, workdir / "out" / out)  # type: ignore[operator]
            except (ConversionRefused, OutputError):
                pass
            except BaseException as exc:
                problems.append(f"{convert.__name__} raised {type(exc).__name__}: {exc}")
    elapsed, cpu = time.monotonic() - start, time.process_time() - cpu_start
    if cpu > TIME_BUDGET or elapsed > WALL_FACTOR * TIME_BUDGET:
        problems.append(f"took {cpu:.1f} s of CPU, {elapsed:.1f} s in all (budget {TIME_BUDGET} s of CPU, "
                        f"{WALL_FACTOR * TIME_BUDGET:.0f} s in all)")
    if fingerprint(case.seed.parent) != before:
        problems.append(f"files changed outside the temporary folder, in {case.seed.parent}")
    return problems


def _first_of(models: tuple[str, ...], path: Path, load: Any, refused: type[Exception]) -> Any:
    """The first of *models* (the names a file of several holds), loaded by its name; ``None`` if
    there are none or it does not load."""
    try:
        return load(str(path), model=models[0]) if models else None
    except (refused, ValueError, FileNotFoundError):
        return None


def isolated_env() -> dict[str, str]:
    """Environment overrides that keep caches inside the temporary folder."""
    return {"URDFTOOL_NO_CACHE": "1"}


@contextlib.contextmanager
def applied_env(overrides: dict[str, str]) -> Iterator[None]:
    """*overrides* in the environment for the block, the variables as they were after it (a
    fuzz case must not turn the mesh cache off for the tests that run after it in one worker)."""
    before = {name: os.environ.get(name) for name in overrides}
    os.environ.update(overrides)
    try:
        yield
    finally:
        for name, value in before.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value
