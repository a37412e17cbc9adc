"""Mesh assets for MJCF: which files MuJoCo reads as they are, which are converted, and their names.

MuJoCo reads binary STL (up to 200000 triangles), OBJ and MSH. Every other
mesh trimesh can load (DAE, ASCII STL, PLY, ...) is converted to binary STL in
``assets/`` beside OUT (to OBJ above MuJoCo's STL triangle limit).
With ``copy_assets`` the readable meshes are copied there too; otherwise they
are referenced by their path relative to OUT's folder.

A COLLADA or OBJ visual with materials of several colours is split into one mesh
per colour, each with a ``<material>`` of that colour (:meth:`AssetPlan.visual_parts`),
as MuJoCo Menagerie writes its Panda (``link0_0`` … with ``off_white``,
``black``) and as ``obj2mjcf`` splits an OBJ by its ``.mtl`` materials; collision
geometry always uses the whole mesh.

Asset files and ``<mesh>`` names carry a hash of the file's content, so two
files that share a name (``visual/x.stl``, ``collision/x.stl``) never collide
and two copies of one mesh become one asset. A mesh used at two scales is two
``<mesh>`` elements (MuJoCo scales meshes, not geoms).
"""

from __future__ import annotations

import functools
import json
import os
import struct
from dataclasses import field
from pathlib import Path

import numpy as np

from urdftool.backends import mesh_cache
from urdftool.backends.collision_shapes import is_generated
from urdftool.backends.mesh_materials import COLOURED_SUFFIXES, RGBA8, coloured_parts
from urdftool.backends.meshes import MeshError, load_trimesh
from urdftool.export.assets import (
    MeshUnavailable,
    absolute_asset,
    asset_name,
    content_hash,
    is_binary_stl,
    safe_stem,
)
from urdftool.model import Mesh
from urdftool.model.pose import Vec3
from urdftool.records import record
from urdftool.safe_files import read_regular

#: Suffixes MuJoCo's compiler reads itself.
NATIVE_SUFFIXES = (".stl", ".obj", ".msh")
#: MuJoCo's STL decoder refuses files with more triangles.
MAX_STL_TRIANGLES = 200000


@record
class MeshAsset:
    """One ``<mesh>`` element: its name, file (relative to OUT's folder, or absolute) and scale."""

    name: str
    file: str
    scale: Vec3


@record
class VisualPart:
    """One visual geom of a mesh: its ``<mesh>`` name and the ``<material>`` giving its colour
    (``None``: the mesh carries no colour of its own for these triangles)."""

    mesh: str
    material: str | None


def material_name(rgba: RGBA8) -> str:
    """``<material>`` name of an 8-bit colour: ``rgba_e6ebedff``."""
    return "rgba_" + "".join(f"{c:02x}" for c in rgba)


def material_rgba(rgba: RGBA8) -> tuple[float, float, float, float]:
    """An 8-bit colour as MJCF's 0..1 floats, to 4 decimals (1/255 steps need no more)."""
    r, g, b, a = (round(c / 255, 4) for c in rgba)
    return (r, g, b, a)


def mujoco_reads(suffix: str, data: bytes) -> bool:
    """True when MuJoCo's own decoders read this file as it is."""
    if suffix not in NATIVE_SUFFIXES:
        return False
    if suffix != ".stl":
        return True
    return is_binary_stl(data) and 0 < struct.unpack_from("<I", data, 80)[0] <= MAX_STL_TRIANGLES


def binary_stl(vertices: np.ndarray, faces: np.ndarray) -> bytes:
    """A deterministic binary STL (zero header, float32 normals and vertices)."""
    triangles = np.asarray(vertices, dtype=np.float64)[np.asarray(faces, dtype=np.int64)]
    normals = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    lengths = np.linalg.norm(normals, axis=1, keepdims=True)
    normals = np.divide(normals, lengths, out=np.zeros_like(normals), where=lengths > 0)
    record = np.zeros(len(faces), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    record["n"] = normals
    record["v"] = triangles
    return b"\0" * 80 + struct.pack("<I", len(faces)) + record.tobytes()


def wavefront_obj(vertices: np.ndarray, faces: np.ndarray) -> bytes:
    """A deterministic OBJ (vertices and triangles only), for meshes too large for STL."""
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in np.asarray(vertices, dtype=float).tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in np.asarray(faces, dtype=np.int64).tolist()]
    return ("\n".join(lines) + "\n").encode("ascii")


