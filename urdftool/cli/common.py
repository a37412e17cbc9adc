"""Options and helpers shared by the commands; exit codes live here."""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Sequence
from typing import Any, TypeVar

import click

from urdftool.budgets import NAMES, BudgetError, budgets, parse_budgets, set_budgets
from urdftool.parse import InputError
from urdftool.pipeline.check import CheckOptions
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
