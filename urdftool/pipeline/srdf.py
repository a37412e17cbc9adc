"""The SRDF beside a model: discovery, reading, and attaching it to the loaded model.

MoveIt reads a robot from two files, the URDF and the SRDF; ``check`` reads
both when it can find the SRDF, so the SRDF rules (:mod:`urdftool.rules.srdf`)
can check one against the other. The SRDF is taken from ``--srdf FILE`` when
given; otherwise it is looked for beside the model (see :func:`find_srdf`).
The SRDF's own reader findings join the model's, and its files join the
model's files, so inline suppressions in the ``.srdf`` work as in the URDF.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Mapping

from urdftool.catalogue.syntax import XmlSyntax
from urdftool.diagnostics import Diagnostic
from urdftool.parse import Loaded
from urdftool.parse.packages import PackageResolver
from urdftool.source import Span

#: Model suffixes stripped to get the stem an SRDF shares, longest first.
_MODEL_SUFFIXES = (".urdf.xacro", ".xacro", ".urdf")
#: Folders, relative to the model's folder, where an SRDF of the same stem is looked for.
_SIBLING_DIRS = (".", "../srdf", "../config", "config", "srdf")


def model_stem(path: str) -> str | None:
    name = os.path.basename(path)
    lower = name.lower()
    for suffix in _MODEL_SUFFIXES:
        if lower.endswith(suffix):
            return name[: -len(suffix)]
    return None


def package_root(path: str) -> str | None:
    """The nearest folder above *path* that holds a ``package.xml``."""
    folder = os.path.dirname(os.path.abspath(path))
    while True:
        if os.path.isfile(os.path.join(folder, "package.xml")):
            return folder
        parent = os.path.dirname(folder)
        if parent == folder:
            return None
        folder = parent


def find_srdf(model_path: str, robot_name: str | None = None) -> str | None:
    """The SRDF that belongs to the model at *model_path*, or ``None``.

    In order: ``STEM.srdf`` or ``STEM.srdf.xacro`` in the model's folder, in a
    sibling ``srdf/`` or ``config/`` folder (example-robot-data's and MoveIt
    configuration packages' layouts) or in ``config/`` and ``srdf/`` below it;
    then, in the ROS package that holds the model, ``config/*.srdf`` (or
    ``.srdf.xacro``) named after the stem or the robot, or the only one there.
    A URDF (not a xacro) never claims a SRDF of another stem, so the several
    URDF variants of one package each meet only their own SRDF.
    """
    stem = model_stem(model_path)
    if stem is None:
        return None
    folder = os.path.dirname(os.path.abspath(model_path))
    for sub in _SIBLING_DIRS:
        directory = os.path.normpath(os.path.join(folder, sub))
        # One look at the folder before two at the files in it: most of these folders do not
        # exist, and the discovery runs for every model checked.
        if sub != "." and not os.path.isdir(directory):
            continue
        for suffix in (".srdf", ".srdf.xacro"):
            candidate = os.path.join(directory, stem + suffix)
            if os.path.isfile(candidate):
                return candidate
    root = package_root(model_path)
    if root is None:
        return None
    config = os.path.join(root, "config")
    try:
        names = os.listdir(config)
    except OSError:  # no config folder, the commonest case (a glob took longer to say so)
        return None
    found = sorted(os.path.join(config, name) for name in names  # as glob's *.srdf: no hidden files
                   if name.endswith((".srdf", ".srdf.xacro")) and not name.startswith("."))
    for name in (stem, robot_name):
        for candidate in found:
            base = os.path.basename(candidate)
            if name and base.split(".srdf")[0] == name:
                return candidate
    return found[0] if len(found) == 1 else None


def attach(loaded: Loaded, srdf_path: str | None, resolver: PackageResolver, discover: bool = True,
           args: Mapping[str, str] | None = None) -> Loaded:
    """*loaded* with its SRDF read (from *srdf_path*, else discovered) and its findings joined;
    an ``.srdf.xacro`` is expanded with the model's xacro *args*, as a MoveIt launch file does."""
    if loaded.robot is None:
        return loaded
    path = srdf_path or (find_srdf(loaded.path, loaded.robot.name) if discover else None)
    if path is None:
        return loaded
    # Function-level: the SRDF reader brings the xacro processor, which a plain URDF never needs.
    from urdftool.parse.srdf import Srdf, read_srdf

    try:
        srdf = read_srdf(path, resolver, args)
    except OSError as exc:
        srdf = Srdf(path, diagnostics=[_unreadable(path, exc)])
    robot = dataclasses.replace(loaded.robot, diagnostics=(*loaded.robot.diagnostics, *srdf.diagnostics))
    files = [*loaded.files, *(f for f in srdf.files if f not in loaded.files)]
    return dataclasses.replace(loaded, robot=robot, diagnostics=[*loaded.diagnostics, *srdf.diagnostics],
                               files=files, srdf=srdf)


def _unreadable(path: str, exc: OSError) -> Diagnostic:
    return XmlSyntax.diagnostic(f"cannot read the SRDF: {exc.strerror or exc}", Span(path))