@functools.lru_cache(maxsize=128)
def _convert_cached(content: str, path: str) -> tuple[bytes, str]:
    """:func:`convert` once per file content: in memory for this process (robots share meshes)
    and on disk across runs (the mesh cache, keyed by the source's content hash)."""
    for suffix in (".stl", ".obj"):
        stored = mesh_cache.get_blob(f"mjcf{suffix}", content)
        if stored is not None:
            return stored, suffix
    data, suffix = convert(path)
    mesh_cache.put_blob(f"mjcf{suffix}", content, data)
    return data, suffix


#: Cache kind of the colour split (:func:`_parts_cached`); a new kind, so the entries of ``mjcf.stl``
#: and the mesh facts keep their meaning and the cache schema need not change.
PARTS_KIND = "mjcf-colours1"


@functools.lru_cache(maxsize=128)
def _parts_cached(content: str, path: str) -> tuple[tuple[RGBA8 | None, bytes, str], ...]:
    """:func:`split_by_colour` once per file content, in memory and in the disk mesh cache."""
    stored = mesh_cache.get_blob(PARTS_KIND, content)
    if stored is not None:
        try:
            return _unpack_parts(stored)
        except (ValueError, KeyError, TypeError):
            pass  # a damaged entry is computed again
    parts = split_by_colour(path)
    mesh_cache.put_blob(PARTS_KIND, content, _pack_parts(parts))
    return parts


def split_by_colour(path: str) -> tuple[tuple[RGBA8 | None, bytes, str], ...]:
    """The visual COLLADA or OBJ file at *path* as (colour, file bytes, suffix) per colour. Empty
    when it has no colour; one entry with empty bytes when all its triangles share one colour (the whole
    mesh is used then, the same asset as its collision use)."""
    parts = coloured_parts(path)
    if len(parts) == 1:
        return ((parts[0].rgba, b"", ""),)
    out = []
    for part in parts:
        if len(part.faces) > MAX_STL_TRIANGLES:
            out.append((part.rgba, wavefront_obj(part.vertices, part.faces), ".obj"))
        else:
            out.append((part.rgba, binary_stl(part.vertices, part.faces), ".stl"))
    return tuple(out)


def _pack_parts(parts: tuple[tuple[RGBA8 | None, bytes, str], ...]) -> bytes:
    """One cache blob: a JSON line listing colour, suffix and size of each part, then the bytes."""
    header = [{"rgba": list(rgba) if rgba else None, "suffix": suffix, "size": len(data)}
              for rgba, data, suffix in parts]
    return json.dumps(header).encode("utf-8") + b"\n" + b"".join(data for _, data, _ in parts)


def _unpack_parts(blob: bytes) -> tuple[tuple[RGBA8 | None, bytes, str], ...]:
    head, _, body = blob.partition(b"\n")
    parts = []
    offset = 0
    for entry in json.loads(head):
        size = int(entry["size"])
        rgba = entry["rgba"]
        colour: RGBA8 | None = (int(rgba[0]), int(rgba[1]), int(rgba[2]), int(rgba[3])) if rgba else None
        parts.append((colour, body[offset:offset + size], str(entry["suffix"])))
        offset += size
    if offset != len(body):
        raise ValueError("truncated cache entry")
    return tuple(parts)


def convert(path: str) -> tuple[bytes, str]:
    """Load *path* with trimesh (scenes flattened with their transforms); return the bytes and
    suffix of a file MuJoCo reads: binary STL, or OBJ above the STL triangle limit."""
    try:
        mesh = load_trimesh(path)
    except MeshError as exc:
        raise MeshUnavailable(f"trimesh cannot read it ({exc})") from exc
    if len(mesh.faces) > MAX_STL_TRIANGLES:
        return wavefront_obj(mesh.vertices, mesh.faces), ".obj"
    return binary_stl(mesh.vertices, mesh.faces), ".stl"


