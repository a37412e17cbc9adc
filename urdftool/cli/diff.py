"""``urdftool diff OLD NEW`` and ``urdftool diff --rev GITREV PATH``."""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Iterator, Sequence

import click

from urdftool.cli.common import (
    EXIT_FINDINGS,
    EXIT_OK,
    InputProblem,
    build_options,
    input_error,
    model_options,
)
from urdftool.parse import InputError
from urdftool.pipeline.diff import (
    DiffError,
    FailOnError,
    RobotDiff,
    diff_files,
    parse_fail_on,
    revision,
    tripped,
)
from urdftool.pipeline.load import NoSuchModel
from urdftool.render.diff import RENDERERS


@click.command("diff")
@click.argument("paths", nargs=-1, required=True, type=click.Path())
@model_options
@click.option("--rev", metavar="GITREV",
              help="Compare PATH as it was at this git revision with the working copy (one PATH).")
@click.option("--format", "fmt", type=click.Choice(sorted(RENDERERS)), default="text", show_default=True)
@click.option("-o", "--output-file", "output", type=click.Path(dir_okay=False), help="Write the output here.")
@click.option("--fail-on", "fail_on", default="", metavar="TERMS",
              help="Exit 1 when a term trips, e.g. 'pose>1mm,rotation>0.5deg,mass>1%,com>2mm,new-errors,"
              "new-warnings,structure,any'.")
@click.option("--model", "model_name", help="For files with several models (SDF worlds): which one.")
@click.option("--no-findings", is_flag=True, help="Do not run the rules on either side.")
@click.option("--no-dynamics", is_flag=True, help="Skip the dynamics pass when running the rules.")
def diff_command(
    paths: Sequence[str], xacro_args: Sequence[str], packages: Sequence[str], package_paths: Sequence[str],
    rev: str | None, fmt: str, output: str | None, fail_on: str, model_name: str | None,
    no_findings: bool = False, no_dynamics: bool = False,
) -> None:
    """What changed in the robot: renames, joints, link poses at zero, masses, meshes, findings.

    Both sides are read with the same xacro arguments and packages. A reformatted or reordered
    file diffs as empty.
    """
    options = build_options(xacro_args, packages, package_paths, dynamics=not no_dynamics)
    try:
        terms = parse_fail_on(fail_on)
    except FailOnError as exc:
        raise InputProblem(str(exc)) from exc
    if rev is not None and len(paths) != 1:
        raise InputProblem("diff --rev GITREV takes one PATH")
    if rev is None and len(paths) != 2:
        raise InputProblem("diff takes OLD and NEW (or --rev GITREV PATH)")
    try:
        with _sides(paths, rev) as (old, new):
            result = diff_files(old, new, options, model_name, findings=not no_findings)
    except (DiffError, NoSuchModel) as exc:
        raise InputProblem(str(exc)) from exc
    except InputError as exc:
        raise input_error(exc) from exc
    if rev is not None:
        result = RobotDiff(f"{paths[0]}@{rev}", paths[0], result.changes, result.link_renames,
                           result.joint_renames)
    hits = tripped(result, terms)
    text = RENDERERS[fmt](result, hits)
    if output:
        with open(output, "w", encoding="utf-8") as handle:
            handle.write(text)
    else:
        click.echo(text, nl=False)
    sys.exit(EXIT_FINDINGS if hits else EXIT_OK)


@contextlib.contextmanager
def _sides(paths: Sequence[str], rev: str | None) -> Iterator[tuple[str, str]]:
    if rev is None:
        yield paths[0], paths[1]
        return
    with revision(rev, paths[0]) as old:
        yield old, paths[0]
