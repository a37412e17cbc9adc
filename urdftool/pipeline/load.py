"""From a path to the models in it: the first stage of every command and of the API."""

from __future__ import annotations

from urdftool.parse import Loaded, read
from urdftool.pipeline.check import CheckOptions
from urdftool.pipeline.home import with_home
from urdftool.pipeline.model_names import NoSuchModel, no_such_model, several_models

__all__ = ["NoSuchModel", "load_models", "load_one", "no_such_model"]


def load_models(path: str, options: CheckOptions) -> list[Loaded]:
    """Every model in *path*, read with the options' xacro arguments and packages, each with its
    home configuration (from the SRDF beside it when the model gives none).

    Raises :class:`~urdftool.parse.InputError` when the file cannot be read at all.
    """
    resolver = options.resolver()
    return [with_home(loaded, resolver) for loaded in read(path, options.xacro_args, resolver)]


def load_one(path: str, options: CheckOptions, model: str | None = None) -> Loaded:
    """The model named *model* in *path*, or its only model.

    Raises :class:`~urdftool.parse.InputError`, and :class:`NoSuchModel` when *model* names none
    or when *path* holds several models (an SDF world) and *model* is not given.
    """
    models = load_models(path, options)
    robots = [m.robot.name for m in models if m.robot is not None]
    if model is None and len(robots) > 1:
        raise several_models(path, robots)
    chosen = [m for m in models if model is None or (m.robot and m.robot.name == model)]
    if not chosen:
        raise no_such_model(path, model or "", (m.robot.name for m in models if m.robot))
    return chosen[0]
