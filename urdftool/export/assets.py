"""Mesh files carried into an export: referenced where they are, copied, or converted.

Shared by the exporters that write mesh files beside OUT. A target says which
files its engine reads as they are (:attr:`MeshFiles.native`) and how to
convert the others (:attr:`MeshFiles.convert`). Readable files are referenced
by their path relative to OUT's folder, or copied into ``assets/`` with
``copy``; converted files always go to ``assets/``.

Asset names carry a hash of the bytes written (``hokuyo-3f2a9c01b4de.obj``):
two source files that share a name never collide, one mesh used twice is
written once, and reruns give identical names and bytes.
"""

from __future__ import annotations

import hashlib
import os
import re
import struct
from collections.abc import Callable
from dataclasses import field
from pathlib import Path

from urdftool.backends.collision_shapes import is_generated
from urdftool.records import record
from urdftool.safe_files import read_regular

ASSETS_DIR = "assets"


class MeshUnavailable(Exception):
    """The mesh file is missing, or neither the engine nor trimesh can read it."""


def content_hash(data: bytes) -> str:
    """SHA-256 hex digest of *data*."""
    return hashlib.sha256(data).hexdigest()


def safe_stem(path: str) -> str:
    """The file name before its first dot, reduced to ``[A-Za-z0-9_-]`` (``mesh`` when empty)."""
    stem = Path(path).name.split(".")[0] or "mesh"
    return re.sub(r"[^A-Za-z0-9_-]", "_", stem)


def asset_name(source: str, payload: bytes, suffix: str) -> str:
    """``assets/<stem>-<12 hex digits of the payload's hash><suffix>``."""
    return f"{ASSETS_DIR}/{safe_stem(source)}-{content_hash(payload)[:12]}{suffix}"


def is_binary_stl(data: bytes) -> bool:
    """A binary STL has exactly 84 + 50 × (triangle count) bytes; ASCII STL does not."""
    if len(data) < 84:
        return False
    count: int = struct.unpack_from("<I", data, 80)[0]
    return len(data) == 84 + 50 * count


def relative_reference(path: str, out_dir: Path | None) -> str:
    """*path* relative to *out_dir* with forward slashes; absolute when there is no OUT folder."""
    if out_dir is None:
        return Path(path).resolve().as_posix()
    try:
        return Path(os.path.relpath(Path(path).resolve(), out_dir.resolve())).as_posix()
    except ValueError:  # another drive on Windows
        return Path(path).resolve().as_posix()


def absolute_asset(reference: str, out_dir: Path | None) -> str:
    """*reference* (``assets/...``, relative to OUT's folder) as an absolute path."""
    return ((out_dir or Path.cwd()).resolve() / reference).as_posix()


@record
class MeshFile:
    """Where a source mesh went: the reference to write, and whether it was converted."""

    reference: str
    converted: bool
    #: SHA-256 of the source file's bytes
    source_hash: str


@record(frozen=False)
class MeshFiles:
    """The mesh files of one export, keyed by resolved source path.

    ``native(path, data)`` says whether the engine reads the file as it is;
    ``convert(path)`` returns the converted bytes (raising
    :class:`MeshUnavailable`) in the format named by ``converted_suffix``.
    ``files`` collects what must be written, relative to OUT's folder.
    """

    out_dir: Path | None
    native: Callable[[str, bytes], bool]
    convert: Callable[[str], bytes]
    converted_suffix: str
    copy: bool = False
    #: every reference absolute: source meshes where they are, written files under *out_dir*
    #: (the Python API without an OUT, whose text is loaded from anywhere)
    absolute: bool = False
    files: dict[str, bytes] = field(default_factory=dict)
    _seen: dict[str, MeshFile] = field(default_factory=dict)

    def carry(self, path: str) -> MeshFile:
        """The file for the mesh at *path*, planned on first use. Raises :class:`MeshUnavailable`."""
        if path in self._seen:
            return self._seen[path]
        try:
            data = read_regular(path, "mesh")
        except OSError as exc:
            raise MeshUnavailable(f"cannot read '{path}' ({exc.strerror or exc})") from exc
        native = self.native(path, data)
        if native and not self.copy and not is_generated(path):
            planned = MeshFile(relative_reference(path, None if self.absolute else self.out_dir), False,
                               content_hash(data))
        else:
            payload = data if native else self.convert(path)
            suffix = Path(path).suffix.lower() if native else self.converted_suffix
            reference = asset_name(path, payload, suffix)
            self.files[reference] = payload
            planned = MeshFile(absolute_asset(reference, self.out_dir) if self.absolute else reference,
                               not native, content_hash(data))
        self._seen[path] = planned
        return planned
