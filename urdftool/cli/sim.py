"""``urdftool sim IN``: the bundled smoke simulation, with a verdict per engine."""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence

import click

from urdftool.cli.common import (
    EXIT_FINDINGS,
    EXIT_OK,
    F,
    InputProblem,
    build_options,
    input_error,
    model_options,
)
from urdftool.cli.output import explain_verdict_exit
from urdftool.facts.simulation import engine_names
from urdftool.facts.simulation.scene import DURATION, SimOptions
from urdftool.facts.simulation.verdict import verdict_failed
from urdftool.parse import InputError, detect_format
from urdftool.pipeline.load import NoSuchModel
from urdftool.render import render_json, render_text


def sim_options(func: F) -> F:
    """``--engine``, ``--duration``, ``--timestep``, ``--hold``, ``--repair-inertia``."""
    for option in reversed((
        click.option("--engine", type=click.Choice(["mujoco", "pybullet", "all"]), default="all",
                     show_default=True, help="Engine(s) to simulate in."),
        click.option("--duration", type=click.FloatRange(min=0.0, min_open=True, max=60.0), default=DURATION,
                     show_default=True, help="Simulated time (s)."),
        click.option("--timestep", type=click.FloatRange(min=1e-5, max=0.05), default=None,
                     help="Fixed step (s); default: each engine's own (MuJoCo 2 ms, PyBullet 1/240 s)."),
        click.option("--hold", is_flag=True, help="Hold every joint at its start pose with a PD "
                     "controller (torques clipped at the effort limit) instead of damping only."),
        click.option("--repair-inertia", is_flag=True, help="Let the exporters repair physically "
                     "invalid inertia instead of refusing the model."),
    )):
        func = option(func)
    return func


def simulation_options(engine: str, duration: float, timestep: float | None, hold: bool,
                       repair_inertia: bool) -> SimOptions:
    return SimOptions(engine_names(engine), duration, timestep, hold, repair_inertia)


@click.command("sim")
@click.argument("path", type=click.Path())
@model_options
@sim_options
@click.option("--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True)
@click.option("--strict", is_flag=True, help="Warnings fail too (exit 1).")
@click.option("--model", "model_name", help="For files with several models (SDF worlds): only this one.")
def sim_command(
    path: str, xacro_args: Sequence[str], packages: Sequence[str], package_paths: Sequence[str],
    engine: str, duration: float, timestep: float | None, hold: bool, repair_inertia: bool,
    fmt: str, strict: bool, model_name: str | None,
) -> None:
    """Simulate the robot for a few seconds in MuJoCo and/or PyBullet and give a verdict.

    Mobile robots (wheels, legs) are dropped onto a ground plane, others are
    bolted to the world; joints get zero commands and are held by their
    damping (or, with --hold, by PD at the start pose). Findings: sim-unstable,
    sim-initial-penetration, sim-drift, sim-joint-limit-violation, and a
    summary per engine (JSON: data.summary).

    Exit 1 when an engine's verdict is "failed", even when its findings are
    warnings (a blow-up, links overlapping at the start), or on errors.
    """
    from urdftool.pipeline.simulate import simulate_file

    options = build_options(xacro_args, packages, package_paths)
    if not os.path.isfile(path):
        raise InputProblem(f"{path}: no such file")
    if detect_format(path) is None:
        raise InputProblem(f"{path}: unknown format (expected .urdf, .xacro, .urdf.xacro, .sdf or .world)")
    sim = simulation_options(engine, duration, timestep, hold, repair_inertia)
    try:
        report = simulate_file(path, sim, options, model_name)
    except InputError as exc:
        raise input_error(exc) from exc
    except NoSuchModel as exc:
        raise InputProblem(str(exc)) from exc
    click.echo(render_json(report) if fmt == "json" else render_text(report, colour=sys.stdout.isatty()),
               nl=False)
    # a "failed" verdict fails the run even when its findings are only warnings
    explain_verdict_exit(report, strict)
    sys.exit(EXIT_FINDINGS if report.failed(strict) or verdict_failed(report) else EXIT_OK)
