"""``urdftool graph IN -o OUT``: the kinematic tree as a diagram (PDF, SVG, PNG or DOT)."""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path
from typing import NoReturn

import click

from urdftool.cli.common import (
    EXIT_FINDINGS,
    EXIT_OK,
    EXIT_USAGE,
    build_options,
    choose_models,
    input_error,
    model_options,
    per_model_path,
    selection_options,
)
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.export.graph import (
    RANKDIRS,
    GraphOptions,
    GraphvizFailed,
    GraphvizNotFound,
    check_output_suffix,
    dot_text,
    write_diagram,
)
from urdftool.export.write import OutputError, guard_inputs, model_inputs
from urdftool.parse import InputError, Loaded
from urdftool.pipeline.check import CheckOptions
from urdftool.pipeline.convert import graph_findings
from urdftool.pipeline.load import load_models
from urdftool.render.text import render_diagnostic
from urdftool.source import SourceIndex


def _fail(message: str, code: int) -> NoReturn:
    click.echo(f"urdftool: {message}", err=True)
    sys.exit(code)


def _guard(out: str, inputs: Sequence[str]) -> None:
    try:
        guard_inputs(out, inputs)
    except OutputError as exc:
        _fail(str(exc), EXIT_USAGE)


def _load(source: str, model_name: str | None, all_models: bool, options: CheckOptions) -> list[Loaded]:
    """The models to draw: the one named, all of them, or the only one (a world must say which)."""
    try:
        models = load_models(source, options)
    except InputError as exc:
        raise input_error(exc) from exc
    return choose_models(source, models, model_name, all_models, "draw each")


def _summary(written: Sequence[Path], diagnostics: Sequence[Diagnostic]) -> str:
    """``urdftool: wrote tree.pdf (2 errors, 1 warning marked)``: only files that exist."""
    errors = sum(1 for d in diagnostics if d.severity is Severity.ERROR)
    warnings = sum(1 for d in diagnostics if d.severity is Severity.WARNING)
    marked = (
        f" ({errors} errors, {warnings} warnings marked; see urdftool check)"
        if errors or warnings
        else ""
    )
    return f"urdftool: wrote {', '.join(map(str, written))}{marked}"


@click.command("graph")
@click.argument("source", type=click.Path())
@click.option(
    "-o",
    "--output",
    "out",
    required=True,
    type=click.Path(dir_okay=False),
    help="Output file: .pdf, .svg, .png (rendered with Graphviz) or .dot/.gv (DOT text).",
)
@click.option(
    "--rankdir",
    type=click.Choice(RANKDIRS, case_sensitive=False),
    metavar="|".join(RANKDIRS),
    default="TB",
    show_default=True,
    help="Direction the tree grows: top to bottom, left to right, ...",
)
@click.option(
    "--collapse-fixed", is_flag=True, help="Merge links joined by fixed joints into one box."
)
@click.option(
    "--diagnostics/--no-diagnostics",
    default=True,
    show_default=True,
    help="Mark links and joints that have error or warning findings, with their codes.",
)
@click.option(
    "--keep-dot", is_flag=True, help="Also write the DOT text beside a rendered OUT (suffix .dot)."
)
@click.option(
    "--model", "model_name", help="For files with several models (SDF worlds): which one."
)
@click.option(
    "--all-models",
    is_flag=True,
    help="For files with several models: draw each, to OUT with the model's name added.",
)
@click.option("-q", "--quiet", is_flag=True, help="Print nothing on success.")
@selection_options
@model_options
def graph_command(
    source: str,
    out: str,
    rankdir: str,
    collapse_fixed: bool,
    diagnostics: bool,
    keep_dot: bool,
    model_name: str | None,
    all_models: bool,
    quiet: bool,
    select: Sequence[str],
    ignore: Sequence[str],
    xacro_args: Sequence[str],
    packages: Sequence[str],
    package_paths: Sequence[str],
) -> None:
    """Draw the kinematic tree of SOURCE (URDF, xacro or SDF) to OUT.

    Links are boxes (name, mass), joints ellipses coloured by type (name, type,
    axis, limits), edges carry the joint origins. Findings are marked, but do
    not change the exit code: 0 when OUT was written, 1 when no robot could be
    read, 2 for usage errors, unreadable input or a missing/failed Graphviz.
    """
    try:
        check_output_suffix(out)
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint="-o/--output") from exc
    options = build_options(xacro_args, packages, package_paths, select, ignore)
    _guard(out, [source])  # before any work
    chosen = _load(source, model_name, all_models, options)
    graph_options = GraphOptions(
        rankdir=rankdir,
        collapse_fixed=collapse_fixed,
        diagnostics=diagnostics,
        select=options.select,
        ignore=options.ignore,
    )
    for loaded in chosen:
        name = (loaded.robot.name if loaded.robot else None) or "model"
        _draw(loaded, source, out if len(chosen) == 1 else per_model_path(out, name), graph_options,
              keep_dot, quiet)
    sys.exit(EXIT_OK)


def _draw(loaded: Loaded, source: str, out: str, graph_options: GraphOptions, keep_dot: bool,
          quiet: bool) -> None:
    """Write one model's diagram to OUT (and its DOT text with *keep_dot*); exits on a failure."""
    inputs = model_inputs(loaded.robot, loaded.files or [source])
    _guard(out, inputs)
    if loaded.robot is None:
        sources = SourceIndex()
        for d in loaded.diagnostics:
            click.echo(render_diagnostic(d, sources, colour=sys.stderr.isatty()), err=True)
        _fail(f"{source}: no robot to draw: fix the errors above first", EXIT_FINDINGS)
    found = graph_findings(loaded.robot, graph_options)
    text = dot_text(loaded.robot, graph_options, found)
    written: list[Path] = []
    try:
        warnings = write_diagram(text, out, inputs, keep_dot, written)
    except OutputError as exc:
        _fail(str(exc), EXIT_USAGE)
    except (GraphvizNotFound, GraphvizFailed) as exc:
        kept = f"\nthe DOT text was written to {written[0]}" if written else ""
        failed = "Graphviz failed to render it:\n" if isinstance(exc, GraphvizFailed) else ""
        _fail(f"{out} not written. {failed}{exc}{kept}", EXIT_USAGE)
    for warning in warnings:
        click.echo(f"graphviz: {warning}", err=True)
    if not quiet:
        click.echo(_summary(written, found), err=True)
