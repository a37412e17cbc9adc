"""Meshes and geometry (M): files that resolve, load, and have plausible sizes.

The rules share one survey per robot (:mod:`urdftool.rules.mesh_survey`): each
URI is resolved once, each file sniffed once, and each readable file loaded
once, in parallel, only when a selected rule needs its contents. Findings about
a file are reported once per robot, at the first element that uses it.
Thresholds and their calibration on the corpora are in ``docs/meshes.md``.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
else:
    # NumPy is imported on first use: a structural check must not pay for it.
    from urdftool.lazy import numpy as np

from urdftool.diagnostics import Diagnostic, Severity
from urdftool.rules import mesh_survey as survey
from urdftool.rules.mesh_geometry import (
    FACE_BUDGET,
    UNITS_TOO_LARGE,
    UNITS_TOO_SMALL,
    degenerate_shape,
    moving_groups,
    robot_size,
    suggested_factor,
)
from urdftool.rules.registry import CheckContext, Family, Rule, register
from urdftool.safe_files import describe_path, read_head

if TYPE_CHECKING:
    from urdftool.backends.meshes import MeshFacts


class _Meshes(Rule):
    family = Family.MESHES


def _fmt(value: float) -> str:
    return f"{value:.3g}"


def _tried(tried: list[str], limit: int = 6) -> str:
    unique = list(dict.fromkeys(tried))
    shown = "; ".join(unique[:limit])
    return shown + (f"; and {len(unique) - limit} more" if len(unique) > limit else "")


@register
class UnresolvedPackage(_Meshes):
    """A mesh URI names a ROS package or Gazebo model that cannot be found.

    ## What it does
    Resolves every `package://PKG/...` and `model://MODEL/...` mesh URI the
    way ROS and Gazebo would, without a ROS installation: `--package`,
    `--package-path`, `ROS_PACKAGE_PATH`, ament and cmeel prefixes, Gazebo
    resource paths and the folders around the file. Reports each package that
    is found nowhere, once, listing the places searched.

    ## Why it matters
    Every loader that shows or collides the robot (RViz, Gazebo, PyBullet,
    MuJoCo's importer, Pinocchio's `buildGeomFromUrdf`) fails on the mesh or
    drops it, so the robot loses its shape or refuses to load.

    ## Example
    ```xml
    <mesh filename="package://b1_description/meshes/trunk.dae"/>
    ```
    with no `b1_description` package anywhere on the search path.

    ## Fix
    Tell urdftool where the package is (`--package b1_description=DIR`, or
    `--package-path` with a folder holding its `package.xml`), or fix the
    package name in the URI.
    """

    code = "M001"
    name = "unresolved-package"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        groups: dict[str, list[survey.MeshUse]] = {}
        for use in survey.mesh_uses(ctx):
            if use.mesh.resolved is not None or survey.has_substitution(use.mesh.filename):
                continue
            found = survey.lookup(ctx, use)
            if found.package_missing:
                groups.setdefault(found.package or "", []).append(use)
        for package, uses in groups.items():
            first = uses[0]
            found = survey.lookup(ctx, first)
            count = f" (and {len(uses) - 1} more mesh element(s))" if len(uses) > 1 else ""
            beside = _beside_the_file(first, ctx.robot.path)
            hint = (
                f"; a file exists at {beside}, where PyBullet finds it, but ROS tools need the "
                "package"
                if beside
                else ""
            )
            yield self.diagnostic(
                f"{first.describe}: package '{package}' is not found{count}",
                first.location,
                element=first.element,
                help=f"pass --package {package}=DIR or --package-path DIR (a folder holding its "
                f"package.xml){hint}; searched: {_tried(found.tried)}",
                data={
                    "package": package,
                    "uri": first.mesh.filename,
                    "tried": found.tried,
                    "uses": len(uses),
                },
            )


def _beside_the_file(use: survey.MeshUse, robot_path: str) -> str | None:
    """Where PyBullet's search finds a ``package://PKG/rel`` mesh: ``PKG/rel`` or ``rel``
    relative to the describing file's folder."""
    base = os.path.dirname(os.path.abspath(use.location.path if use.location else robot_path))
    rest = use.mesh.filename.split("://", 1)[-1].lstrip("/")
    for candidate in (rest, rest.partition("/")[2]):
        path = os.path.join(base, candidate)
        if candidate and os.path.isfile(path):
            return path
    return None


