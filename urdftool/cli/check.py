"""``urdftool check PATH...``."""

from __future__ import annotations

import dataclasses
import os
import sys
from collections.abc import Sequence
from typing import TYPE_CHECKING

import click
from click.core import ParameterSource

from urdftool.budgets import command_line
from urdftool.cli.common import (
    EXIT_OK,
    InputProblem,
    build_options,
    input_error,
    is_terminal,
    model_options,
    selection_options,
)
from urdftool.cli.fix import fix_options, run_fixes
from urdftool.cli.output import emit_report, exit_code, explain_verdict_exit, output_options
from urdftool.diagnostics import FileReport, Report
from urdftool.lazy import LazyModule
from urdftool.parse import InputError, detect_format
from urdftool.pipeline.check import CheckOptions, check_files, default_jobs
from urdftool.pipeline.discover import expand_paths
from urdftool.pipeline.model_names import no_such_model
from urdftool.pipeline.settings import Overrides, Settings, SettingsError, group_by_settings, resolve
from urdftool.rules import UnknownSelector
from urdftool.targets import TARGETS, UnknownTarget, parse_targets

if TYPE_CHECKING:
    from urdftool.export import write
    from urdftool.facts import simulation
    from urdftool.facts.simulation import options as simulation_options
    from urdftool.pipeline import baseline
else:
    # Each is needed only by the flags that name it (--write-baseline, --sim, --baseline): a plain
    # check does not import the exporters' package, the simulation options or JSON.
    write = LazyModule("urdftool.export.write")
    simulation = LazyModule("urdftool.facts.simulation")
    simulation_options = LazyModule("urdftool.facts.simulation.options")
    baseline = LazyModule("urdftool.pipeline.baseline")

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
@click.option("--extend-select", multiple=True, help="Rules to add to the selection (comma-separated).")
@click.option("--isolated", is_flag=True, help="Ignore urdftool.toml and pyproject.toml settings.")
@click.option("--no-suppressions", is_flag=True, help="Ignore <!-- urdftool: ignore[...] --> comments.")
@click.option("--baseline", "baseline_file", type=click.Path(dir_okay=False),
              help="Report only findings not recorded in this baseline file.")
@click.option("--write-baseline", type=click.Path(dir_okay=False),
              help="Record every finding in this baseline file (exit 0) and report nothing.")
@click.option("--target", "target_names", multiple=True, metavar="T[,T...]",
              help="Also report what these consumers will do with the URDF or xacro file: "
              + ", ".join(TARGETS) + " or all (rules T; SDF files are read by SDFormat, not these tables).")
@click.option("--exclude", multiple=True, metavar="PATTERN[,PATTERN...]",
              help="Leave files and folders matching these patterns out of the directories walked "
              "(as .gitignore lines: 'exports', '*_pb.urdf', 'robots/old/*'); files named are "
              "checked anyway.")
@click.option("--show-settings", is_flag=True,
              help="Print the settings each file is checked with, and where each came from.")
@fix_options  # --fix, --unsafe-fixes, --diff, --fix-only (urdftool/cli/fix.py)
@click.option("--srdf", "srdf_file", type=click.Path(dir_okay=False),
              help="Check the models against this MoveIt SRDF (else one beside the model is used).")
