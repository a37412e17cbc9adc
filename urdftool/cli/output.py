"""Output options of ``check``: ``--format``, ``-o/--output-file``, ``--color``,
``--exit-zero``; and writing the rendered report."""

from __future__ import annotations

import sys
from collections.abc import Iterable
from typing import TYPE_CHECKING

import click

from urdftool.cli.common import EXIT_FINDINGS, EXIT_OK, F, InputProblem
from urdftool.diagnostics import Report
from urdftool.lazy import LazyModule
from urdftool.render.colour import CHOICES, want_colour
from urdftool.render.formats import FORMATS, render_report

if TYPE_CHECKING:
    from urdftool.export import write
    from urdftool.facts.simulation import verdict
else:
    # -o/--output-file and a report with findings need these; a clean check to standard output
    # does not import the exporters' package or the simulation facts.
    write = LazyModule("urdftool.export.write")
    verdict = LazyModule("urdftool.facts.simulation.verdict")


def output_options(func: F) -> F:
    for option in reversed((
        click.option("--format", "fmt", type=click.Choice(FORMATS), default="text", show_default=True,
                     help="text for people; json (its schema: `urdftool schema`), sarif (code scanning), "
                     "github (workflow annotations), junit (test reports), gitlab (Code Quality) for tools."),
        click.option("-o", "--output-file", "--output", "output", type=click.Path(dir_okay=False),
                     help="Write the report to this file (atomically) instead of standard output."),
        click.option("--color", "--colour", "color", type=click.Choice(CHOICES), default="auto",
                     show_default=True, help="Colour the text output (auto: on a terminal, "
                     "honouring NO_COLOR and FORCE_COLOR)."),
        click.option("--exit-zero", is_flag=True,
                     help="Exit 0 even when findings fail the check (report-only runs)."),
    )):
        func = option(func)
    return func


def emit_report(report: Report, fmt: str, output: str | None, color: str, quiet: bool,
                inputs: Iterable[str]) -> None:
    """Render *report* and write it to *output* (atomically) or standard output."""
    colour = want_colour(color, output is None and sys.stdout.isatty())
    text = render_report(report, fmt, colour=colour, quiet=quiet)
    if output:
        try:
            write.write_text_atomic(output, text, inputs=inputs)
        except write.OutputError as exc:
            raise InputProblem(str(exc)) from exc
    else:
        click.echo(text, nl=False, color=colour or None)


def exit_code(report: Report, strict: bool, exit_zero: bool = False) -> int:
    """0 or 1 for ``check``: findings at failing severity or a failed simulation verdict fail,
    unless *exit_zero*."""
    if exit_zero:
        return EXIT_OK
    failed = report.failed(strict) or (bool(report.diagnostics) and verdict.verdict_failed(report))
    return EXIT_FINDINGS if failed else EXIT_OK


def explain_verdict_exit(report: Report, strict: bool) -> None:
    """Say on standard error why the run exits 1 when only a "failed" simulation verdict does it:
    the summary line then reads "0 error(s)", which alone would make exit 1 look like a bug."""
    if report.failed(strict) or not report.diagnostics or not verdict.verdict_failed(report):
        return
    # a sim-summary message reads "<Engine>: failed (<reason>): <numbers>"
    verdicts = [": ".join(d.message.split(": ")[:2]) for d in report.diagnostics
                if verdict.is_failed_verdict(d)]
    click.echo(f"urdftool: exit 1: {', '.join(dict.fromkeys(verdicts))} (a failed simulation verdict "
               "fails the run even when its findings are warnings)", err=True)