@register
class MeshNotFound(_Meshes):
    """A mesh file does not exist where its URI points.

    ## What it does
    Reports each mesh file that resolves to a path where no file exists,
    once per robot, with the path looked for and, when the package holds a
    file of the same name elsewhere or with another case or extension, that
    file.

    ## Why it matters
    RViz shows nothing, Gazebo and PyBullet drop the shape (the link falls
    through the floor when it was the collision), and Pinocchio's
    `buildGeomFromUrdf` and MuJoCo refuse the model.

    ## Example
    ```xml
    <mesh filename="package://turtlebot3_description/meshes/bases/burger_base.stl"/>
    ```
    when `meshes/bases/` holds no `burger_base.stl`.

    ## Fix
    Add the file, or correct the path (mind the case: `.STL` and `.stl` are
    different files on Linux).
    """

    code = "M002"
    name = "mesh-not-found"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        groups: dict[str, list[survey.MeshUse]] = {}
        for use in survey.mesh_uses(ctx):
            path = use.mesh.resolved
            if path is None or survey.has_substitution(use.mesh.filename) or os.path.isfile(path):
                continue
            groups.setdefault(path, []).append(use)
        for path, uses in groups.items():
            first = uses[0]
            found = survey.lookup(ctx, first)
            tried = found.tried or [path]
            where = (
                f" (package '{found.package}' is at {found.package_dir})"
                if found.package_dir
                else ""
            )
            what = describe_path(path)
            nearby = near_misses(path) if what is None else []
            hint = f"; a similar file exists: {', '.join(nearby)}" if nearby else ""
            yield self.diagnostic(
                f"{first.describe} not found" if what is None
                else f"{first.describe} is {what}, not a regular file; it is not read",
                first.location,
                element=first.element,
                help=f"looked for {path}{where}{hint}{survey.other_places(uses)}",
                data={
                    "uri": first.mesh.filename,
                    "path": path,
                    "tried": tried,
                    "similar": nearby,
                    "uses": len(uses),
                },
            )


def near_misses(path: str, limit: int = 3) -> list[str]:
    """Files that the author may have meant: the same name in another case or with another
    mesh extension, in the same folder or up to two folders above it."""
    stem = os.path.splitext(os.path.basename(path))[0]
    wanted = stem.lower()
    found: list[str] = []
    folder = os.path.dirname(path)
    for _ in range(3):
        if os.path.isdir(folder):
            found += _similar_below(folder, wanted, limit - len(found))
            if found:
                break
        folder = os.path.dirname(folder)
    return found[:limit]


def _similar_below(folder: str, stem: str, limit: int, budget: int = 2000) -> list[str]:
    out: list[str] = []
    seen = 0
    for root, dirs, files in os.walk(folder):
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))
        for name in sorted(files):
            seen += 1
            base, ext = os.path.splitext(name)
            if base.lower() == stem and ext.lower() in (".stl", ".dae", ".obj", ".ply"):
                out.append(os.path.join(root, name))
                if len(out) >= limit:
                    return out
        if seen > budget:  # a huge tree: the hint is a courtesy, not worth a long walk
            break
    return out


@register
class MeshUnreadable(_Meshes):
    """A mesh file exists but holds no readable triangles.

    ## What it does
    Loads every mesh file (STL, OBJ, COLLADA, PLY, OFF, glTF, 3MF) with
    trimesh and reports files that fail to parse or contain no triangles:
    truncated downloads, Git LFS pointer files, HTML error pages saved as
    `.stl`, COLLADA files with only lines or points.

    ## Why it matters
    Engines that cannot parse a mesh either refuse the model or silently drop
    the shape, so a link becomes invisible or falls through the floor.

    ## Example
    A `base.stl` of 0 bytes, or a file starting with
    `version https://git-lfs.github.com/spec/v1` (run `git lfs pull`).

    ## Fix
    Re-export or re-download the mesh; for Git LFS, fetch the real files.
    """

    code = "M003"
    name = "mesh-unreadable"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        from urdftool.backends.meshes import MeshError

        contents = survey.contents(ctx)
        for path, uses in survey.by_file(ctx).items():
            result = contents.get(path)
            if not isinstance(result, MeshError):
                continue
            first = uses[0]
            yield self.diagnostic(
                f"{first.describe} cannot be read: {result}",
                first.location,
                element=first.element,
                help=f"{_lfs_hint(path)}re-export the mesh from its source"
                + survey.other_places(uses),
                data={
                    "uri": first.mesh.filename,
                    "path": path,
                    "error": str(result),
                    "uses": len(uses),
                },
            )


