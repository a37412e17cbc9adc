"""``urdftool convert IN -o OUT``: export, with ``--check`` for CI and ``--verify``."""

from __future__ import annotations

import sys
from collections.abc import Sequence

import click

from urdftool.catalogue.xacro import CHANGES_THE_ROBOT
from urdftool.cli.common import (
    EXIT_FINDINGS,
    EXIT_OK,
    EXIT_USAGE,
    build_options,
    choose_models,
    input_error,
    is_terminal,
    model_options,
    per_model_path,
)
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.export import ExportOptions, UnknownTarget, target_for, verify_model
from urdftool.export.write import OutputError, guard_inputs, is_stale, model_inputs
from urdftool.model import Robot
from urdftool.parse import InputError, Loaded
from urdftool.pipeline.check import CheckOptions
from urdftool.pipeline.collision import (
    CAPSULE_TARGETS,
    CollisionOptions,
    Simplification,
    collision_meshes,
    simplify_collisions,
    with_collision_files,
)
from urdftool.pipeline.collision import MODES as COLLISION_MODES
from urdftool.pipeline.convert import convert_robot, output_paths, write_conversion
from urdftool.pipeline.load import load_models
from urdftool.render.text import render_diagnostic
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
@click.option("--all-models", is_flag=True,
              help="For files with several models: convert each, to OUT with the model's name added.")
@click.option(
    "--floating-base", type=click.Choice(["auto", "free", "fixed"]), default="auto", show_default=True
)
@click.option(
    "--actuators", type=click.Choice(["none", "position", "velocity", "motor", "auto"]), default="none",
    show_default=True, help="MJCF actuators; auto follows <transmission>/<ros2_control> (docs/mjcf.md)."
)
@click.option(
    "--repair-inertia", is_flag=True, help="Repair physically invalid inertia (each change is reported)."
)
@click.option("--copy-assets", is_flag=True, help="Copy meshes into an assets folder beside OUT.")
@click.option("--scene", is_flag=True, help="MJCF: add a ground plane and a light.")
@click.option("--fuse-fixed", is_flag=True,
              help="PyBullet: merge links on fixed joints into the links that carry them (exact "
              "composite inertia; the fused frames listed in OUT). Automatic above 127 joints.")
@click.option("--collision", "collision_mode", type=click.Choice(list(COLLISION_MODES)), default="as-is",
              show_default=True, help="Replace collision meshes by their convex hulls, a convex "
              "decomposition (CoACD) or fitted primitives (box, cylinder, sphere, capsule); visual meshes "
              "are untouched.")
@click.option("--collision-threshold", type=click.FloatRange(0.01, 1.0), default=0.05, show_default=True,
              help="decompose: CoACD's concavity threshold (smaller: more, tighter parts).")
@click.option("--collision-max-parts", type=click.IntRange(1, 256), default=16, show_default=True,
              help="decompose: at most this many convex parts per mesh.")
@click.option("--collision-tolerance", type=click.FloatRange(0.0, 10.0), default=0.15, show_default=True,
              help="primitives: largest relative volume error of a fitted box, cylinder, sphere or capsule.")
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
    fuse_fixed: bool,
    quiet: bool,
    all_models: bool,
    collision_mode: str,
    collision_threshold: float,
    collision_max_parts: int,
    collision_tolerance: float,
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
        chosen = _models(source, options, model_name, all_models)
    except InputError as exc:
        raise input_error(exc) from exc
    export_options = ExportOptions(
        floating_base=floating_base,
        actuators=actuators,
        repair_inertia=repair_inertia,
        copy_assets=copy_assets,
        scene=scene,
        fuse_fixed=fuse_fixed,
    )
    collision = CollisionOptions(
        collision_mode, collision_threshold, collision_max_parts, collision_tolerance
    )
    codes = []
    for loaded in chosen:
        name = (loaded.robot.name if loaded.robot else None) or "model"
        where = out if len(chosen) == 1 else per_model_path(out, name)
        if len(chosen) > 1:
            click.echo(f"urdftool: model '{name}' -> {where}", err=True)
        codes.append(_convert_one(loaded, source, where, target, export_options, collision, check_only,
                                  verify, quiet, one_of_many=len(chosen) > 1))
    sys.exit(max(codes))


