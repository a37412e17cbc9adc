"""Meshes and geometry (M): files that resolve, load, and have plausible sizes.

The rules share one survey per robot (:mod:`urdftool.facts.meshes`): each
URI is resolved once, each file sniffed once, and each readable file loaded
once, in parallel, only when a selected rule needs its contents. Findings about
a file are reported once per robot, at the first element that uses it.
Thresholds and their calibration on the corpora are in ``docs/meshes.md``.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    pass
else:
    # NumPy is imported on first use: a structural check must not pay for it.
    pass

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts import meshes as survey
from urdftool.facts.context import CheckContext
from urdftool.facts.meshes import ENGINE_NAMES, MeshError, describe_path, engines_refusing, read_head
from urdftool.targets import TARGETS
from urdftool.targets.gazebo_classic_models import database_model, read_by_classic


class _Meshes(Rule):
    family = Family.MESHES


def _fmt(value: float) -> str:
    return f"{value:.3g}"


def _tried(tried: Sequence[str], limit: int = 6) -> str:
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
    is found nowhere, once, listing the places searched. When every mesh of
    that package exists where PyBullet looks for it (the URI's path after
    `package://`, in the describing file's folder or any folder above it, as
    pybullet_data's own robots are written), the finding is a warning: one
    consumer loads the robot as it is, ROS tools do not. When PyBullet finds
    only some of them, it refuses the robot, and the finding stays an error.

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
    package name in the URI. A `model://` URI names a Gazebo model, a folder
    holding `model.config`: pass `--package-path` with the folder above it, or
    list that folder in `GZ_SIM_RESOURCE_PATH` (gz-sim) or `GAZEBO_MODEL_PATH`
    (Gazebo classic), where the simulator looks too. When several models of
    one world use the missing package, each reports it and the help is given
    once, at the first.

    A `model://` URI into Gazebo Classic's online model database
    (`construction_cone`, `suv`, …) in a world Classic reads (SDFormat 1.7 or
    older, no gz-sim systems) is not missing: Classic downloads the model on
    first load. It is reported as an info, since urdftool cannot check it.
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
        # a model of a world Gazebo Classic reads (a model read alone is no world's)
        classic = bool(groups) and ctx.robot.world is not None and read_by_classic(ctx.robot.world)
        for package, uses in groups.items():
            first = uses[0]
            found = survey.lookup(ctx, first)
            count = f" (and {len(uses) - 1} more mesh element(s))" if len(uses) > 1 else ""
            if classic and database_model(first.mesh.filename):
                yield self.diagnostic(
                    f"{first.describe}: model '{package}' is not on this machine{count}; Gazebo "
                    "Classic downloads it from its model database on first load, so it is not checked",
                    first.location, element=first.element, severity=Severity.INFO,
                    help="to check it too, download the model (osrf/gazebo_models) and pass its "
                    "folder's parent with --package-path or GAZEBO_MODEL_PATH",
                    data={"package": package, "uri": first.mesh.filename, "uses": len(uses),
                          "remote": True},
                )
                continue
            # PyBullet loads the robot only when it finds every one of the package's meshes: one
            # it misses (a file named in another case, say) fails the whole loadURDF
            where = [_where_pybullet_finds(use, ctx.robot.path) for use in uses]
            beside = where[0] if all(where) else None
            lost = next((use for use, path in zip(uses, where, strict=True) if path is None), None)
            if beside:
                hint = (f"; a file exists at {beside}, where PyBullet finds it, but ROS tools need "
                        "the package")
            elif any(where) and lost is not None:
                hint = (f"; PyBullet finds {sum(1 for path in where if path)} of these {len(uses)} "
                        f"meshes but not '{lost.mesh.filename}', and then refuses the robot")
            else:
                hint = ""
            yield self.diagnostic(
                f"{first.describe}: package '{package}' is not found{count}",
                first.location,
                element=first.element,
                help=f"{_where_to_point(package, first.mesh.filename)}{hint}; "
                f"searched: {_tried(found.tried)}",
                data={
                    "package": package,
                    "uri": first.mesh.filename,
                    "tried": found.tried,
                    "uses": len(uses),
                    "pybullet_finds": beside,
                },
                severity=Severity.WARNING if beside else None,
            )


def _where_to_point(package: str, uri: str) -> str:
    """How to tell urdftool (and the consumer) where *package* is: a ROS package holds
    ``package.xml``; a Gazebo model (``model://``) is a folder holding ``model.config``, found
    through Gazebo's resource path variables, which the resolver reads too."""
    if uri.startswith("model://"):
        return (f"'{package}' is a Gazebo model: pass --package-path DIR, DIR being the folder that "
                f"holds '{package}/' (with its model.config), or list DIR in GZ_SIM_RESOURCE_PATH "
                f"(gz-sim) or GAZEBO_MODEL_PATH (Gazebo classic), as the simulator needs it too; "
                f"or --package {package}=DIR for the model folder itself")
    return f"pass --package {package}=DIR or --package-path DIR (a folder holding its package.xml)"


def _where_pybullet_finds(use: survey.MeshUse, robot_path: str) -> str | None:
    """Where PyBullet's URDF importer finds a ``package://PKG/rel`` mesh, or None.

    It drops the scheme and looks for ``PKG/rel`` in the describing file's folder and in every
    folder above it, so ``robots/robot.urdf`` with ``package://meshes/base.stl`` finds
    ``meshes/base.stl`` beside ``robots/``. Measured with PyBullet 3.2.7 (tests/test_precision.py):
    found 24 levels up; ``rel`` without the ``PKG`` folder is not found; names are case-sensitive.
    """
    folder = os.path.dirname(os.path.abspath(use.location.path if use.location else robot_path))
    rest = use.mesh.filename.split("://", 1)[-1].lstrip("/")
    if not rest:
        return None
    while True:
        path = os.path.join(folder, rest)
        if os.path.isfile(path):
            return path
        parent = os.path.dirname(folder)
        if parent == folder:
            return None
        folder = parent


@register
class MeshNotFound(_Meshes):
    """A mesh file does not exist where its URI points.

    ## What it does
    Reports each mesh file that resolves to a path where no file exists,
    once per robot, with the path looked for and, when the package holds a
    file of the same name elsewhere or with another case or extension, that
    file. When two folders under one search folder declare the package's
    name and the file is only in the one not taken, the help names that
    folder (docs/packages.md). A mesh given by web address (`https://fuel.gazebosim.org/…`, which
    Gazebo downloads and caches) is one info per robot: it is not fetched, so
    not checked.

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
        remote: list[survey.MeshUse] = []
        for use in survey.mesh_uses(ctx):
            path = use.mesh.resolved
            if use.mesh.filename.lower().startswith(("http://", "https://")):
                remote.append(use)
                continue
            if path is None or survey.has_substitution(use.mesh.filename) or survey.is_file(ctx, path):
                continue
            groups.setdefault(path, []).append(use)
        if remote:
            first = remote[0]
            more = f" (and {len(remote) - 1} more)" if len(remote) > 1 else ""
            yield self.diagnostic(
                f"{first.describe} is a web address{more}; not checked offline",
                first.location,
                element=first.element,
                help="Gazebo downloads and caches such meshes (Gazebo Fuel); urdftool does not "
                "fetch them, so their shape and size are not checked",
                data={"uri": first.mesh.filename, "uses": len(remote), "remote": True},
                severity=Severity.INFO,
            )
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
            # the same file in a second folder of the package's name says more than a look-alike
            hint = _in_twin(ctx, found.package or "", found.package_dir, path) if what is None else ""
            nearby = near_misses(path) if what is None and not hint else []
            hint = hint or (f"; a similar file exists: {', '.join(nearby)}" if nearby else "")
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


def _in_twin(ctx: CheckContext, package: str, package_dir: str | None, path: str) -> str:
    """``"; package P is also at D, where this file exists…"`` when a second folder of the same
    package name under one search root holds the file the first one lacks; else ``""``."""
    if not package_dir:
        return ""
    inside = os.path.relpath(path, package_dir)
    for twin in survey.resolver(ctx).twins(package_dir):
        if os.path.isfile(os.path.join(twin, inside)):
            return (f"; package '{package}' is also at {twin}, where this file exists: two folders "
                    f"under one search folder hold a package.xml named '{package}' and urdftool took "
                    "the first in name order (colcon refuses such a workspace); remove or rename one")
    return ""


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
    read the file, as info when one of them can, and as info in an SDF model
    (gz-sim and Drake, its consumers, read glTF and COLLADA).

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
        # An SDF model is loaded by libsdformat's consumers (gz-sim, Drake), which read glTF and
        # COLLADA; MuJoCo and PyBullet see it only through an export, so it is a note there.
        sdf = ctx.robot.format == "sdf"
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
                severity=Severity.INFO if sdf or len(refusing) < len(ENGINE_NAMES) else Severity.WARNING,
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


#: A path that is absolute on Windows (``C:\meshes\x.stl``, ``C:/…``).
_DRIVE = re.compile(r"[A-Za-z]:[\\/]")


def is_bare_relative(filename: str) -> bool:
    """A mesh filename with no URI scheme that is not an absolute path (``meshes/x.stl``)."""
    name = filename.strip()
    return bool(name) and "://" not in name and not name.startswith(("/", "\\")) and not (
        _DRIVE.match(name) or survey.has_substitution(name)
    )


@register
class MeshPathRelative(_Meshes):
    """A URDF mesh path is relative to the file (`meshes/x.stl`), which ROS tools cannot load.

    ## What it does
    Reports a URDF mesh `filename` that is a bare relative path, with no
    `package://` or `file://` scheme, once per robot at the first one (with
    the count):

    - a warning when other meshes of the robot use `package://` or
      `file://`: the model is written for ROS tools, which will miss this one;
    - an info when all of them are relative and the file sits in a ROS
      package (a `package.xml` in its folder or above);
    - nothing when all are relative outside any ROS package: a model written
      for PyBullet, MuJoCo or Drake (pybullet_data's robots, Unitree's
      humanoids).

    With `--target`, a consumer that does not find such a path (gazebo,
    gz-sim, pinocchio, moveit) makes any relative path a warning saying why,
    and targets that all find it (mujoco, pybullet, drake) silence the rule.
    `package://`, `file://`, `model://`, web addresses and absolute paths are
    left alone, and so is SDF, where SDFormat and gz-sim resolve a relative
    `<uri>` against the file.

    ## Why it matters
    PyBullet, MuJoCo and Drake resolve the path against the URDF's folder
    (tested: each loads `meshes/link1.stl` beside the file). ROS tools
    receive the URDF as the `robot_description` string, with no folder: RViz
    and MoveIt load meshes through resource_retriever, which takes URLs only
    ("failed to load resource ../meshes/ur5/visual/base.obj",
    ros/collada_urdf#33), so the robot shows without that mesh and MoveIt
    plans without that collision shape; Gazebo spawned from
    `robot_description` does not find it either. Pinocchio 4.1 looks a
    relative path up only in its `package_dirs` ("Mesh meshes/link1.stl
    could not be found"; stack-of-tasks/pinocchio#1741).

    ## Example
    ```xml
    <mesh filename="package://panda_description/meshes/visual/link0.dae"/>
    <mesh filename="meshes/visual/link1.dae"/>   <!-- the one RViz will not show -->
    ```

    ## Fix
    In a ROS package, write `package://PKG/meshes/link1.stl`; nothing to do
    for a model meant for PyBullet, MuJoCo or Drake only.
    """

    code = "M009"
    name = "mesh-path-relative"
    severity = Severity.INFO

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        if ctx.robot.format == "sdf":
            return
        named = [TARGETS[n] for n in ctx.options.get("targets") or () if n in TARGETS]
        failing = [t for t in named if t.relative_mesh is not None]
        if named and not failing:
            return  # every consumer asked about resolves the path against the file
        uses = survey.mesh_uses(ctx)
        relative = [use for use in uses if is_bare_relative(use.mesh.filename)]
        if not relative:
            return
        first = relative[0]
        where = first.location.path if first.location and first.location.path else ctx.robot.path
        mixed = any(use.mesh.filename.strip().startswith(("package://", "file://")) for use in uses)
        if mixed or failing:
            severity = Severity.WARNING
        elif survey.in_ros_package(ctx, where):
            severity = Severity.INFO
        else:
            return  # written for PyBullet, MuJoCo or Drake, which find it
        count = f" (and {len(relative) - 1} more mesh element(s))" if len(relative) > 1 else ""
        context = (
            "; the robot's other meshes use package:// or file://, so it is meant for ROS tools"
            if mixed
            else ""
        )
        why = "; ".join(f"{t.label}: {t.relative_mesh}" for t in failing)
        yield self.diagnostic(
            f"{first.describe} is a path relative to the file{count}: PyBullet, MuJoCo and Drake "
            f"find it, ROS tools (RViz, MoveIt, Gazebo from robot_description) do not{context}",
            first.location,
            element=first.element,
            severity=severity,
            help="write package://PKG/" + first.mesh.filename.strip().lstrip("./")
            + " (PKG: the package holding the mesh)" + (f"; {why}" if why else ""),
            data={
                "uri": first.mesh.filename,
                "uses": len(relative),
                "mixed": mixed,
                "targets": [t.name for t in failing],
            },
        )