def _lfs_hint(path: str) -> str:
    try:
        head = read_head(path, 64)
    except OSError:
        return ""
    if head.startswith(b"version https://git-lfs"):
        return "the file is a Git LFS pointer: run `git lfs pull`, or "
    if not head:
        return "the file is empty: "
    return ""


@register
class MeshFormatUnsupported(_Meshes):
    """A mesh is in a format that MuJoCo or PyBullet cannot read.

    ## What it does
    Sniffs each mesh file's format from its name and header and names the
    engines that cannot use it: MuJoCo reads binary STL (up to 200000
    triangles) and OBJ, not COLLADA or ASCII STL; PyBullet reads binary STL,
    OBJ and COLLADA, not ASCII STL (it loads no shape) nor other formats (it
    refuses the URDF). Reported at warning severity when neither engine can
    read the file, as info when one of them can.

    ## Why it matters
    A model that works in RViz and Gazebo (which read nearly every format)
    loses shapes or fails to load when simulated in MuJoCo or PyBullet, or
    when exported to them.

    ## Example
    ```xml
    <mesh filename="package://arm/meshes/base.dae"/>
    ```
    (MuJoCo: "no decoder found for mesh file").

    ## Fix
    Provide a binary STL or OBJ version of the mesh (Blender, MeshLab or
    trimesh convert it) and point the URDF, or the exported model, at it.
    """

    code = "M004"
    name = "mesh-format-unsupported"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        from urdftool.backends.mesh_formats import ENGINE_NAMES, engines_refusing

        for path, uses in survey.by_file(ctx).items():
            fmt = survey.mesh_format(ctx, path)
            refusing = engines_refusing(fmt) if fmt is not None else {}
            if fmt is None or not refusing:
                continue
            first = uses[0]
            why = "; ".join(f"{ENGINE_NAMES[k]} {reason}" for k, reason in refusing.items())
            names = " and ".join(ENGINE_NAMES[k] for k in refusing)
            yield self.diagnostic(
                f"{first.describe} is {fmt.label}, which {names} cannot read",
                first.location,
                element=first.element,
                severity=Severity.WARNING if len(refusing) == len(ENGINE_NAMES) else Severity.INFO,
                help=f"{why}; give {names} a binary STL or OBJ copy{survey.other_places(uses)}",
                data={
                    "uri": first.mesh.filename,
                    "path": path,
                    "format": fmt.kind,
                    "faces": fmt.faces,
                    "engines": sorted(refusing),
                    "uses": len(uses),
                },
            )


@register
class MeshUnitsSuspect(_Meshes):
    """A mesh is about 1000 times too large or too small for the robot around it.

    ## What it does
    Compares each mesh's size (its bounding-box diagonal after `scale`, and
    after the COLLADA `<unit>`) with the size of the robot: the spread of its
    link frames, or, for a one-link model, its primitive shapes. Reports
    meshes more than 10 times larger or 300 times smaller than the robot, and
    says what `scale` would bring them in line (usually `0.001` for a mesh
    exported in millimetres).

    ## Why it matters
    CAD tools export in millimetres; URDF is in metres. A millimetre mesh
    without `scale="0.001 0.001 0.001"` is a 1000-fold giant: a collision
    shape kilometres wide that the robot starts inside of, and a visual that
    fills the screen. The reverse (a scale applied twice) makes a link vanish.

    ## Example
    ```xml
    <mesh filename="package://arm/meshes/forearm.stl"/>  <!-- 280 m across -->
    ```
    on an arm whose joints span 0.9 m.

    ## Fix
    ```xml
    <mesh filename="package://arm/meshes/forearm.stl" scale="0.001 0.001 0.001"/>
    ```
    """

    code = "M005"
    name = "mesh-units-suspect"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        from urdftool.backends.meshes import MeshError, scaled_info

        contents = survey.contents(ctx)
        reference = robot_size(ctx)
        if reference is None:
            return
        size, basis = reference
        reported: set[tuple[str, tuple[float, float, float]]] = set()
        for use in survey.mesh_uses(ctx):
            path = survey.existing_file(use)
            facts = contents.get(path) if path else None
            if path is None or facts is None or isinstance(facts, MeshError):
                continue
            if (path, use.mesh.scale) in reported or 0.0 in use.mesh.scale:
                continue
            diagonal = scaled_info(path, facts, use.mesh.scale).diagonal
            ratio = diagonal / size
            if UNITS_TOO_SMALL <= ratio <= UNITS_TOO_LARGE:
                continue
            reported.add((path, use.mesh.scale))
            yield self._finding(use, diagonal, ratio, size, basis)

    def _finding(
        self, use: survey.MeshUse, diagonal: float, ratio: float, size: float, basis: str
    ) -> Diagnostic:
        factor = suggested_factor(ratio)
        scale = tuple(s * factor for s in use.mesh.scale)
        new_scale = " ".join(_fmt(s) for s in scale)
        what = "larger" if ratio > 1 else "smaller"
        times = ratio if ratio > 1 else 1 / ratio
        unit_hint = (
            " (a mesh in millimetres?)"
            if factor == 1e-3
            else (" (a scale applied twice?)" if factor == 1e3 else "")
        )
        return self.diagnostic(
            f"{use.describe} is {_fmt(diagonal)} m across, {_fmt(times)}× {what} than the robot "
            f"({_fmt(size)} m {basis}){unit_hint}",
            use.location,
            element=use.element,
            help=f'if the file is in other units, write scale="{new_scale}"',
            data={
                "uri": use.mesh.filename,
                "diagonal_m": diagonal,
                "robot_size_m": size,
                "ratio": ratio,
                "suggested_scale": list(scale),
            },
        )


