"""Which files ``urdftool check DIR`` reads.

Directories are walked recursively for ``*.urdf``, ``*.xacro``, ``*.urdf.xacro``,
``*.sdf`` and ``*.world`` (hidden folders and virtual environments skipped).
A xacro file that another xacro file in the same set includes is a fragment
(a macro library or a piece of a robot): it is checked through its includer,
not on its own, since alone it usually cannot expand. Files named explicitly
on the command line are always checked.
"""

from __future__ import annotations

import fnmatch
import os
import re
from collections.abc import Iterable, Sequence
from pathlib import Path

from urdftool.parse import SUFFIXES
from urdftool.parse.packages import PackageResolver

_SKIP = {".git", ".hg", ".svn", "node_modules", "__pycache__", ".venv", "venv", ".tox", "build", "install"}
_INCLUDE = re.compile(rb"<xacro:include\b[^>]*?\bfilename\s*=\s*[\"']([^\"']+)[\"']", re.DOTALL)
_FIND = re.compile(r"\$\(find\s+([^)\s]+)\)")
_DIRNAME = re.compile(r"\$\(dirname\)")


def is_model_file(path: str) -> bool:
    lower = path.lower()
    return any(lower.endswith(suffix) for suffix, _ in SUFFIXES)


def walk(directory: str) -> list[str]:
    """Model files below *directory*, sorted."""
    found: list[str] = []
    for root, dirs, files in os.walk(directory):
        dirs[:] = sorted(d for d in dirs if d not in _SKIP and not d.startswith("."))
        found.extend(os.path.join(root, f) for f in sorted(files) if is_model_file(f))
    return found


def included_files(path: str, resolver: PackageResolver) -> set[str]:
    """Absolute paths that *path* includes with ``<xacro:include>``, where they can be worked out
    without expanding it (``$(find PKG)``, ``$(dirname)`` and relative paths)."""
    try:
        data = Path(path).read_bytes()
    except OSError:
        return set()
    base = Path(path).resolve().parent
    out: set[str] = set()
    for raw in _INCLUDE.findall(data):
        spec = raw.decode("utf-8", "replace")
        spec = _DIRNAME.sub(str(base), spec)

        def find(match: re.Match[str]) -> str:
            lookup = resolver.find_package(match.group(1), path)
            return lookup.path or match.group(0)

        spec = _FIND.sub(find, spec)
        if "$" in spec:
            continue
        target = Path(spec) if os.path.isabs(spec) else base / spec
        out.add(str(target.resolve()))
        # An include whose path is stale still marks a file of that name in the
        # same package as a fragment (see include-not-at-path).
        out.add("name:" + target.name)
    return out


def excluded(relative: str, patterns: Iterable[str]) -> bool:
    """Whether the file at *relative* (a path relative to the folder the patterns belong to, with
    ``/``) matches one of *patterns*, as a ``.gitignore`` line would: a pattern with a ``/`` matches
    the path or a folder at its start (``exports``, ``robots/old/*.urdf``); one without matches
    any file or folder name on the path (``*_pb.urdf``, ``build``)."""
    parts = relative.split("/")
    for pattern in patterns:
        pattern = pattern.strip().strip("/")
        if not pattern:
            continue
        if "/" in pattern:
            if fnmatch.fnmatchcase(relative, pattern) or any(
                    fnmatch.fnmatchcase("/".join(parts[:n]), pattern) for n in range(1, len(parts))):
                return True
        elif any(fnmatch.fnmatchcase(part, pattern) for part in parts):
            return True
    return False


def expand_paths(paths: Sequence[str], resolver: PackageResolver, exclude: Sequence[str] = ()) -> list[str]:
    """The files to check for *paths*: files as given, directories walked (less what *exclude*
    matches, relative to the directory walked), fragments dropped."""
    explicit: list[str] = []
    walked: list[str] = []
    for p in paths:
        if os.path.isdir(p):
            walked.extend(f for f in walk(p)
                          if not excluded(Path(os.path.relpath(f, p)).as_posix(), exclude))
        else:
            explicit.append(p)
    fragments = _fragments(walked, resolver)
    chosen = explicit + [p for p in walked if str(Path(p).resolve()) not in fragments]
    return _dedupe(chosen)


def _fragments(files: Iterable[str], resolver: PackageResolver) -> set[str]:
    files = list(files)
    xacros = [f for f in files if f.lower().endswith(".xacro")]
    included: set[str] = set()
    for f in xacros:
        included |= included_files(f, resolver)
    names = {i[5:] for i in included if i.startswith("name:")}
    out = set()
    for f in xacros:
        resolved = str(Path(f).resolve())
        if resolved in included or (Path(f).name in names and _is_stale_target(f, included)):
            out.add(resolved)
    return out


def _is_stale_target(path: str, included: set[str]) -> bool:
    """True when some include names *path*'s file name but points at a file that does not exist."""
    name = Path(path).name
    return any(
        Path(i).name == name and not os.path.exists(i) for i in included if not i.startswith("name:")
    )


def _dedupe(paths: Iterable[str]) -> list[str]:
    seen: set[str] = set()
    out = []
    for p in paths:
        key = str(Path(p).resolve())
        if key not in seen:
            seen.add(key)
            out.append(p)
    return out
