"""Numbers as exporters write them: exact, short, and the same on every run."""

from __future__ import annotations

from collections.abc import Iterable


def num(value: float) -> str:
    """Shortest text that parses back to exactly *value*; ``-0`` is ``0``, ``2.0`` is ``2``.

    Exact round trips are what lets ``--verify`` hold exported models to 1e-9.
    """
    value = float(value)
    if value == 0.0:
        return "0"
    if value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    return repr(value)


def vec(values: Iterable[float]) -> str:
    """Space-separated :func:`num` values."""
    return " ".join(num(v) for v in values)