@register
class CollisionMeshTooComplex(_Meshes):
    """A collision mesh has more triangles than collision checking should pay for.

    ## What it does
    Counts the triangles of each collision mesh and reports those over the
    budget of 10000 (see docs/meshes.md for how the budget was set). Visual
    meshes are not counted: they cost only rendering.

    ## Why it matters
    Collision meshes are tested every simulation step and every motion
    planning query. Gazebo (ODE, Bullet) tests triangle soups face by face,
    PyBullet hulls every vertex, MuJoCo hulls the mesh at every compile and
    refuses STL files over 200000 triangles; a CAD-resolution mesh makes
    simulation and planning many times slower for no gain in accuracy.

    ## Example
    A 120000-triangle `forearm.stl` used as both visual and collision mesh.

    ## Fix
    Use a simplified mesh for `<collision>`: its convex hull, a decimated copy
    (Blender's Decimate, MeshLab's quadric edge collapse) of a few hundred to
    a few thousand triangles, or primitive shapes (boxes, cylinders, capsules).
    """

    code = "M006"
    name = "collision-mesh-too-complex"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        from urdftool.backends.meshes import MeshError

        contents = survey.contents(ctx)
        for path, uses in survey.by_file(ctx, role="collision").items():
            facts = contents.get(path)
            if facts is None or isinstance(facts, MeshError) or facts.faces <= FACE_BUDGET:
                continue
            first = uses[0]
            yield self.diagnostic(
                f"{first.describe} has {facts.faces} triangles, {_fmt(facts.faces / FACE_BUDGET)}× "
                f"the collision budget of {FACE_BUDGET}",
                first.location,
                element=first.element,
                help="use a convex hull, a decimated copy (a few thousand triangles at most) or "
                f"primitive shapes for <collision>{survey.other_places(uses)}",
                data={
                    "uri": first.mesh.filename,
                    "faces": facts.faces,
                    "budget": FACE_BUDGET,
                    "uses": len(uses),
                },
            )


@register
class NoCollisionGeometry(_Meshes):
    """A moving link has visual geometry but nothing to collide with.

    ## What it does
    For every joint that moves, looks at the link it moves together with the
    links welded to it by fixed joints. Reports the link when that rigid body
    has `<visual>` geometry but no `<collision>` anywhere. Links with no
    geometry at all (frames, the intermediate links of a two-axis joint) are
    not reported.

    ## Why it matters
    Without collision geometry the part passes through the floor, through
    obstacles and through the robot itself in Gazebo, PyBullet and MuJoCo,
    and motion planners (MoveIt) plan straight through it, while RViz shows
    it as solid.

    ## Example
    ```xml
    <link name="gripper_finger">
      <visual><geometry><box size="0.02 0.01 0.05"/></geometry></visual>
    </link>
    ```

    ## Fix
    Add a `<collision>` with the visual's shape, or a simpler one that encloses it.
    """

    code = "M007"
    name = "no-collision-geometry"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        bare = [
            (joint, group)
            for joint, group in moving_groups(ctx.tree)
            if not any(link.collisions for link in group) and any(link.visuals for link in group)
        ]
        if bare and not any(link.collisions for link in ctx.robot.links):
            # A model with no collision geometry at all is one decision, reported once.
            yield self._whole_robot(ctx, [group[0].name for _, group in bare])
            return
        for joint, group in bare:
            link = group[0]
            welded = [other.name for other in group[1:]]
            also = f" (nor do the links fixed to it: {', '.join(welded)})" if welded else ""
            yield self.diagnostic(
                f"link '{link.name}' moves ({joint.type.value} joint '{joint.name}') and has "
                f"visual geometry but no collision geometry{also}",
                link.span,
                element=f"link[{link.name}]",
                help="add a <collision> with the visual's shape (or a simpler one enclosing it)",
                data={"link": link.name, "joint": joint.name, "welded_links": welded},
            )

    def _whole_robot(self, ctx: CheckContext, links: list[str]) -> Diagnostic:
        shown = ", ".join(links[:5]) + (f" and {len(links) - 5} more" if len(links) > 5 else "")
        name = f"robot '{ctx.robot.name}'" if ctx.robot.name else "the robot"
        return self.diagnostic(
            f"{name} has no collision geometry at all; {len(links)} moving link(s) have visual "
            f"geometry only ({shown})",
            ctx.robot.span,
            element="robot",
            help="add <collision> elements (the visual shapes, or simpler ones enclosing them) if "
            "the model is meant for simulation or motion planning",
            data={"links": links},
        )


