"""``urdftool check PATH...``."""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence

import click

from urdftool.check import check_files, default_jobs
from urdftool.cli.common import (
    InputProblem,
    build_options,
    input_error,
    is_terminal,
    model_options,
    selection_options,
)
from urdftool.cli.output import emit_report, exit_code, output_options
from urdftool.diagnostics import Report
from urdftool.discover import expand_paths
from urdftool.parse import InputError, detect_format

#: a progress bar is shown on a terminal from this many files on
PROGRESS_FROM = 4


@click.command("check")
@click.argument("paths", nargs=-1, required=True, type=click.Path())
@model_options
@selection_options
@output_options  # --format, -o/--output-file, --color, --exit-zero (urdftool/cli/output.py)
@click.option("--strict", is_flag=True, help="Warnings fail too (exit 1).")
@click.option("-j", "--jobs", type=click.IntRange(0, 64), default=1, show_default=True,
              help="Worker processes; 0 picks one per core.")
@click.option("-q", "--quiet", is_flag=True, help="Text output: errors and the summary only.")
@click.option(
    "--model", "model_name", help="For files with several models (SDF worlds): check only this one."
)
@click.option(
    "--no-dynamics", is_flag=True, help="Skip the dynamics pass (Pinocchio: mass matrix, gravity torques)."
)
@click.option(
    "--sim", is_flag=True, help="Also run the smoke simulation (runtime rules R; see `urdftool sim`)."
)
@click.option("--engine", type=click.Choice(["mujoco", "pybullet", "all"]), default="all", show_default=True,
              help="With --sim: the engine(s) to simulate in.")
def check_command(
    paths: Sequence[str],
    xacro_args: Sequence[str],
    packages: Sequence[str],
    package_paths: Sequence[str],
    select: Sequence[str],
    ignore: Sequence[str],
    fmt: str,
    strict: bool,
    jobs: int,
    quiet: bool,
    output: str | None,
    model_name: str | None,
    no_dynamics: bool = False,
    sim: bool = False,
    engine: str = "all",
    color: str = "auto",
    exit_zero: bool = False,
) -> None:
    """Load each model (files, or directories searched recursively) and report diagnostics."""
    from urdftool.dynamics.sim import engine_names, rule_options_for
    from urdftool.dynamics.sim_scene import SimOptions

    simulation = rule_options_for(SimOptions(engine_names(engine))) if sim else {}
    options = build_options(xacro_args, packages, package_paths, select, ignore, dynamics=not no_dynamics,
                            **simulation)
    for path in paths:
        if not os.path.exists(path):
            raise InputProblem(f"{path}: no such file or directory")
        if os.path.isfile(path) and detect_format(path) is None:
            raise InputProblem(
                f"{path}: unknown format (expected .urdf, .xacro, .urdf.xacro, .sdf or .world)"
            )
    files = expand_paths(list(paths), options.resolver())
    if not files:
        raise InputProblem("no robot descriptions found in " + ", ".join(paths))
    workers = jobs or default_jobs()
    progress = None
    if is_terminal() and len(files) >= PROGRESS_FROM and not quiet:
        bar = click.progressbar(length=len(files), label="checking", file=sys.stderr)
        bar.__enter__()

        def progress(done: int, total: int) -> None:
            bar.update(1)
            if done == total:
                bar.__exit__(None, None, None)

    try:
        report = check_files(files, options, jobs=workers, progress=progress)
    except InputError as exc:  # a file found in a directory that cannot be read at all
        raise input_error(exc) from exc
    if model_name is not None:
        report = Report(tuple(f for f in report.files if f.robot == model_name))
        if not report.files:
            raise InputProblem(f"no model named '{model_name}' in " + ", ".join(paths))
    emit_report(report, fmt, output, color, quiet, inputs=files)
    sys.exit(exit_code(report, strict, exit_zero))