def _models(source: str, options: CheckOptions, model_name: str | None, all_models: bool) -> list[Loaded]:
    """The models to convert: the one named, all of them, or the only one (a world must say which)."""
    return choose_models(source, load_models(source, options), model_name, all_models, "convert each")


def _convert_one(loaded: Loaded, source: str, out: str, target: str, export_options: ExportOptions,
                 collision: CollisionOptions, check_only: bool, verify: bool, quiet: bool,
                 one_of_many: bool = False) -> int:
    """Convert one model (one of several in a world with *one_of_many*); the exit code for it."""
    if loaded.robot is None:
        _emit(loaded.diagnostics)
        return EXIT_FINDINGS
    if not quiet:
        _emit([d for d in loaded.diagnostics if d.code in CHANGES_THE_ROBOT])
    inputs = model_inputs(loaded.robot, loaded.files or [source])
    _refuse_output(out, inputs)  # an included xacro file or a mesh
    simplified = _simplify(loaded.robot, collision, quiet, target in CAPSULE_TARGETS)
    try:
        conversion = convert_robot(simplified.robot, target, out, export_options, inputs)
        if not conversion.refused:
            conversion = with_collision_files(conversion, simplified)
    except UnknownTarget as exc:
        click.echo(f"urdftool: {exc}", err=True)
        return EXIT_USAGE
    _emit([d for d in [*simplified.diagnostics, *conversion.diagnostics]
           if not quiet or d.severity is Severity.ERROR])
    if conversion.refused:
        structural = conversion.errors and all(d.code[0] in "SX" for d in conversion.errors)
        hint = ": fix the errors above first" if structural else ""
        # in a world converted with --all-models, say which model was refused
        which = f" model '{loaded.robot.name}'" if one_of_many else ""
        click.echo(f"urdftool: {source}:{which} not converted{hint}", err=True)
        return EXIT_FINDINGS
    try:
        for path in output_paths(conversion):
            guard_inputs(path, conversion.inputs)
    except OutputError as exc:
        click.echo(f"urdftool: {exc}", err=True)
        return EXIT_USAGE
    if check_only:
        folder = conversion.out.resolve().parent
        stale = [rel for rel, data in conversion.files.items() if is_stale(folder / rel, data)]
        for rel in stale:
            why = "stale (differs from what would be written)" if (folder / rel).exists() else "missing"
            click.echo(f"{folder / rel}: {why}", err=True)
        if not stale and not quiet:  # a CI log says what was checked, not only what failed
            click.echo(f"{conversion.out}: up to date ({len(conversion.files)} file(s))", err=True)
        return EXIT_FINDINGS if stale else EXIT_OK
    try:
        write_conversion(conversion)
    except OutputError as exc:
        click.echo(f"urdftool: {exc}", err=True)
        return EXIT_USAGE
    if not verify:
        return EXIT_OK
    try:
        # the robot as exported (SDFormat's default inertials written in), so that both sides
        # weigh the same links
        outcome = verify_model(conversion.robot, target, out, export_options)
    except UnknownTarget as exc:
        click.echo(f"urdftool: {exc}", err=True)
        return EXIT_USAGE
    _emit(outcome.diagnostics)
    if outcome.rows:
        click.echo(f"{'quantity':40} {'max error':>12} {'tolerance':>12}  result")
        for name, error, tolerance, passed in outcome.rows:
            click.echo(f"{name:40} {error:12.3g} {tolerance:12.3g}  {'ok' if passed else 'FAIL'}")
    return EXIT_OK if outcome.ok else EXIT_FINDINGS


def _simplify(robot: Robot, options: CollisionOptions, quiet: bool, capsules: bool) -> Simplification:
    """The robot with its collision meshes simplified; a progress bar on a terminal for many meshes."""
    count = len(collision_meshes(robot)) if options.mode != "as-is" else 0
    if count < 3 or quiet or not is_terminal():
        return simplify_collisions(robot, options, capsules=capsules)
    with click.progressbar(length=count, label=f"collision: {options.mode}", file=sys.stderr) as bar:
        return simplify_collisions(robot, options, progress=lambda _name: bar.update(1), capsules=capsules)