@record(frozen=False)
class AssetPlan:
    """Collects the meshes of one export: ``<mesh>`` elements and files to write under OUT's folder."""

    out_dir: Path | None
    copy: bool = False
    #: every ``file`` absolute: source meshes where they are, written files under *out_dir*
    absolute: bool = False
    meshes: list[MeshAsset] = field(default_factory=list)
    files: dict[str, bytes] = field(default_factory=dict)
    #: ``<material>`` name -> rgba (0..1), for the colours of split COLLADA visuals
    materials: dict[str, tuple[float, float, float, float]] = field(default_factory=dict)
    #: (source content hash, scale) -> mesh name
    _by_content: dict[tuple[str, Vec3], str] = field(default_factory=dict)
    #: resolved path -> (content hash, file reference for MJCF)
    _by_path: dict[str, tuple[str, str]] = field(default_factory=dict)
    #: resolved path -> content hash, for files read only to split them by colour
    _hashes: dict[str, str] = field(default_factory=dict)

    def mesh_name(self, mesh: Mesh) -> str:
        """The ``<mesh>`` name for this geometry, adding the asset on first use.

        Raises :class:`MeshUnavailable` when the file cannot be carried.
        """
        if mesh.resolved is None:
            raise MeshUnavailable(f"'{mesh.filename}' did not resolve to a file")
        content, reference = self._file_for(mesh.resolved)
        return self._named((content, _scale(mesh)), f"{safe_stem(mesh.resolved)}-{content[:8]}",
                           reference)

    def visual_parts(self, mesh: Mesh) -> list[VisualPart]:
        """The visual geoms for this geometry: one per colour of a multi-colour COLLADA or OBJ
        file (with its material), else the whole mesh: with the material of a single-colour
        file, without a colour of its own otherwise. Raises :class:`MeshUnavailable`.
        """
        path = mesh.resolved
        if path is None or not path.lower().endswith(COLOURED_SUFFIXES):
            return [VisualPart(self.mesh_name(mesh), None)]
        content = self._content(path)
        parts = _parts_cached(content, path)
        if len(parts) <= 1:
            rgba = parts[0][0] if parts else None
            return [VisualPart(self.mesh_name(mesh), self._material(rgba) if rgba else None)]
        out = []
        for number, (rgba, payload, suffix) in enumerate(parts):
            reference = asset_name(path, payload, suffix)
            self.files[reference] = payload
            base = f"{safe_stem(path)}-{content[:8]}_{number}"
            name = self._named((f"{content}#{number}", _scale(mesh)), base, self._written(reference))
            out.append(VisualPart(name, self._material(rgba) if rgba else None))
        return out

    def _content(self, path: str) -> str:
        """SHA-256 of the file's bytes (without planning its conversion)."""
        if path in self._by_path:
            return self._by_path[path][0]
        if path not in self._hashes:
            try:
                self._hashes[path] = content_hash(read_regular(path, "mesh"))
            except OSError as exc:
                raise MeshUnavailable(f"cannot read '{path}' ({exc.strerror or exc})") from exc
        return self._hashes[path]

    def _material(self, rgba: RGBA8) -> str:
        name = material_name(rgba)
        self.materials.setdefault(name, material_rgba(rgba))
        return name

    def _named(self, key: tuple[str, Vec3], base: str, reference: str) -> str:
        """The ``<mesh>`` name for *key*, adding a :class:`MeshAsset` on first use."""
        if key in self._by_content:
            return self._by_content[key]
        taken = {m.name for m in self.meshes}
        name, n = base, 1
        while name in taken:
            n += 1
            name = f"{base}-s{n}"
        self._by_content[key] = name
        self.meshes.append(MeshAsset(name, reference, key[1]))
        return name

    def _file_for(self, path: str) -> tuple[str, str]:
        if path in self._by_path:
            return self._by_path[path]
        try:
            data = read_regular(path, "mesh")
        except OSError as exc:
            raise MeshUnavailable(f"cannot read '{path}' ({exc.strerror or exc})") from exc
        content = content_hash(data)
        suffix = Path(path).suffix.lower()
        native = mujoco_reads(suffix, data)
        if native and not self.copy and not is_generated(path):
            reference = self._reference(path)
        else:
            payload, out_suffix = (data, suffix) if native else _convert_cached(content, path)
            written = asset_name(path, payload, out_suffix)
            self.files[written] = payload
            reference = self._written(written)
        self._by_path[path] = (content, reference)
        return content, reference

    def _written(self, reference: str) -> str:
        """The ``file`` of an asset written at *reference* (relative to OUT's folder)."""
        return absolute_asset(reference, self.out_dir) if self.absolute else reference

    def _reference(self, path: str) -> str:
        """*path* relative to OUT's folder (forward slashes), or absolute when there is no OUT."""
        if self.out_dir is None or self.absolute:
            return Path(path).resolve().as_posix()
        try:
            return Path(os.path.relpath(Path(path).resolve(), self.out_dir.resolve())).as_posix()
        except ValueError:  # another drive on Windows
            return Path(path).resolve().as_posix()


def _scale(mesh: Mesh) -> Vec3:
    sx, sy, sz = mesh.scale
    return (float(sx), float(sy), float(sz))

