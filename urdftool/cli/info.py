"""``urdftool info PATH``."""

from __future__ import annotations

import json
import sys
from collections.abc import Sequence

import click

from urdftool.catalogue.xacro import CHANGES_THE_ROBOT
from urdftool.cli.common import (
    EXIT_FINDINGS,
    EXIT_OK,
    InputProblem,
    build_options,
    input_error,
    model_options,
)
from urdftool.parse import InputError, read
from urdftool.pipeline.info import format_summary, summarize
from urdftool.pipeline.load import no_such_model
from urdftool.render.text import render_diagnostic
from urdftool.source import SourceIndex


@click.command("info")
@click.argument("path", type=click.Path())
@model_options
@click.option("--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True)
@click.option("--model", "model_name", help="For files with several models (SDF worlds): which one.")
def info_command(
    path: str, xacro_args: Sequence[str], packages: Sequence[str], package_paths: Sequence[str], fmt: str,
    model_name: str | None = None,
) -> None:
    """Summary: robot name, root, links, joints by type, DOF, total mass, loops, and the tree."""
    options = build_options(xacro_args, packages, package_paths)
    try:
        models = read(path, options.xacro_args, options.resolver())
    except InputError as exc:
        raise input_error(exc) from exc
    if model_name is not None:
        names = [m.robot.name for m in models if m.robot is not None]
        models = [m for m in models if m.robot is not None and m.robot.name == model_name]
        if not models:
            raise InputProblem(str(no_such_model(path, model_name, names)))
    summaries = []
    failed = False
    sources_of_warnings = SourceIndex()
    for loaded in models:
        if loaded.robot is None:
            failed = True
            sources = SourceIndex()
            for d in loaded.diagnostics:
                click.echo(render_diagnostic(d, sources), err=True)
            continue
        # an ignored xacro argument describes another robot than the one asked for: say so
        for d in loaded.diagnostics:
            if d.code in CHANGES_THE_ROBOT:
                click.echo(render_diagnostic(d, sources_of_warnings), err=True)
        summaries.append(summarize(loaded.robot))
    if fmt == "json":
        click.echo(json.dumps(summaries if len(summaries) != 1 else summaries[0], indent=2))
    else:
        click.echo("\n".join(format_summary(s) for s in summaries), nl=False)
    sys.exit(EXIT_FINDINGS if failed else EXIT_OK)
