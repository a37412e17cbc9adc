"""Consumers (T) and collision meshes: hulls, formats and budgets for the targets of ``--target``.

The mesh half of :mod:`urdftool.rules.targets`: reads the collision shape facts
(:mod:`urdftool.facts.mesh_shape`) and the mesh survey.
"""

from __future__ import annotations

from collections.abc import Iterator

from urdftool.catalogue.registry import register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts import mesh_shape
from urdftool.facts import meshes as survey
from urdftool.facts.context import CheckContext
from urdftool.rules.targets import HULL_NOTE, HULL_WARN, _pct, _Targets, targets
from urdftool.targets import Target


def _extension(filename: str) -> str:
    """The file's extension, lower case with its dot (``""`` when it has none)."""
    return "." + filename.rsplit(".", 1)[-1].lower() if "." in filename.rsplit("/", 1)[-1] else ""


def _refused(target: Target, filename: str) -> bool:
    """The target stops loading the file at a collision mesh of this format (Drake)."""
    formats = target.collision_formats
    return target.unread_format_fails and formats is not None and _extension(filename) not in formats


@register
class TargetHullsConcaveMesh(_Targets):
    """A consumer will collide with the convex hull of a concave collision mesh.

    ## What it does
    For each target of `--target` that collides with convex shapes only
    (MuJoCo, PyBullet, Drake point contact, Isaac Sim/PhysX), measures how much
    of the hull each collision mesh fills (its volume, or for an open mesh the
    hulls of its pieces, over the hull's volume; PyBullet hulls each object
    of an OBJ file on its own). Reports meshes that fill less than 75 % of
    the hull (a warning below 50 %). A mesh whose format stops the
    consumer's load (an STL mesh in Drake: `target-mesh-format`) is left to
    that rule.

    ## Why it matters
    A bowl becomes a solid dome, a tray a block: objects placed in it rest on
    the hull's lid, and a gripper's concave palm keeps fingers apart.

    ## Example
    A tray whose collision mesh fills 15 % of its hull, loaded in MuJoCo.

    ## Fix
    `urdftool convert --collision decompose` splits the mesh into convex
    parts (CoACD); or model the collision with several primitives.
    """

    code = "T003"
    name = "target-hulls-concave-mesh"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        chosen = [t for t in targets(ctx) if t.hulls_collision_meshes is not None]
        if not chosen:
            return
        for shape, uses in mesh_shape.collision_shapes(ctx).values():
            first = uses[0]
            for target in chosen:
                if _refused(target, first.mesh.filename):
                    continue
                per_object = target.hulls_collision_meshes == "object" and shape.objects > 1
                fill = shape.hull_fill(per_object)
                if fill >= HULL_NOTE or shape.hull_volume <= 0:
                    continue
                hull = f"the convex hulls of the {shape.objects} objects" if per_object else "its convex hull"
                yield self.diagnostic(
                    f"{target.label} will treat {first.describe} as {hull}: the mesh fills "
                    f"{_pct(fill)} of it, so {_pct(1 - fill)} of the hull is solid where the mesh is empty",
                    first.location, element=first.element,
                    severity=Severity.WARNING if fill < HULL_WARN else Severity.INFO,
                    help="split it into convex parts: urdftool convert --collision decompose"
                    + survey.other_places(uses),
                    data={"target": target.name, "uri": first.mesh.filename, "fill": fill,
                          "hull_volume": shape.hull_volume, "solid_volume": shape.solid_volume,
                          "objects": shape.objects, "suggest": "decompose"},
                )


