"""From a path to the models in it: the first stage of every command and of the API."""

from __future__ import annotations

import dataclasses

from urdftool.parse import Loaded, read
from urdftool.parse.srdf import home_from_srdf
from urdftool.pipeline.check import CheckOptions


class NoSuchModel(ValueError):
    """The file holds no model of the name asked for (``--model``)."""


def load_models(path: str, options: CheckOptions) -> list[Loaded]:
    """Every model in *path*, read with the options' xacro arguments and packages.

    Raises :class:`~urdftool.parse.InputError` when the file cannot be read at all.
    """
    return [with_home(loaded) for loaded in read(path, options.xacro_args, options.resolver())]


def with_home(loaded: Loaded) -> Loaded:
    """*loaded* with its robot's home configuration from an SRDF beside it, when it has none."""
    robot = loaded.robot
    if robot is None or robot.home is not None:
        return loaded
    found = home_from_srdf(loaded.path, robot.name, [j.name for j in robot.joints])
    if found is None:
        return loaded
    _, state = found
    return dataclasses.replace(loaded, robot=dataclasses.replace(robot, home=dict(state.values)))


def load_one(path: str, options: CheckOptions, model: str | None = None) -> Loaded:
    """The model named *model* in *path*, or its first model.

    Raises :class:`~urdftool.parse.InputError` and :class:`NoSuchModel`.
    """
    models = load_models(path, options)
    chosen = [m for m in models if model is None or (m.robot and m.robot.name == model)]
    if not chosen:
        raise NoSuchModel(f"{path} has no model named '{model}'")
    return chosen[0]
