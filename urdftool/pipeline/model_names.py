"""``--model NAME`` that names no model: the error every command and the API raise.

Kept apart from :mod:`urdftool.pipeline.load` so that a structural check, which
needs only the message, does not import the home-configuration and SRDF readers.
"""

from __future__ import annotations

from collections.abc import Iterable


class NoSuchModel(ValueError):
    """The file holds no model of the name asked for (``--model``), or several and none was asked
    for; ``models`` are the names it does hold, in file order."""

    def __init__(self, message: str, models: Iterable[str] = ()):
        super().__init__(message)
        self.models = tuple(models)


def no_such_model(path: str, model: str, names: Iterable[str | None]) -> NoSuchModel:
    """The error for ``--model NAME`` naming no model in *path*, with the names it does hold, so
    the user can pick one without opening the world file."""
    held = [n for n in dict.fromkeys(names) if n]
    return NoSuchModel(f"{path} has no model named '{model}' (it has: {', '.join(held) or 'none'})", held)


def several_models(path: str, names: Iterable[str | None]) -> NoSuchModel:
    """The error for a file of several models read with no ``--model``: which one is meant cannot
    be guessed, and taking the first would answer for a model the user did not ask about."""
    names = list(names)
    known = [n or "?" for n in names]
    return NoSuchModel(f"{path} holds {len(known)} models ({', '.join(known)}): choose one with "
                       "--model NAME (model=NAME in Python)", [n for n in names if n])
