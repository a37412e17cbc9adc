"""The controllers YAML of a model: which file, reading it, and attaching it to the loaded model.

ros2_control's controller manager reads its controllers from a parameter file;
``check`` reads it too so the controller rules (:mod:`urdftool.rules.controllers`)
can check it against the robot's ``<ros2_control>`` block. The file is taken
from ``--controllers FILE`` when given; otherwise from the ``<parameters>`` of
the model's Gazebo ros2_control plugins (``gazebo_ros2_control``,
``gz_ros2_control``, ``ign_ros2_control``), resolved through the package
resolver (``$(find pkg)/config/x.yaml`` is already a path after xacro;
``package://pkg/config/x.yaml`` is resolved here). The YAML's reader findings
join the model's.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from urdftool.catalogue.ros2_control import ControllersYamlInvalid
from urdftool.catalogue.syntax import UnexpandedSubstitution
from urdftool.diagnostics import Diagnostic
from urdftool.lazy import LazyModule
from urdftool.model import Robot
from urdftool.parse import Loaded
from urdftool.parse.locate import span_of
from urdftool.parse.packages import PackageResolver
from urdftool.safe_files import is_regular
from urdftool.source import Span

if TYPE_CHECKING:
    from urdftool.parse import ament
    from urdftool.parse import controllers as reader
else:
    # Imported when a model names a controllers file (a ros2_control plugin's <parameters>) or
    # --controllers is given: most models do neither.
    ament = LazyModule("urdftool.parse.ament")
    reader = LazyModule("urdftool.parse.controllers")


def parameter_elements(robot: Robot) -> Iterator[Any]:
    """``<parameters>`` of every ros2_control simulation plugin in the robot's ``<gazebo>`` blocks."""
    for extension in robot.extensions:
        if extension.tag != "gazebo" or extension.element is None:
            continue
        for plugin in extension.element.iter("plugin"):
            if "ros2_control" in (plugin.get("filename") or "").lower():
                yield from (child for child in plugin if child.tag == "parameters")


def _resolve(
    text: str, model_path: str, resolver: PackageResolver
) -> tuple[str | None, tuple[str, ...], bool]:
    """(readable path or None, places looked, whether a miss is certain).

    A relative path is read by Gazebo from its working directory, which a static
    check cannot know: it is looked for beside the model, and a miss is not certain.
    """
    if text.startswith(("package://", "file://")) or os.path.isabs(text):
        lookup = resolver.resolve_uri(text, model_path)
        path = lookup.path if lookup.path and is_regular(lookup.path) else None
        if path is None and lookup.path:
            # `$(find pkg)` is the installed share folder: in a source tree the file sits where the
            # package's ament install rule takes it from (config/ installed from description/config)
            path = ament.installed_source(lookup.path)
        return path, tuple(lookup.tried), True
    candidate = os.path.join(os.path.dirname(os.path.abspath(model_path)), text)
    return (candidate if is_regular(candidate) else None), (candidate,), False


def attach(loaded: Loaded, controllers_path: str | None, resolver: PackageResolver) -> Loaded:
    """*loaded* with its controllers YAML read (from *controllers_path*, else its plugins')."""
    if loaded.robot is None:
        return loaded
    paths: list[str] = []
    missing: list[tuple[str, Span | None, tuple[str, ...]]] = []
    unexpanded: list[Diagnostic] = []
    if controllers_path is not None:
        paths.append(controllers_path)
    else:
        for element in parameter_elements(loaded.robot):
            text = (element.text or "").strip()
            if text and ("$(" in text or "${" in text) and loaded.format == "urdf":
                # read as plain URDF: the plugin receives the substitution as it is written
                unexpanded.append(_unexpanded(text, element))
                continue
            if not text or "$(" in text or "${" in text:
                continue
            path, tried, certain = _resolve(text, loaded.path, resolver)
            if path is not None:
                if path not in paths:
                    paths.append(path)
            elif certain:
                missing.append((text, span_of(element), tried))
    if unexpanded:
        robot = dataclasses.replace(loaded.robot, diagnostics=(*loaded.robot.diagnostics, *unexpanded))
        loaded = dataclasses.replace(loaded, robot=robot, diagnostics=[*loaded.diagnostics, *unexpanded])
    if not paths and not missing:
        return loaded
    assert loaded.robot is not None
    found = reader.Controllers(missing=missing, given=controllers_path is not None)
    for path in paths:
        try:
            found.configs.append(reader.read_controllers(path))
        except OSError as exc:
            found.configs.append(reader.ControllerConfig(path, diagnostics=[_unreadable(path, exc)]))
    extra = [d for config in found.configs for d in config.diagnostics]
    robot = dataclasses.replace(loaded.robot, diagnostics=(*loaded.robot.diagnostics, *extra))
    return dataclasses.replace(
        loaded, robot=robot, diagnostics=[*loaded.diagnostics, *extra], controllers=found
    )


def _unexpanded(text: str, element: Any) -> Diagnostic:
    return UnexpandedSubstitution.diagnostic(
        f"ros2_control plugin parameters '{text}' hold a xacro substitution in a file read as plain "
        "URDF: the plugin receives it as written and cannot open the controllers file",
        span_of(element), element="plugin/parameters",
        help="name the file .urdf.xacro (or .xacro.urdf) and run it through xacro, as its launch file "
        "should, or write the path out",
        data={"parameters": text},
    )


def _unreadable(path: str, exc: OSError) -> Diagnostic:
    return ControllersYamlInvalid.diagnostic(
        f"cannot read the controllers YAML: {exc.strerror or exc}", Span(path)
    )
