"""``urdftool convert IN -o OUT``: export, with ``--check`` for CI and ``--verify``."""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

import click

from urdftool.check import run_rules
from urdftool.cli.common import EXIT_FINDINGS, EXIT_OK, EXIT_USAGE, build_options, input_error, model_options
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.export import ExportOptions, UnknownTarget, export_model, target_for, verify_model
from urdftool.export.write import OutputError, guard_inputs, is_stale, model_inputs, write_bytes_atomic
from urdftool.parse import InputError, read
from urdftool.render.text import render_diagnostic
from urdftool.rules import Selection
from urdftool.source import SourceIndex


def _emit(diagnostics: Sequence[Diagnostic]) -> None:
    sources = SourceIndex()
    for d in diagnostics:
        click.echo(render_diagnostic(d, sources, colour=sys.stderr.isatty()), err=True)


def _refuse_output(out: str, inputs: Sequence[str]) -> None:
    try:
        guard_inputs(out, inputs)
    except OutputError as exc:
        click.echo(f"urdftool: {exc}", err=True)
        sys.exit(EXIT_USAGE)


@click.command("convert")
@click.argument("source", type=click.Path())
@click.option("-o", "--output", "out", required=True, type=click.Path(dir_okay=False), help="Output file.")
@click.option("--to", "to", type=click.Choice(["mjcf", "urdf", "pybullet", "sdf", "dot"]),
              help="Target; by default it follows OUT's suffix.")
@click.option(
    "--check",
    "check_only",
    is_flag=True,
    help="Exit 1 when OUT (and its assets) differ from what would be written; write nothing.",
)
@click.option("--verify", is_flag=True, help="Load the output in its engine and compare it with the source.")
@click.option("--model", "model_name", help="For files with several models (SDF worlds): which one.")
@click.option(
    "--floating-base", type=click.Choice(["auto", "free", "fixed"]), default="auto", show_default=True
)
@click.option(
    "--actuators", type=click.Choice(["none", "motor", "position"]), default="none", show_default=True
)
@click.option(
    "--repair-inertia", is_flag=True, help="Repair physically invalid inertia (each change is reported)."
)
@click.option("--copy-assets", is_flag=True, help="Copy meshes into an assets folder beside OUT.")
@click.option("--scene", is_flag=True, help="MJCF: add a ground plane and a light.")
@click.option("-q", "--quiet", is_flag=True, help="Print errors only (not the loss report's warnings).")
@model_options
def convert_command(
    source: str,
    out: str,
    to: str | None,
    check_only: bool,
    verify: bool,
    model_name: str | None,
    floating_base: str,
    actuators: str,
    repair_inertia: bool,
    copy_assets: bool,
    scene: bool,
    quiet: bool,
    xacro_args: Sequence[str],
    packages: Sequence[str],
    package_paths: Sequence[str],
) -> None:
    """Export SOURCE to OUT (MJCF, URDF, PyBullet URDF, SDF or DOT)."""
    options = build_options(xacro_args, packages, package_paths)
    try:
        target = target_for(out, to)
    except UnknownTarget as exc:
        raise click.BadParameter(str(exc), param_hint="--to/-o") from exc
    _refuse_output(out, [source])  # before any work: -o is the input, a device, a FIFO...
    try:
        models = read(source, options.xacro_args, options.resolver())
    except InputError as exc:
        raise input_error(exc) from exc
    chosen = [m for m in models if model_name is None or (m.robot and m.robot.name == model_name)]
    if not chosen:
        click.echo(f"urdftool: {source} has no model named '{model_name}'", err=True)
        sys.exit(EXIT_USAGE)
    loaded = chosen[0]
    if loaded.robot is None:
        _emit(loaded.diagnostics)
        sys.exit(EXIT_FINDINGS)
    robot = loaded.robot
    inputs = model_inputs(robot, loaded.files or [source])
    _refuse_output(out, inputs)  # an included xacro file or a mesh
    # A model that was not read correctly cannot be exported faithfully.
    structural = [d for d in run_rules(robot, Selection.of(["S", "X"])) if d.severity is Severity.ERROR]
    if structural:
        _emit(structural)
        click.echo(f"urdftool: {source}: not converted: fix the errors above first", err=True)
        sys.exit(EXIT_FINDINGS)
    export_options = ExportOptions(
        floating_base=floating_base,
        actuators=actuators,
        repair_inertia=repair_inertia,
        copy_assets=copy_assets,
        scene=scene,
    )
    try:
        result = export_model(robot, target, out, export_options)
    except UnknownTarget as exc:
        click.echo(f"urdftool: {exc}", err=True)
        sys.exit(EXIT_USAGE)
    _emit([d for d in result.diagnostics if not quiet or d.severity is Severity.ERROR])
    if result.failed:
        click.echo(f"urdftool: {source}: not converted", err=True)
        sys.exit(EXIT_FINDINGS)
    folder = Path(out).resolve().parent
    try:
        for rel in result.files:
            guard_inputs(folder / rel, inputs)
    except OutputError as exc:
        click.echo(f"urdftool: {exc}", err=True)
        sys.exit(EXIT_USAGE)
    if check_only:
        stale = [rel for rel, data in result.files.items() if is_stale(folder / rel, data)]
        for rel in stale:
            click.echo(f"{folder / rel}: stale (differs from what would be written)", err=True)
        sys.exit(EXIT_FINDINGS if stale else EXIT_OK)
    try:
        for rel, data in sorted(result.files.items()):
            write_bytes_atomic(folder / rel, data, inputs)
    except OutputError as exc:
        click.echo(f"urdftool: {exc}", err=True)
        sys.exit(EXIT_USAGE)
    if verify:
        try:
            outcome = verify_model(robot, target, out, export_options)
        except UnknownTarget as exc:
            click.echo(f"urdftool: {exc}", err=True)
            sys.exit(EXIT_USAGE)
        _emit(outcome.diagnostics)
        if outcome.rows:
            click.echo(f"{'quantity':40} {'max error':>12} {'tolerance':>12}  result")
            for name, error, tolerance, passed in outcome.rows:
                click.echo(f"{name:40} {error:12.3g} {tolerance:12.3g}  {'ok' if passed else 'FAIL'}")
        sys.exit(EXIT_OK if outcome.ok else EXIT_FINDINGS)
    sys.exit(EXIT_OK)
