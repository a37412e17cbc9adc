"""Where a robot uses mesh files, where they resolved, and what they hold.

The meshes-and-geometry rules (``rules/meshes.py``) share one survey per
robot, kept in ``ctx.cache``, and read mesh contents only through this
module: the mesh elements in link order, each URI resolved once, each file
sniffed once, and each readable file loaded once (in parallel, through
:func:`urdftool.backends.meshes.load_many`) only when a selected rule needs
the contents. Nothing here imports trimesh; a robot without meshes never loads it.
"""

from __future__ import annotations

import math
import os
import stat
from collections.abc import Iterator

from urdftool.backends.mesh_formats import ENGINE_NAMES, MeshFormat, engines_refusing, sniff
from urdftool.backends.meshes import (
    MeshError,
    MeshFacts,
    MeshInfo,
    load_many,
    mesh_info,
    scaled_info,
)
from urdftool.facts.context import CheckContext
from urdftool.model import Link, Mesh, Pose, Resolution
from urdftool.parse.packages import PackageResolver
from urdftool.records import record
from urdftool.safe_files import describe_path, read_head
from urdftool.source import Span

__all__ = [
    "ENGINE_NAMES",
    "MeshError",
    "MeshFacts",
    "MeshFormat",
    "MeshInfo",
    "MeshUse",
    "by_file",
    "contents",
    "describe_path",
    "engines_refusing",
    "existing_file",
    "existing_files",
    "is_file",
    "lookup",
    "mesh_extents",
    "mesh_format",
    "mesh_uses",
    "read_head",
    "scaled_info",
]


@record
class MeshUse:
    """One ``<mesh>`` element: in which link, as visual or collision, and where it sits.

    ``origin`` is the geometry frame in the link frame.
    """

    link: str
    role: str
    mesh: Mesh
    origin: Pose

    @property
    def element(self) -> str:
        return f"link[{self.link}]/{self.role}/geometry/mesh"

    @property
    def location(self) -> Span | None:
        return self.mesh.span

    @property
    def describe(self) -> str:
        link = f"link '{self.link}'" if self.link else "an unnamed link"
        return f"{link}: {self.role} mesh '{self.mesh.filename}'"


def has_substitution(filename: str) -> bool:
    """A filename still holding ``$(…)`` or ``${…}`` (the syntax rules report it, not these)."""
    return "$(" in filename or "${" in filename


def uses_in(link: Link) -> Iterator[MeshUse]:
    for role, items in (("visual", link.visuals), ("collision", link.collisions)):
        for item in items:
            if isinstance(item.geometry, Mesh):
                yield MeshUse(link.name, role, item.geometry, item.origin)


def mesh_uses(ctx: CheckContext) -> list[MeshUse]:
    """Every mesh element of the robot, in link order, visuals before collisions."""
    if "mesh-uses" not in ctx.cache:
        uses = []
        for link in ctx.robot.links:  # uses_in() written out: it runs for every link of a check
            for role, items in (("visual", link.visuals), ("collision", link.collisions)):
                for item in items:
                    if isinstance(item.geometry, Mesh):
                        uses.append(MeshUse(link.name, role, item.geometry, item.origin))
        ctx.cache["mesh-uses"] = uses
    found: list[MeshUse] = ctx.cache["mesh-uses"]
    return found


def resolver(ctx: CheckContext) -> PackageResolver:
    """The run's resolver (``check`` passes the one the robot was read with)."""
    given = ctx.options.get("resolver")
    if isinstance(given, PackageResolver):
        return given
    if "mesh-resolver" not in ctx.cache:
        ctx.cache["mesh-resolver"] = PackageResolver.create()
    made: PackageResolver = ctx.cache["mesh-resolver"]
    return made


def lookup(ctx: CheckContext, use: MeshUse) -> Resolution:
    """How *use*'s URI was resolved: the reader's record on the mesh. Only a robot built in code
    (no record) is resolved here, once per URI and file, with the run's resolver."""
    if use.mesh.resolution is not None:
        return use.mesh.resolution
    base = use.location.path if use.location else ctx.robot.path
    return resolver(ctx).resolution(use.mesh.filename, base)


def existing_file(use: MeshUse) -> str | None:
    """The resolved path when it is a readable file, else ``None``."""
    path = use.mesh.resolved
    if path is None or has_substitution(use.mesh.filename):
        return None
    return path if os.path.isfile(path) else None


def existing_files(ctx: CheckContext) -> list[tuple[MeshUse, str | None]]:
    """Every mesh element (:func:`mesh_uses`) with its :func:`existing_file`, each file looked
    at once per check (a robot's meshes are asked for by most of the mesh rules)."""
    if "mesh-files" not in ctx.cache:
        found: list[tuple[MeshUse, str | None]] = []
        for use in mesh_uses(ctx):
            path = use.mesh.resolved
            if path is None or has_substitution(use.mesh.filename):
                found.append((use, None))
                continue
            known = status(ctx, path)
            found.append((use, path if known is not None and stat.S_ISREG(known.st_mode) else None))
        ctx.cache["mesh-files"] = found
    files: list[tuple[MeshUse, str | None]] = ctx.cache["mesh-files"]
    return files


