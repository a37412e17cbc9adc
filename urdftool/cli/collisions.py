"""``urdftool collisions MODEL -o OUT``: MoveIt's self-collision matrix as SRDF or MJCF."""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from typing import NoReturn

import click

from urdftool.cli.common import (
    EXIT_FINDINGS,
    EXIT_OK,
    EXIT_USAGE,
    build_options,
    input_error,
    is_terminal,
    model_options,
)
from urdftool.export.write import OutputError, guard_inputs, model_inputs, write_bytes_atomic
from urdftool.parse import InputError
from urdftool.pipeline.collisions import NoMatrix, collision_matrix, mjcf_bytes, srdf_bytes, summary
from urdftool.pipeline.load import NoSuchModel, load_one
from urdftool.render.text import render_diagnostic
from urdftool.source import SourceIndex


def _fail(message: str, code: int) -> NoReturn:
    click.echo(f"urdftool: {message}", err=True)
    sys.exit(code)


@click.command("collisions")
@click.argument("source", type=click.Path())
@click.option("-o", "--output", "out", required=True, type=click.Path(dir_okay=False),
              help="Output: an SRDF (.srdf; an existing one keeps everything but its <disable_collisions>) "
                   "or an MJCF file (.xml) with a <contact> block of <exclude> pairs.")
@click.option("--samples", type=click.IntRange(min=1), default=10_000, show_default=True,
              help="Random configurations sampled within the joint limits.")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the sampling.")
@click.option("--model", "model_name", help="For files with several models (SDF worlds): which one.")
@click.option("-q", "--quiet", is_flag=True, help="Print nothing on success.")
@model_options
def collisions_command(
    source: str,
    out: str,
    samples: int,
    seed: int,
    model_name: str | None,
    quiet: bool,
    xacro_args: Sequence[str],
    packages: Sequence[str],
    package_paths: Sequence[str],
) -> None:
    """Compute the self-collision matrix of SOURCE as MoveIt Setup Assistant does.

    Every pair of links with collision geometry is classified: Adjacent
    (joined by a joint), Default (in contact at the default state), Always
    (in contact in at least 95% of the samples) or Never (in none); those
    pairs are written as <disable_collisions> (or MJCF <exclude>). Meshes are
    taken as their convex hulls. The result depends only on the model,
    --samples and --seed. Exit 0 when OUT was written, 1 when no robot (or no
    geometry) could be read, 2 for usage errors.
    """
    mjcf = out.lower().endswith(".xml")
    if not mjcf and not out.lower().endswith((".srdf", ".srdf.xacro")):
        raise click.BadParameter("write an SRDF (.srdf) or an MJCF file (.xml)", param_hint="-o/--output")
    options = build_options(xacro_args, packages, package_paths)
    try:
        loaded = load_one(source, options, model_name)
    except InputError as exc:
        raise input_error(exc) from exc
    except NoSuchModel as exc:
        _fail(str(exc), EXIT_USAGE)
    if loaded.robot is None:
        sources = SourceIndex()
        for d in loaded.diagnostics:
            click.echo(render_diagnostic(d, sources, colour=is_terminal()), err=True)
        _fail(f"{source}: no robot to check: fix the errors above first", EXIT_FINDINGS)
    try:
        guard_inputs(out, model_inputs(loaded.robot, loaded.files or [source]))
    except OutputError as exc:
        _fail(str(exc), EXIT_USAGE)
    existing = None
    if not mjcf and os.path.exists(out):
        try:
            with open(out, "rb") as handle:
                existing = handle.read()
        except OSError as exc:
            _fail(f"{out}: cannot read: {exc.strerror or exc}", EXIT_USAGE)
    robot = loaded.robot
    try:
        if is_terminal() and not quiet:
            with click.progressbar(length=samples, label="sampling", file=sys.stderr) as bar:
                found = collision_matrix(robot, samples, seed, bar.update)
        else:
            found = collision_matrix(robot, samples, seed)
    except NoMatrix as exc:
        _fail(f"{source}: no collision matrix: {exc}", EXIT_FINDINGS)
    name = robot.name or "robot"
    try:
        data = mjcf_bytes(found, name) if mjcf else srdf_bytes(found, name, existing)
    except ValueError as exc:
        _fail(f"{out}: {exc}", EXIT_USAGE)
    try:
        write_bytes_atomic(out, data, model_inputs(robot, loaded.files or [source]))
    except OutputError as exc:
        _fail(str(exc), EXIT_USAGE)
    if not quiet:
        counts = ", ".join(f"{n} {reason}" for reason, n in summary(found).items())
        kept = f"; {len(found.sometimes)} pairs collide sometimes and stay enabled"
        merged = " (merged)" if existing is not None else ""
        click.echo(f"urdftool: wrote {out}{merged}: {len(found.reasons)} disabled pairs ({counts}){kept}; "
                   f"{found.samples} samples, seed {found.seed}", err=True)
    sys.exit(EXIT_OK)
