"""``convert --collision as-is|hull|decompose|primitives``: collision meshes simulators can use.

:func:`simplify_collisions` returns the robot with each collision mesh
replaced (visual geometry untouched) and one ``collision-simplified`` note per
mesh with its volume error. Generated meshes are OBJ files in the collision
cache (:mod:`urdftool.backends.collision_shapes`); the MJCF and PyBullet
exporters copy them into ``assets/`` beside OUT, and for URDF and SDF output
they are written to ``collision/`` beside OUT. A fitted capsule stays one
capsule for targets that have the shape (MJCF, PyBullet's URDF); URDF and SDF
1.7 have none, so there it is written as a cylinder and two spheres at its
ends, which together enclose exactly the capsule.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable
from dataclasses import field

from urdftool.backends.collision_shapes import Simplified, simplify
from urdftool.backends.meshes import MeshError
from urdftool.catalogue.collision import CollisionSimplified
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.model import Box, Capsule, Collision, Cylinder, Link, Mesh, Pose, Robot, Sphere
from urdftool.pipeline.convert import Conversion
from urdftool.records import record
from urdftool.safe_files import read_regular

MODES = ("as-is", "hull", "decompose", "primitives")
#: OUT-relative folder for generated meshes referenced by URDF and SDF output
FOLDER = "collision"
#: export targets that write a capsule as a capsule (the others get a cylinder and two spheres)
CAPSULE_TARGETS = frozenset({"mjcf", "pybullet"})


@record
class CollisionOptions:
    mode: str = "as-is"
    threshold: float = 0.05
    max_parts: int = 16
    tolerance: float = 0.15


@record(frozen=False)
class Simplification:
    robot: Robot
    diagnostics: list[Diagnostic] = field(default_factory=list)
    #: OUT-relative path -> bytes, for targets that reference meshes by their written name
    files: dict[str, bytes] = field(default_factory=dict)


def collision_meshes(robot: Robot) -> list[str]:
    """Resolved collision mesh files, each once."""
    return list(dict.fromkeys(
        c.geometry.resolved for link in robot.links for c in link.collisions
        if isinstance(c.geometry, Mesh) and c.geometry.resolved and os.path.isfile(c.geometry.resolved)
    ))


def simplify_collisions(
    robot: Robot, options: CollisionOptions, progress: Callable[[str], None] | None = None,
    *, capsules: bool = True,
) -> Simplification:
    """*robot* with its collision meshes replaced as *options* say (unchanged for ``as-is``).

    With *capsules* false (a target without the shape: see :data:`CAPSULE_TARGETS`), a
    fitted capsule becomes a cylinder and two spheres.
    """
    if options.mode == "as-is":
        return Simplification(robot)
    out = Simplification(robot)
    links = []
    for link in robot.links:
        collisions: list[Collision] = []
        for item in link.collisions:
            collisions.extend(_replace(link, item, options, out, progress, capsules))
        links.append(dataclasses.replace(link, collisions=tuple(collisions)))
    out.robot = dataclasses.replace(robot, links=tuple(links))
    return out


def _replace(link: Link, item: Collision, options: CollisionOptions, out: Simplification,
             progress: Callable[[str], None] | None, capsules: bool) -> list[Collision]:
    mesh = item.geometry
    if not isinstance(mesh, Mesh) or not mesh.resolved or not os.path.isfile(mesh.resolved):
        return [item]
    if progress is not None:
        progress(mesh.filename)
    try:
        result = simplify(mesh.resolved, options.mode, mesh.scale, threshold=options.threshold,
                          max_parts=options.max_parts, tolerance=options.tolerance)
    except MeshError as exc:
        out.diagnostics.append(CollisionSimplified.diagnostic(
            f"link '{link.name}': collision mesh '{mesh.filename}' kept as it is ({exc})",
            mesh.span, element=f"link[{link.name}]/collision", severity=Severity.WARNING))
        return [item]
    split = not capsules and result.primitive is not None and result.primitive.kind == "capsule"
    out.diagnostics.append(_note(link, mesh, result, split))
    if result.primitive is not None:
        shape = result.primitive
        geometry: Box | Cylinder | Sphere | Capsule
        if shape.kind == "box":
            geometry = Box((shape.size[0], shape.size[1], shape.size[2]))
        elif shape.kind == "cylinder":
            geometry = Cylinder(shape.size[0], shape.size[1])
        elif shape.kind == "capsule":
            geometry = Capsule(shape.size[0], shape.size[1])
        else:
            geometry = Sphere(shape.size[0])
        origin = Pose.from_matrix(item.origin.matrix @ Pose(shape.xyz, shape.rpy).matrix)
        fitted = dataclasses.replace(item, geometry=geometry, origin=origin)
        return _without_capsule(fitted) if split else [fitted]
    parts = []
    for number, path in enumerate(result.parts):
        name = f"{FOLDER}/{os.path.basename(os.path.dirname(path))[:12]}-{os.path.basename(path)}"
        out.files[name] = read_regular(path, "mesh")
        part = Mesh(filename=name, resolved=path, scale=mesh.scale, span=mesh.span)
        label = f"{item.name}_{number}" if item.name and len(result.parts) > 1 else item.name
        parts.append(dataclasses.replace(item, geometry=part, name=label))
    return parts


def _without_capsule(item: Collision) -> list[Collision]:
    """A capsule as a cylinder and a sphere at each end of its axis (the same solid); others as they are."""
    shape = item.geometry
    if not isinstance(shape, Capsule):
        return [item]
    parts: list[tuple[Cylinder | Sphere, float, str]] = [
        (Cylinder(shape.radius, shape.length), 0.0, "cylinder"),
        (Sphere(shape.radius), -shape.length / 2, "end0"),
        (Sphere(shape.radius), shape.length / 2, "end1"),
    ]
    return [dataclasses.replace(
        item, geometry=geometry, name=f"{item.name}_{label}" if item.name else item.name,
        origin=Pose.from_matrix(item.origin.matrix @ Pose((0.0, 0.0, z), (0.0, 0.0, 0.0)).matrix),
    ) for geometry, z, label in parts]


def _note(link: Link, mesh: Mesh, result: Simplified, split: bool) -> Diagnostic:
    what = {
        "hull": "its convex hull",
        "decompose": f"{len(result.parts)} convex parts",
        "primitive": f"a {result.primitive.kind if result.primitive else 'shape'}",
    }[result.mode]
    note = "written as a cylinder and two spheres: the target has no capsule" if split else result.note
    detail = f" ({note})" if note else ""
    return CollisionSimplified.diagnostic(
        f"link '{link.name}': collision mesh '{mesh.filename}' became {what}{detail}; "
        f"volume error {100 * result.volume_error:+.1f} %",
        mesh.span, element=f"link[{link.name}]/collision",
        data={"link": link.name, "uri": mesh.filename, "mode": result.mode, "parts": len(result.parts),
              "volume": result.volume, "mesh_volume": result.mesh_volume,
              "volume_error": result.volume_error, "cached": result.cached,
              "shape": result.primitive.kind if result.primitive else None,
              "size": list(result.primitive.size) if result.primitive else None},
    )


def with_collision_files(conversion: Conversion, simplified: Simplification) -> Conversion:
    """*conversion* plus the generated meshes its output references by name (URDF, SDF)."""
    if not simplified.files or conversion.target not in ("urdf", "sdf"):
        return conversion
    return dataclasses.replace(conversion, files={**conversion.files, **simplified.files})
