"""The persistent mesh cache: what a mesh file holds, keyed by its content hash.

Loading meshes is the slow part of a check (COLLADA above all), and mesh files
rarely change, so the facts urdftool derives from a file are kept on disk under
the user cache folder and reused by every later run, from any project, for any
file with the same bytes:

    $URDFTOOL_CACHE_DIR, else $XDG_CACHE_HOME/urdftool, else ~/.cache/urdftool
        meshes/v<SCHEMA>-trimesh<version>/<first two hex digits>/<sha256>.json

The trimesh version is part of the folder name, so a trimesh upgrade (which may
read a file differently) starts a fresh cache. ``URDFTOOL_NO_CACHE=1`` turns
the cache off. A cache that cannot be read or written is ignored: it makes
checks faster, never different, and never makes them fail.

Exports keep their mesh conversions there too (``converted/<kind>/``, by the
source's content hash): a second ``urdftool convert`` of a robot with COLLADA
meshes reads the converted bytes instead of converting again. ``exports/`` holds
the files that ``urdftool.to_mjcf(robot)`` and ``to_urdf(robot, flavor="pybullet")``
without an output file refer to by absolute path (:func:`export_folder`). Each kind is a
folder of its own (``mjcf.stl``, ``mjcf.obj``, ``mjcf-colours1`` for a visual
split by material colour), so a new kind needs no new :data:`SCHEMA`.
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from functools import lru_cache
from pathlib import Path
from typing import Any

#: Bump when the stored facts change shape or meaning.
SCHEMA = 5  # 2: a COLLADA file is read up to its first NUL byte, as Assimp reads it;
#            3: a closed mesh with some triangles reversed is measured with its winding fixed;
#            4: a COLLADA attribute value holding "<" is read, as Assimp and tinyxml2 read it;
#            5: a COLLADA file with a comment among a mesh's primitives is read, as Assimp reads it


@lru_cache(maxsize=1)
def _trimesh_version() -> str:
    # importlib.metadata reads the installed version without importing trimesh.
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("trimesh")
    except PackageNotFoundError:
        return "none"


def cache_root() -> Path | None:
    """The folder holding this urdftool/trimesh pair's mesh facts, or ``None`` when disabled."""
    if os.environ.get("URDFTOOL_NO_CACHE", "").strip() not in ("", "0"):
        return None
    base = os.environ.get("URDFTOOL_CACHE_DIR")
    if not base:
        xdg = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        base = os.path.join(xdg, "urdftool")
    return Path(base) / "meshes" / f"v{SCHEMA}-trimesh{_trimesh_version()}"


def _entry(root: Path, key: str) -> Path:
    return root / key[:2] / f"{key}.json"


def get(key: str) -> dict[str, Any] | None:
    """The stored facts for content hash *key*, or ``None``."""
    root = cache_root()
    if root is None:
        return None
    try:
        with open(_entry(root, key), encoding="utf-8") as handle:
            value = json.load(handle)
    except (OSError, ValueError):
        return None
    return value if isinstance(value, dict) else None


def put(key: str, value: dict[str, Any]) -> None:
    """Store *value* for *key*; concurrent writers are safe (write a temporary file, then rename).

    No fsync: a cache entry lost in a crash is simply computed again.
    """
    root = cache_root()
    if root is not None:
        text = json.dumps(value, separators=(",", ":"), sort_keys=True)
        _store(_entry(root, key), text.encode("utf-8"))


def _store(target: Path, data: bytes) -> bool:
    """Write *data* to *target* through a temporary file and a rename; an error is ignored
    (``False``)."""
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=".entry.", suffix=".tmp", dir=target.parent)
        try:
            with os.fdopen(fd, "wb") as handle:
                handle.write(data)
            os.replace(tmp, target)
        except BaseException:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
            raise
    except OSError:
        return False
    return True


def _blob_entry(root: Path, kind: str, key: str) -> Path:
    return root / "converted" / kind / key[:2] / key


def get_blob(kind: str, key: str) -> bytes | None:
    """A stored conversion of a mesh (*kind* names the conversion, *key* the source content hash)."""
    root = cache_root()
    if root is None:
        return None
    try:
        return _blob_entry(root, kind, key).read_bytes()
    except OSError:
        return None


def put_blob(kind: str, key: str, data: bytes) -> None:
    """Store a conversion's bytes (same guarantees as :func:`put`: atomic, failures ignored)."""
    root = cache_root()
    if root is not None:
        _store(_blob_entry(root, kind, key), data)


def export_folder() -> Path | None:
    """Where an export without an output file keeps the files its text refers to (meshes
    converted for MuJoCo or PyBullet, by content hash: ``assets/<stem>-<hash>.<ext>``), or
    ``None`` when the cache is off."""
    root = cache_root()
    return None if root is None else root / "exports"


def store_export_file(folder: Path, relative: str, data: bytes) -> bool:
    """Write one such file (atomically; an existing file of that name holds the same bytes, its
    name being their hash). ``False`` when it cannot be written."""
    target = folder / relative
    if target.is_file() and target.stat().st_size == len(data):
        return True
    return _store(target, data)
