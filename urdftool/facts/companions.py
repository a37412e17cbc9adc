"""Files that travel with a robot description: its SRDF (for ``check --target moveit``)."""

from __future__ import annotations

import glob
import os

from urdftool.facts.context import CheckContext

__all__ = ["srdf_files"]


def srdf_files(ctx: CheckContext) -> list[str]:
    """SRDF files for the robot: the run's ``srdf`` option, else ``*.srdf`` (and ``*.srdf.xacro``)
    in the file's folder, ``../srdf/`` or ``../config/``."""
    if "srdf-files" not in ctx.cache:
        given = ctx.options.get("srdf")
        if given:
            found = [str(given)]
        elif not ctx.robot.path:
            found = []
        else:
            here = os.path.dirname(os.path.abspath(ctx.robot.path))
            found = []
            for folder in (here, os.path.join(here, "..", "srdf"), os.path.join(here, "..", "config")):
                for pattern in ("*.srdf", "*.srdf.xacro"):
                    found.extend(sorted(glob.glob(os.path.join(glob.escape(folder), pattern))))
        ctx.cache["srdf-files"] = found
    files: list[str] = ctx.cache["srdf-files"]
    return files
