"""Files that travel with a robot description: its SRDF (for ``check --target moveit``)."""

from __future__ import annotations

import glob
import os

from urdftool.facts.context import CheckContext

__all__ = ["srdf_files"]


def srdf_files(ctx: CheckContext) -> list[str]:
    """SRDF files for the robot: the run's ``srdf`` option, else ``<file stem or robot name>.srdf``
    beside the file, or any ``*.srdf`` (``*.srdf.xacro``) in ``../srdf/`` or ``../config/``."""
    if "srdf-files" not in ctx.cache:
        given = ctx.options.get("srdf")
        if given:
            found = [str(given)]
        elif not ctx.robot.path:
            found = []
        else:
            here = os.path.dirname(os.path.abspath(ctx.robot.path))
            stem = os.path.basename(ctx.robot.path).split(".")[0]
            names = {n for n in (stem, ctx.robot.name) if n}
            found = []
            # beside the file: only an SRDF named after it or its robot (a folder of robots is common)
            for name in sorted(names):
                for suffix in (".srdf", ".srdf.xacro"):
                    candidate = os.path.join(here, name + suffix)
                    if os.path.isfile(candidate):
                        found.append(candidate)
            for folder in (os.path.join(here, "..", "srdf"), os.path.join(here, "..", "config")):
                for pattern in ("*.srdf", "*.srdf.xacro"):
                    found.extend(sorted(glob.glob(os.path.join(glob.escape(folder), pattern))))
        ctx.cache["srdf-files"] = found
    files: list[str] = ctx.cache["srdf-files"]
    return files
