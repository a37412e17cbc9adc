"""Budgets per stage: how much work a stage may do before it stops with one finding.

A robot description can ask for unbounded work without being large: a xacro macro that calls
itself twice, forty levels deep, expands to 2^40 elements from a file of forty lines. Each stage
that can run away has a budget. A stage that spends it stops, says so in one finding naming the
budget and how to raise it, and the rest of the check goes on.

| budget | default | unit | stage |
|---|---|---|---|
| ``xacro-seconds`` | 30 | CPU seconds | one file's xacro expansion |
| ``xacro-elements`` | 1,000,000 | elements | one file's xacro expansion (elements evaluated) |
| ``dynamics-dof`` | 120 | moving degrees of freedom | above it the dynamics pass takes the linear sweep |
| ``collision-faces`` | 10,000 | triangles | per collision mesh (``collision-mesh-too-complex``) |

File sizes have their caps in :mod:`urdftool.safe_files` (``--max-file-size``). Raise or lower a
budget with ``--budget NAME=VALUE`` (repeatable) or ``budgets = {NAME = VALUE}`` in
``[tool.urdftool]``; in Python, :func:`stage_budgets` is a context manager doing the same, and
``CheckOptions(budgets=…)`` carries them to worker processes.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator, Mapping

#: name -> default value
DEFAULT_BUDGETS: dict[str, float] = {
    "xacro-seconds": 30.0,
    "xacro-elements": 1_000_000,
    "dynamics-dof": 120,
    "collision-faces": 10_000,
}

#: name -> what it bounds, for messages and ``--help``
MEANING: dict[str, str] = {
    "xacro-seconds": "CPU seconds of one file's xacro expansion",
    "xacro-elements": "elements one file's xacro expansion evaluates",
    "dynamics-dof": "moving degrees of freedom of the dense dynamics pass",
    "collision-faces": "triangles of a collision mesh",
}

NAMES = tuple(DEFAULT_BUDGETS)

_budgets: dict[str, float] = dict(DEFAULT_BUDGETS)
_given: dict[str, float] = {}


class BudgetError(ValueError):
    """A budget that does not exist, or a value that is not a positive number."""


def budget(name: str) -> float:
    """The budget *name* in force."""
    return _budgets[name]


def budgets() -> dict[str, float]:
    """Every budget in force (the defaults unless :func:`stage_budgets` changed them)."""
    return dict(_budgets)


def set_budgets(values: Mapping[str, float]) -> None:
    """Set budgets for the rest of the process (what ``--budget`` does): the defaults, then
    *values*, which :func:`command_line` gives back (they win over a configuration file's)."""
    given = checked(values)
    _budgets.clear()
    _budgets.update(DEFAULT_BUDGETS, **given)
    _given.clear()
    _given.update(given)


def command_line() -> dict[str, float]:
    """The budgets the last :func:`set_budgets` gave (``--budget`` on the command line)."""
    return dict(_given)


@contextlib.contextmanager
def stage_budgets(overrides: Mapping[str, float] | None) -> Iterator[None]:
    """Raise (or lower) budgets for the duration of the block (process-wide)."""
    previous = dict(_budgets)
    _budgets.update(checked(overrides or {}))
    try:
        yield
    finally:
        _budgets.clear()
        _budgets.update(previous)


def checked(values: Mapping[str, object]) -> dict[str, float]:
    """*values* with every name known and every value a positive number. Raises :class:`BudgetError`."""
    out: dict[str, float] = {}
    for name, value in values.items():
        if name not in DEFAULT_BUDGETS:
            import difflib  # only for a misspelt name: a structural check's cold start never needs it

            close = difflib.get_close_matches(name, NAMES, n=1)
            hint = f"; did you mean '{close[0]}'?" if close else f" (budgets: {', '.join(NAMES)})"
            raise BudgetError(f"unknown budget '{name}'{hint}")
        if (isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0
                or not math.isfinite(value)):  # inf would reach int() in the stages that count
            raise BudgetError(f"budget '{name}' must be a positive finite number, not {value!r}")
        out[name] = float(value)
    return out


def parse_budgets(texts: list[str]) -> dict[str, float]:
    """``["xacro-seconds=120", "collision-faces=20000"]`` → budgets. Raises :class:`BudgetError`."""
    values: dict[str, object] = {}
    for text in texts:
        name, found, value = text.partition("=")
        if not found:
            raise BudgetError(f"'{text}' is not NAME=VALUE (budgets: {', '.join(NAMES)})")
        try:
            values[name.strip()] = float(value)
        except ValueError:
            raise BudgetError(
                f"budget '{name.strip()}' must be a positive finite number, not '{value}'") from None
    return checked(values)


def how_to_raise(name: str) -> str:
    """The sentence a finding ends with when its stage spent budget *name*."""
    return (f"the {name} budget ({MEANING[name]}) is {budget(name):g}; raise it with "
            f"--budget {name}=N or budgets = {{{name} = N}} in [tool.urdftool]")
