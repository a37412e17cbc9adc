"""From a path to the models in it: the first stage of every command and of the API."""

from __future__ import annotations

from collections.abc import Iterable

from urdftool.parse import Loaded, read
from urdftool.pipeline.check import CheckOptions
from urdftool.pipeline.home import with_home


class NoSuchModel(ValueError):
    """The file holds no model of the name asked for (``--model``)."""


def no_such_model(path: str, model: str, names: Iterable[str | None]) -> NoSuchModel:
    """The error for ``--model NAME`` naming no model in *path*, with the names it does hold, so
    the user can pick one without opening the world file."""
    known = ", ".join(n for n in dict.fromkeys(names) if n) or "none"
    return NoSuchModel(f"{path} has no model named '{model}' (it has: {known})")


def load_models(path: str, options: CheckOptions) -> list[Loaded]:
    """Every model in *path*, read with the options' xacro arguments and packages, each with its
    home configuration (from the SRDF beside it when the model gives none).

    Raises :class:`~urdftool.parse.InputError` when the file cannot be read at all.
    """
    resolver = options.resolver()
    return [with_home(loaded, resolver) for loaded in read(path, options.xacro_args, resolver)]


def load_one(path: str, options: CheckOptions, model: str | None = None) -> Loaded:
    """The model named *model* in *path*, or its first model.

    Raises :class:`~urdftool.parse.InputError` and :class:`NoSuchModel`.
    """
    models = load_models(path, options)
    chosen = [m for m in models if model is None or (m.robot and m.robot.name == model)]
    if not chosen:
        raise no_such_model(path, model or "", (m.robot.name for m in models if m.robot))
    return chosen[0]