def is_file(ctx: CheckContext, path: str) -> bool:
    """``os.path.isfile(path)``, from the file's :func:`status`."""
    found = status(ctx, path)
    return found is not None and stat.S_ISREG(found.st_mode)


def status(ctx: CheckContext, path: str) -> os.stat_result | None:
    """``os.stat(path)`` (``None`` when nothing is there), asked of the file system once per
    check: a robot's visual and collision elements often share one file, and whether it
    exists, its format and its content key all start from its status."""
    known: dict[str, os.stat_result | None] = ctx.cache.setdefault("mesh-status", {})
    if path in known:
        return known[path]
    try:
        found: os.stat_result | None = os.stat(path)
    except (OSError, ValueError):  # as os.path.isfile: a broken link, a NUL in the name
        found = None
    known[path] = found
    return found


def by_file(ctx: CheckContext, role: str | None = None) -> dict[str, list[MeshUse]]:
    """Existing mesh files -> the elements using them (optionally only visuals or collisions).

    Shared by every rule of the run: read it, never write into it.
    """
    key = ("mesh-by-file", role)
    if key not in ctx.cache:
        out: dict[str, list[MeshUse]] = {}
        for use, path in existing_files(ctx):
            if path is not None and (role is None or use.role == role):
                out.setdefault(path, []).append(use)
        ctx.cache[key] = out
    found: dict[str, list[MeshUse]] = ctx.cache[key]
    return found


def scaled_diagonal(
    ctx: CheckContext, path: str, facts: MeshFacts, scale: tuple[float, float, float]
) -> float:
    """The bounding-box diagonal (m) of the mesh at *path* (its *facts*) under *scale*, once per
    file and scale: a robot's links repeat a few meshes many times."""
    key = ("mesh-diagonal", path, scale)
    if key not in ctx.cache:
        # each side of the scaled box is |max·s − min·s|, the difference of the bounds that
        # scaled_bounds() would sort; summed in floats, without NumPy's dispatch per mesh
        lo, hi = facts.bounds_min, facts.bounds_max
        dx = abs(hi[0] * scale[0] - lo[0] * scale[0])
        dy = abs(hi[1] * scale[1] - lo[1] * scale[1])
        dz = abs(hi[2] * scale[2] - lo[2] * scale[2])
        ctx.cache[key] = math.sqrt(dx * dx + dy * dy + dz * dz)
    diagonal: float = ctx.cache[key]
    return diagonal


def mesh_format(ctx: CheckContext, path: str) -> MeshFormat | None:
    """The sniffed format of an existing mesh file (``None`` when it cannot be read at all)."""
    key = ("mesh-format", path)
    if key not in ctx.cache:
        try:
            ctx.cache[key] = sniff(path, status(ctx, path))
        except OSError:
            ctx.cache[key] = None
    found: MeshFormat | None = ctx.cache[key]
    return found


def contents(ctx: CheckContext) -> dict[str, MeshFacts | MeshError]:
    """Facts (or the read error) for every existing mesh file trimesh can read, loaded once."""
    if "mesh-contents" not in ctx.cache:
        paths = [
            p
            for p in by_file(ctx)
            if (fmt := mesh_format(ctx, p)) is not None and fmt.trimesh_reads
        ]
        if paths:
            statuses = {path: status(ctx, path) for path in paths}
            ctx.cache["mesh-contents"] = load_many(paths, ctx.options.get("jobs"), statuses)
        else:
            ctx.cache["mesh-contents"] = {}
    loaded: dict[str, MeshFacts | MeshError] = ctx.cache["mesh-contents"]
    return loaded


def other_places(uses: list[MeshUse]) -> str:
    """ ", also used at file:line, …" for the second and later elements of a group."""
    placed = [u.location for u in uses[1:] if u.location is not None]
    if not placed:
        return ""
    # only the places shown are put into words: finding a span's line and column costs more
    # than the rest of the finding
    shown = ", ".join(dict.fromkeys(str(span) for span in placed[:4]))
    more = f" and {len(placed) - 4} more" if len(placed) > 4 else ""
    return f"; also used at {shown}{more}"


def mesh_extents(path: str, scale: tuple[float, float, float]) -> tuple[float, float, float] | None:
    """The scaled bounding-box extents (m) of the mesh file at *path*, ``None`` when unreadable."""
    try:
        info = mesh_info(path, scale)
    except MeshError:
        return None
    x, y, z = (float(v) for v in info.extents)
    return (x, y, z)


def in_ros_package(ctx: CheckContext, path: str) -> bool:
    """Whether the file at *path* sits in a ROS package: a ``package.xml`` in its folder or one
    above it (ROS tools reach its files by ``package://``). Memoised per folder."""
    folder = os.path.dirname(os.path.abspath(path))
    key = ("in-ros-package", folder)
    if key not in ctx.cache:
        here, found = folder, False
        while True:
            if os.path.isfile(os.path.join(here, "package.xml")):
                found = True
                break
            parent = os.path.dirname(here)
            if parent == here:
                break
            here = parent
        ctx.cache[key] = found
    return bool(ctx.cache[key])