@register
class TargetMeshFormat(_Targets):
    """A consumer does not read the format of a collision mesh.

    ## What it does
    For each target of `--target` other than MuJoCo and PyBullet (whose
    formats `mesh-format-unsupported` checks), reports collision meshes whose
    file extension the consumer does not read: Drake reads OBJ, VTK and
    glTF (`.gltf`, not `.glb`), Gazebo, Isaac Sim and MoveIt read STL, OBJ
    and COLLADA. For Drake it is an error: its parser stops at the mesh.

    ## Why it matters
    The consumer drops the collision shape, with a warning at best: the link
    passes through everything. Drake, loading into a plant with a
    SceneGraph, refuses the whole file ("MakeConvexHull only applies to .obj,
    .vtk, and .gltf meshes").

    ## Example
    ```xml
    <collision><geometry><mesh filename="bowl.stl"/></geometry></collision>  <!-- Drake -->
    ```

    ## Fix
    Convert the mesh (`trimesh`, MeshLab, Blender) to a format every
    consumer reads; OBJ is read by all of them.
    """

    code = "T006"
    name = "target-mesh-format"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        chosen = [
            t for t in targets(ctx)
            if t.collision_formats is not None and t.name not in survey.ENGINE_NAMES
        ]
        if not chosen:
            return  # no target that limits collision formats: no mesh to look at
        for use in survey.mesh_uses(ctx):
            if use.role != "collision" or survey.has_substitution(use.mesh.filename):
                continue
            extension = _extension(use.mesh.filename)
            for target in chosen:
                if extension in (target.collision_formats or ()):
                    continue
                reads = ", ".join(sorted(e.lstrip(".").upper() for e in target.collision_formats or ()))
                refused = _refused(target, use.mesh.filename)
                effect = (
                    f"{target.label} will refuse to load the file because of {use.describe}"
                    if refused
                    else f"{target.label} will not use {use.describe} as collision geometry"
                )
                yield self.diagnostic(
                    f"{effect}: it reads {reads} collision meshes only",
                    use.location, element=use.element, help="convert the mesh to OBJ",
                    severity=Severity.ERROR if refused else Severity.WARNING,
                    data={"target": target.name, "uri": use.mesh.filename, "extension": extension,
                          "refused": refused},
                )


@register
class TargetCollisionBudget(_Targets):
    """A collision mesh costs more than a consumer should pay for each step or query.

    ## What it does
    For each target of `--target`, compares each collision mesh's triangle
    count with the consumer's budget (MoveIt 5000, Gazebo, Drake and Isaac
    Sim 20000, PyBullet 50000, MuJoCo 200000), and for Isaac Sim its hull's
    vertex count with PhysX's limit of 64. Says which `convert --collision`
    option fits the mesh.

    ## Why it matters
    Planners check collisions thousands of times a second; simulators test
    every collision pair every step. A CAD-resolution mesh makes both slow
    for no gain, and a hull PhysX coarsens to 64 vertices is not the shape
    the author drew.

    ## Example
    A 100000-triangle gripper palm used as its own collision mesh.

    ## Fix
    `urdftool convert --collision hull` (convex parts), `decompose`
    (concave parts) or `primitives` (boxes, cylinders, spheres or capsules).
    """

    code = "T007"
    name = "target-collision-budget"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        chosen = targets(ctx)
        if not any(t.face_budget or t.hull_vertex_limit for t in chosen):
            return
        for shape, uses in mesh_shape.collision_shapes(ctx).values():
            first = uses[0]
            option = "decompose" if shape.fill < HULL_NOTE else "hull"
            for target in chosen:
                if target.face_budget and shape.faces > target.face_budget:
                    yield self.diagnostic(
                        f"{target.label}: {first.describe} has {shape.faces} triangles, over the "
                        f"budget of {target.face_budget} for collision checking",
                        first.location, element=first.element,
                        help=f"urdftool convert --collision {option} (the mesh fills "
                        f"{_pct(shape.fill)} of its hull){survey.other_places(uses)}",
                        data={"target": target.name, "uri": first.mesh.filename, "faces": shape.faces,
                              "budget": target.face_budget, "suggest": option},
                    )
                if target.hull_vertex_limit and shape.hull_vertices > target.hull_vertex_limit:
                    yield self.diagnostic(
                        f"{target.label} will cook {first.describe} into a hull of at most "
                        f"{target.hull_vertex_limit} vertices (its hull has {shape.hull_vertices})",
                        first.location, element=first.element, severity=Severity.INFO,
                        help=f"urdftool convert --collision {option}",
                        data={"target": target.name, "uri": first.mesh.filename,
                              "hull_vertices": shape.hull_vertices, "limit": target.hull_vertex_limit,
                              "suggest": option},
                    )