@click.option("--no-srdf", is_flag=True, help="Do not look for an SRDF beside the model.")
@click.option("--controllers", "controllers_file", type=click.Path(dir_okay=False),
              help="Check the models' ros2_control blocks against this controllers YAML "
              "(else the file a Gazebo ros2_control plugin's <parameters> names).")
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
    extend_select: Sequence[str] = (),
    isolated: bool = False,
    no_suppressions: bool = False,
    baseline_file: str | None = None,
    write_baseline: str | None = None,
    show_settings: bool = False,
    fix: bool = False,
    unsafe_fixes: bool = False,
    show_diff: bool = False,
    fix_only: bool = False,
    srdf_file: str | None = None,
    no_srdf: bool = False,
    controllers_file: str | None = None,
    target_names: Sequence[str] = (),
    exclude: Sequence[str] = (),
) -> None:
    """Load each model (files, or directories searched recursively) and report diagnostics.

    Settings come from the nearest urdftool.toml or pyproject.toml [tool.urdftool] above each
    file (flags win; --isolated ignores them); <!-- urdftool: ignore[CODE] --> comments silence
    findings on their line or the next (--no-suppressions shows everything).
    """
    engines = simulation_options.SimOptions(simulation.engine_names(engine)) if sim else None
    rule_options = simulation.rule_options_for(engines) if engines is not None else {}
    try:
        chosen = parse_targets(target_names)
    except UnknownTarget as exc:
        raise click.BadParameter(str(exc), param_hint="--target") from exc
    if chosen:
        rule_options = {**rule_options, "targets": tuple(t.name for t in chosen)}
    options = build_options(xacro_args, packages, package_paths, select, ignore, dynamics=not no_dynamics,
                            **rule_options)
    options = dataclasses.replace(options, suppressions=not no_suppressions, srdf=srdf_file,
                                  discover_srdf=not no_srdf, controllers=controllers_file)
    for given in (srdf_file, controllers_file):
        if given is not None and not os.path.isfile(given):
            raise InputProblem(f"{given}: no such file")
    if srdf_file is not None and not os.path.isfile(srdf_file):
        raise InputProblem(f"{srdf_file}: no such file")
    for path in paths:
        if not os.path.exists(path):
            raise InputProblem(f"{path}: no such file or directory")
        if os.path.isfile(path) and detect_format(path) is None:
            raise InputProblem(
                f"{path}: unknown format (expected .urdf, .xacro, .urdf.xacro, .sdf or .world)"
            )
    format_given = click.get_current_context().get_parameter_source("fmt") is ParameterSource.COMMANDLINE
    overrides = Overrides(
        select=options.select, ignore=options.ignore, extend_select=tuple(_split(extend_select)),
        strict=strict or None, package_paths=options.package_paths, packages=options.packages,
        xacro_args=options.xacro_args, format=fmt if format_given else None, isolated=isolated,
    )
    files = expand_paths(list(paths), options.resolver(), exclude=_split(exclude))
    if not files:
        raise InputProblem("no robot descriptions found in " + ", ".join(paths))
    try:
        if show_settings:
            for path in files:
                click.echo(f"# {path}\n{resolve(path, overrides).describe()}", nl=False)
            sys.exit(EXIT_OK)
        named = frozenset(p for p in paths if not os.path.isdir(p))
        groups = group_by_settings(files, overrides, named=named)
    except SettingsError as exc:
        raise InputProblem(str(exc)) from exc
    if fix or fix_only or show_diff:
        report = run_fixes([(_group_options(settings, options), group) for settings, group in groups],
                           unsafe=unsafe_fixes, write=not show_diff, fix_only=fix_only,
                           jobs=jobs or default_jobs())
    else:
        report = _check_groups(groups, files, options, jobs, quiet)
    if model_name is not None:
        names = [f.robot for f in report.files]
        report = Report(tuple(f for f in report.files if f.robot == model_name))
        if not report.files:
            raise InputProblem(str(no_such_model(", ".join(paths), model_name, names)))
    if write_baseline:
        try:
            count = baseline.write_baseline(report, write_baseline, inputs=files)
        except write.OutputError as exc:
            raise InputProblem(str(exc)) from exc
        click.echo(f"urdftool: recorded {count} finding(s) in {write_baseline}", err=True)
        sys.exit(EXIT_OK)
    if baseline_file:
        try:
            known = baseline.apply_baseline(report, baseline.read_baseline(baseline_file), baseline_file)
        except baseline.BaselineError as exc:
            raise InputProblem(str(exc)) from exc
        report = known.report
        if not quiet and (known.known or known.fixed):
            fixed = (f"; {known.fixed} recorded finding(s) are gone: shrink it with --write-baseline"
                     if known.fixed else "")
            click.echo(f"urdftool: {known.known} known finding(s) hidden by {baseline_file}{fixed}", err=True)
    settings_format = next((settings.format for settings, _ in groups if settings.format), None)
    strict = strict or any(settings.strict for settings, _ in groups)
    emit_report(report, fmt if format_given else settings_format or fmt, output, color, quiet, inputs=files)
    if not exit_zero:
        explain_verdict_exit(report, strict)
    sys.exit(exit_code(report, strict, exit_zero))


def _split(values: Sequence[str]) -> list[str]:
    return [part.strip() for value in values for part in value.split(",") if part.strip()]


def _group_options(settings: Settings, options: CheckOptions) -> CheckOptions:
    return dataclasses.replace(
        options, select=settings.select, ignore=settings.ignore, xacro_args=dict(settings.xacro_args),
        packages=dict(settings.packages), package_paths=settings.package_paths,
        severity=dict(settings.severity), budgets={**settings.budgets, **command_line()},
    )


def _check_groups(groups: list[tuple[Settings, list[str]]], files: list[str], options: CheckOptions,
                  jobs: int, quiet: bool) -> Report:
    """Check each group of files with the options its settings give; reports in input order."""
    workers = jobs or default_jobs()
    progress = None
    if is_terminal() and len(files) >= PROGRESS_FROM and not quiet:
        bar = click.progressbar(length=len(files), label="checking", file=sys.stderr)
        bar.__enter__()
        done_so_far = [0]

        def progress(done: int, total: int) -> None:
            bar.update(1)
            done_so_far[0] += 1
            if done_so_far[0] == len(files):
                bar.__exit__(None, None, None)

    order = {path: index for index, path in enumerate(files)}
    reports: list[FileReport] = []
    for settings, group in groups:
        group_options = _group_options(settings, options)
        if settings.target and "targets" not in options.rule_options:
            try:
                configured = parse_targets(settings.target)
            except UnknownTarget as exc:
                raise InputProblem(f"{settings.config or 'settings'}: {exc}") from exc
            group_options = dataclasses.replace(group_options, rule_options={
                **options.rule_options, "targets": tuple(t.name for t in configured)})
        try:
            group_options.selection()
            result = check_files(group, group_options, jobs=workers, progress=progress)
        except UnknownSelector as exc:
            raise InputProblem(f"{settings.config or 'settings'}: {exc}") from exc
        except InputError as exc:  # a file found in a directory that cannot be read at all
            raise input_error(exc) from exc
        reports.extend(result.files)
    return Report(tuple(sorted(reports, key=lambda r: order.get(r.path, len(order)))))
