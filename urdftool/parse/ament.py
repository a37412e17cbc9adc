"""Where an ament package's ``install()`` rules take files from, read from its ``CMakeLists.txt``.

In ROS 2, ``$(find pkg)`` is the installed share folder (``share/pkg``). A path written for that
layout (``$(find pkg)/config/x.yaml``) names a file that, in a source tree, sits where an
``install(DIRECTORY bringup/config DESTINATION share/${PROJECT_NAME})`` rule takes it from. Kept
apart from the xacro reader so that looking a file up does not import xacro.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from urdftool.safe_files import read_up_to

_INSTALL = re.compile(r"\binstall\s*\(([^()]*)\)", re.IGNORECASE)
_INSTALL_KEYWORDS = frozenset({"DESTINATION", "FILES_MATCHING", "PATTERN", "REGEX", "EXCLUDE", "PERMISSIONS",
                               "USE_SOURCE_PERMISSIONS", "CONFIGURATIONS", "COMPONENT", "OPTIONAL",
                               "MESSAGE_NEVER", "FILE_PERMISSIONS", "DIRECTORY_PERMISSIONS", "TYPE"})


def installed_at(package: str, root: Path, relative: str) -> str | None:
    """The source file that the package's ament ``install(DIRECTORY … DESTINATION share/${PROJECT_NAME})``
    puts at *relative* (a path below ``$(find package)``), when it exists.

    In ROS 2, ``$(find pkg)`` is the installed share folder: an include written for that
    layout (``description/ros2_control`` installed as ``ros2_control``) is right, and is not
    where the file sits in the source tree.
    """
    try:
        text = read_up_to(str(root / "CMakeLists.txt"), "include").decode("utf-8", "replace")
    except OSError:
        return None
    text = re.sub(r"#[^\n]*", "", text)
    for call in _INSTALL.finditer(text):
        words = call.group(1).split()
        if not words or words[0].upper() != "DIRECTORY" or "DESTINATION" not in words:
            continue
        at = words.index("DESTINATION")
        destination = words[at + 1].strip("\"'") if at + 1 < len(words) else ""
        prefix = next((p for p in ("share/${PROJECT_NAME}", f"share/{package}")
                       if destination == p or destination.startswith(p + "/")), None)
        if prefix is None:
            continue
        below = destination[len(prefix):].strip("/")
        for source in words[1:at]:
            if source.upper() in _INSTALL_KEYWORDS:
                break
            source = source.strip("\"'")
            name = "" if source.endswith("/") else os.path.basename(source)
            base = "/".join(part for part in (below, name) if part)
            if not base or relative.startswith(base + "/"):
                candidate = (root / source / relative[len(base):].lstrip("/")).resolve()
                if root in candidate.parents and candidate.is_file():
                    return str(candidate)
    return None


def installed_source(path: str) -> str | None:
    """For a missing *path* below a package folder (what ``$(find pkg)/…`` becomes): the source
    file the package's ament install rule puts there, when it exists; else ``None``."""
    target = Path(os.path.abspath(path))
    for root in target.parents:
        manifest = root / "package.xml"
        if not manifest.is_file():
            continue
        try:
            text = read_up_to(str(manifest), "include").decode("utf-8", "replace")
        except OSError:
            return None
        name = re.search(r"<name>\s*([^<\s]+)\s*</name>", text)
        if name is None:
            return None
        return installed_at(name.group(1), root, target.relative_to(root).as_posix())
    return None
