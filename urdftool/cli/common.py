"""Options and helpers shared by the commands; exit codes live here."""

from __future__ import annotations

import os
import re
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, TypeVar

import click

from urdftool.budgets import NAMES, BudgetError, budgets, parse_budgets, set_budgets
from urdftool.parse import InputError, Loaded
from urdftool.pipeline.check import CheckOptions
from urdftool.pipeline.model_names import no_such_model
from urdftool.rules import UnknownSelector
from urdftool.safe_files import DEFAULT_LIMITS, limits, parse_limits, set_limits

F = TypeVar("F", bound=Callable[..., Any])

EXIT_OK = 0
EXIT_FINDINGS = 1
EXIT_USAGE = 2


class InputProblem(click.ClickException):
    """An input that cannot be read at all: exit code 2."""

    exit_code = EXIT_USAGE

    def format_message(self) -> str:
        return self.message


def _pairs(values: Sequence[str], sep: str, what: str) -> dict[str, str]:
    out: dict[str, str] = {}
    for value in values:
        name, found, rest = value.partition(sep)
        if not found or not name:
            raise click.BadParameter(f"'{value}' is not {what}")
        out[name] = rest
    return out


def _set_file_limits(ctx: click.Context, param: click.Parameter, values: Sequence[str]) -> None:
    try:
        set_limits({**DEFAULT_LIMITS, **parse_limits(list(values))})
    except ValueError as exc:
        raise click.BadParameter(str(exc), ctx=ctx, param=param) from exc


def _set_budgets(ctx: click.Context, param: click.Parameter, values: Sequence[str]) -> None:
    try:
        set_budgets(parse_budgets(list(values)))
    except BudgetError as exc:
        raise click.BadParameter(str(exc), ctx=ctx, param=param) from exc


def model_options(func: F) -> F:
    """``-a/--xacro-arg``, ``--package``, ``--package-path``, ``--max-file-size``, ``--budget``."""
    func = click.option(
        "--budget",
        multiple=True,
        metavar="NAME=VALUE",
        expose_value=False,
        callback=_set_budgets,
        help=f"Raise (or lower) a stage's budget: {', '.join(NAMES)} (docs/robustness.md); "
        "e.g. --budget xacro-seconds=120; repeatable.",
    )(func)
    func = click.option(
        "--max-file-size",
        multiple=True,
        metavar="[KIND=]SIZE",
        expose_value=False,
        callback=_set_file_limits,
        help="Raise (or lower) the size cap on files read: SIZE for all kinds, or model=, include=, "
        "mesh= (defaults 64M, 16M, 256M); e.g. --max-file-size mesh=1G; repeatable.",
    )(func)
    func = click.option(
        "--package-path",
        "package_paths",
        multiple=True,
        type=click.Path(file_okay=False),
        help="Folder to scan for package.xml (and Gazebo models); repeatable.",
    )(func)
    func = click.option(
        "--package",
        "packages",
        multiple=True,
        metavar="NAME=DIR",
        help="Where package NAME lives (for package://, $(find), model://); repeatable.",
    )(func)
    func = click.option(
        "-a",
        "--xacro-arg",
        "xacro_args",
        multiple=True,
        metavar="NAME:=VALUE",
        help="xacro argument; repeatable.",
    )(func)
    return func


def selection_options(func: F) -> F:
    func = click.option(
        "--ignore", multiple=True, help="Rule codes, code prefixes or names to turn off (comma-separated)."
    )(func)
    func = click.option(
        "--select", multiple=True, help="Only these rule codes, code prefixes or names (comma-separated)."
    )(func)
    return func


def build_options(
    xacro_args: Sequence[str],
    packages: Sequence[str],
    package_paths: Sequence[str],
    select: Sequence[str] = (),
    ignore: Sequence[str] = (),
    **rule_options: Any,
) -> CheckOptions:
    options = CheckOptions(
        select=tuple(select) or None,
        ignore=tuple(ignore),
        xacro_args=_pairs(xacro_args, ":=", "NAME:=VALUE"),
        packages={k: os.path.abspath(v) for k, v in _pairs(packages, "=", "NAME=DIR").items()},
        package_paths=tuple(os.path.abspath(p) for p in package_paths),
        rule_options=rule_options,
        file_limits=limits(),
        budgets=budgets(),
    )
    try:
        options.selection()
    except UnknownSelector as exc:
        raise click.BadParameter(str(exc), param_hint="--select/--ignore") from exc
    return options


def input_error(exc: InputError) -> InputProblem:
    return InputProblem(str(exc))


def is_terminal() -> bool:
    return sys.stderr.isatty()


def choose_models(source: str, models: Sequence[Loaded], model_name: str | None, all_models: bool,
                  each: str) -> list[Loaded]:
    """The models a command that writes one file per model works on (``convert``, ``graph``).

    The one named by ``--model``, every one with ``--all-models``, or the only one. A file
    holding several models (an SDF world) without either flag is a usage error that lists them,
    so that no command silently takes the first. *each* ends the hint: "convert each".
    """
    if model_name is not None:
        chosen = [m for m in models if m.robot and m.robot.name == model_name]
        if not chosen:
            missing = no_such_model(source, model_name, (m.robot.name for m in models if m.robot))
            click.echo(f"urdftool: {missing}", err=True)
            sys.exit(EXIT_USAGE)
        return chosen[:1]
    robots = [m for m in models if m.robot is not None]
    if len(robots) > 1 and not all_models:
        names = ", ".join(m.robot.name or "?" for m in robots if m.robot)
        click.echo(f"urdftool: {source} holds {len(robots)} models ({names}): choose one with "
                   f"--model NAME, or {each} with --all-models", err=True)
        sys.exit(EXIT_USAGE)
    return robots or list(models[:1])


def per_model_path(out: str, name: str) -> str:
    """OUT with the model's name before the suffix (``world.xml`` -> ``world_robot.xml``)."""
    path = Path(out)
    safe = re.sub(r"[^A-Za-z0-9_.-]+", "_", name).strip("_") or "model"
    return str(path.with_name(f"{path.stem}_{safe}{path.suffix}"))
