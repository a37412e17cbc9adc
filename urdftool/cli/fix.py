"""``check --fix``, ``--unsafe-fixes``, ``--diff`` and ``--fix-only``."""

from __future__ import annotations

import sys
from collections import Counter
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, TypeVar

import click

from urdftool.cli.common import EXIT_FINDINGS, EXIT_OK, InputProblem
from urdftool.diagnostics import Report
from urdftool.lazy import LazyModule
from urdftool.pipeline.check import CheckOptions

if TYPE_CHECKING:
    from urdftool.export import write as export_write
    from urdftool.pipeline import fix
    from urdftool.pipeline.fix import FixResult
else:  # the fixer (difflib, the exporters' atomic writes) is imported when a fix flag is given
    export_write = LazyModule("urdftool.export.write")
    fix = LazyModule("urdftool.pipeline.fix")

F = TypeVar("F", bound=Callable[..., object])


def fix_options(func: F) -> F:
    decorators = [
        click.option("--fix", is_flag=True,
                     help="Apply the safe fixes to the files (the .xacro where a value was written), then "
                     "report what is left."),
        click.option("--unsafe-fixes", is_flag=True,
                     help="With --fix, --diff or --fix-only: apply the unsafe fixes too "
                     "(they change physics)."),
        click.option("--diff", "show_diff", is_flag=True,
                     help="Print the fixes as a unified diff (applies with `patch -p0` or `git apply -p0`) "
                     "and write nothing; exit 1 when there is something to fix."),
        click.option("--fix-only", is_flag=True,
                     help="Apply the fixes and report only what was fixed "
                     "(exit 0 unless a file was refused)."),
    ]
    for decorator in reversed(decorators):
        func = decorator(func)
    return func


def run_fixes(groups: Sequence[tuple[CheckOptions, Sequence[str]]], unsafe: bool, write: bool, fix_only: bool,
              jobs: int) -> Report:
    """Fix each group of files; with ``--diff`` or ``--fix-only`` print and exit, else return the report."""
    results: list[FixResult] = []
    try:
        for options, paths in groups:
            results.append(fix.fix_files(list(paths), options, unsafe=unsafe, write=write, jobs=jobs))
    except export_write.OutputError as exc:
        raise InputProblem(str(exc)) from exc
    refused = [path for result in results for path in result.refused]
    for path in refused:
        click.echo(f"urdftool: {path}: not fixed: the fixed text would not parse", err=True)
    fixed = [d for result in results for d in result.fixed]
    if not write:
        diff = "".join(result.diff() for result in results)
        sys.stdout.write(diff)
        click.echo(f"urdftool: would fix {_describe(fixed)}", err=True)
        sys.exit(EXIT_FINDINGS if diff or refused else EXIT_OK)
    files = {path for result in results for path in result.changes}
    click.echo(f"urdftool: fixed {_describe(fixed)} in {len(files)} file(s)", err=True)
    if fix_only:
        for diagnostic in fixed:
            click.echo(f"{diagnostic.location}: {diagnostic.code} [{diagnostic.name}] "
                       f"{diagnostic.fix.message if diagnostic.fix else ''}")
        sys.exit(EXIT_FINDINGS if refused else EXIT_OK)
    return Report(tuple(f for result in results for f in result.report.files))


def _describe(fixed: Sequence[object]) -> str:
    counts = Counter(getattr(d, "code", "?") for d in fixed)
    detail = ", ".join(f"{code} ×{n}" for code, n in sorted(counts.items()))
    return f"{len(fixed)} finding(s)" + (f" ({detail})" if detail else "")