@register
class DegenerateGeometry(_Meshes):
    """A shape has a zero or negative size, a zero scale, or a collision mesh is flat.

    ## What it does
    Checks every visual and collision shape: box sizes, cylinder, capsule and
    sphere radii and lengths, ellipsoid radii must be positive; a mesh
    `scale` must have no zero component; a collision mesh must enclose a
    volume (not be a single plane of triangles).

    ## Why it matters
    MuJoCo refuses zero-size geometry, collision engines divide by these
    sizes (ODE and Bullet produce NaNs), a zero scale collapses a mesh to
    nothing, and a flat collision mesh has no convex hull for MuJoCo and
    PyBullet to use.

    ## Example
    ```xml
    <cylinder radius="0.05" length="0"/>
    <mesh filename="wheel.stl" scale="0.001 0 0.001"/>
    ```

    ## Fix
    Give every dimension its real positive size in metres; a scale of
    `1 1 1` leaves a mesh as it is. (Degenerate visual shapes are reported
    as warnings: an invisible marker is odd but harmless.)
    """

    code = "M008"
    name = "degenerate-geometry"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for link in ctx.robot.links:
            for role, items in (("visual", link.visuals), ("collision", link.collisions)):
                for item in items:
                    problem = degenerate_shape(item.geometry)
                    if problem is None or item.geometry is None:
                        continue
                    yield self.diagnostic(
                        f"link '{link.name}': {role} {problem}",
                        item.geometry.span or item.span,
                        # an invisible marker shape is odd but harmless; a collision shape is not
                        severity=Severity.ERROR if role == "collision" else Severity.WARNING,
                        element=f"link[{link.name}]/{role}/geometry/{item.geometry.kind}",
                        help="give every size a positive value in metres (a mesh scale of 1 1 1 "
                        "leaves the file's size)",
                        data={"link": link.name, "shape": item.geometry.kind},
                    )
        yield from self._flat_collision_meshes(ctx)

    def _flat_collision_meshes(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        if not any(use.role == "collision" for use in survey.mesh_uses(ctx)):
            return
        from urdftool.backends.meshes import MeshError

        contents = survey.contents(ctx)
        for path, uses in survey.by_file(ctx, role="collision").items():
            facts = contents.get(path)
            if facts is None or isinstance(facts, MeshError) or not _is_flat(facts):
                continue
            first = uses[0]
            yield self.diagnostic(
                f"{first.describe} is flat (its triangles enclose no volume; extents "
                f"{' × '.join(_fmt(e) for e in _extents(facts))} m)",
                first.location,
                element=first.element,
                help="collision engines need a solid: use a thin box, or give the mesh thickness"
                + survey.other_places(uses),
                data={"uri": first.mesh.filename, "extents_m": list(_extents(facts))},
            )


def _extents(facts: MeshFacts) -> tuple[float, float, float]:
    lo, hi = np.asarray(facts.bounds_min), np.asarray(facts.bounds_max)
    e = hi - lo
    return (float(e[0]), float(e[1]), float(e[2]))


def _is_flat(facts: MeshFacts) -> bool:
    extents = _extents(facts)
    return facts.volume <= 0.0 or min(extents) <= 1e-9 * max(max(extents), 1e-300)
