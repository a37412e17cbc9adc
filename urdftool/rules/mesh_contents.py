"""Meshes and geometry (M) by content: units, complexity, missing collision, degenerate shapes.

Reads mesh contents through the mesh survey fact (:mod:`urdftool.facts.meshes`);
the rules about finding and reading the files are in :mod:`urdftool.rules.meshes`.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
else:
    # NumPy is imported on first use: a structural check must not pay for it.
    from urdftool.lazy import numpy as np

from urdftool.budgets import budget
from urdftool.catalogue.registry import register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts import meshes as survey
from urdftool.facts.context import CheckContext
from urdftool.facts.meshes import MeshError, MeshFacts
from urdftool.model.pose import vector_norm
from urdftool.rules.mesh_geometry import (
    FACE_BUDGET,
    UNITS_TOO_LARGE,
    UNITS_TOO_SMALL,
    degenerate_shape,
    moving_groups,
    robot_size,
    suggested_factor,
)
from urdftool.rules.meshes import _fmt, _Meshes


@register
class MeshUnitsSuspect(_Meshes):
    """A mesh is about 1000 times too large or too small for the robot around it.

    ## What it does
    Compares each mesh's size (its bounding-box diagonal after `scale`, and
    after the COLLADA `<unit>`) with the size of the robot: the spread of its
    link frames, or, for a one-link model, its primitive shapes. Reports
    meshes more than 10 times larger or 300 times smaller than the robot, and
    says what `scale` would bring them in line (usually `0.001` for a mesh
    exported in millimetres). A mesh the robot's size cannot judge (a small
    link of a large robot) is also reported when it is at least 60 times the
    distance from its link frame to the farthest joint of that link, and,
    read in centimetres, inches or millimetres, would be 0.3 to 5 times that
    distance: the evidence of a unit slip on one part. Static SDF models
    (scenery: a runway, a building and its signs) are not judged: they are
    no robot, and their parts span orders of magnitude on purpose.

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
        if ctx.robot.static_span is not None:
            # scenery (an SDF model marked static: a runway, a building with its signs) is no
            # robot, and its parts span orders of magnitude on purpose; sizes are no evidence there
            return
        contents = survey.contents(ctx)
        reference = robot_size(ctx)
        if reference is None:
            return
        size, basis = reference
        # Measured when the first mesh could be evidence: below LINK_RATIO_MIN times the
        # smallest span that counts, no link's span can judge it.
        spans: dict[str, float] | None = None
        reported: set[tuple[str, tuple[float, float, float]]] = set()
        for use, path in survey.existing_files(ctx):
            facts = contents.get(path) if path else None
            if path is None or facts is None or isinstance(facts, MeshError):
                continue
            if (path, use.mesh.scale) in reported or 0.0 in use.mesh.scale:
                continue
            diagonal = survey.scaled_diagonal(ctx, path, facts, use.mesh.scale)
            ratio = diagonal / size
            if UNITS_TOO_SMALL <= ratio <= UNITS_TOO_LARGE:
                if diagonal < LINK_RATIO_MIN * LINK_SPAN_MIN:
                    continue
                if spans is None:
                    spans = link_spans(ctx)
                unit = _link_evidence(diagonal, spans.get(use.link))
                if unit is not None:
                    reported.add((path, use.mesh.scale))
                    yield self._link_finding(use, diagonal, spans[use.link], unit)
                continue
            reported.add((path, use.mesh.scale))
            yield self._finding(use, diagonal, ratio, size, basis)

    def _link_finding(
        self, use: survey.MeshUse, diagonal: float, span: float, unit: tuple[str, float]
    ) -> Diagnostic:
        name, factor = unit
        scale = tuple(s / factor for s in use.mesh.scale)
        new_scale = " ".join(_fmt(s) for s in scale)
        return self.diagnostic(
            f"{use.describe} is {_fmt(diagonal)} m across, {_fmt(diagonal / span)}× the "
            f"{_fmt(span)} m from its link frame to its farthest joint; in {name} it would be "
            f"{_fmt(diagonal / factor)} m (a mesh in {name}?)",
            use.location,
            element=use.element,
            help=f'if the file is in {name}, write scale="{new_scale}"',
            data={
                "uri": use.mesh.filename,
                "diagonal_m": diagonal,
                "link_span_m": span,
                "unit": name,
                "suggested_scale": list(scale),
            },
        )

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


#: The second evidence of mesh-units-suspect, for meshes the robot's size cannot judge (a small
#: link of a large robot): a link whose joints to its neighbours span at least LINK_SPAN_MIN, and a
#: mesh at least LINK_RATIO_MIN times that span which, read in one of UNITS, lands within
#: LINK_FIT of it. On example-robot-data and pybullet_data (1,817 meshes on links with joints)
#: the largest ratio is 22 (hextilt's 1.15 m airframe around a 5 cm arm mount), then 10;
#: LINK_RATIO_MIN leaves a margin near 3 above it.
LINK_SPAN_MIN = 0.02
LINK_RATIO_MIN = 60.0
LINK_FIT = (0.3, 5.0)
UNITS = (("centimetres", 100.0), ("inches", 39.37007874015748), ("millimetres", 1000.0))


def link_spans(ctx: CheckContext) -> dict[str, float]:
    """Per link (m): the largest distance from its frame to a joint that touches it (its
    children's origins; its own origin is its parent joint)."""
    spans: dict[str, float] = {}
    for joint in ctx.robot.joints:
        distance = vector_norm(joint.origin.xyz)
        spans[joint.parent] = max(spans.get(joint.parent, 0.0), distance)
    return {name: span for name, span in spans.items() if span >= LINK_SPAN_MIN}


def _link_evidence(diagonal: float, span: float | None) -> tuple[str, float] | None:
    """The unit the mesh was evidently written in, from its link's span; ``None`` without evidence."""
    if span is None or diagonal < LINK_RATIO_MIN * span:
        return None
    fits = [(abs(np.log(diagonal / factor / span)), name, factor) for name, factor in UNITS
            if LINK_FIT[0] <= diagonal / factor / span <= LINK_FIT[1]]
    if not fits:
        return None
    _, name, factor = min(fits)
    return name, factor


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

        contents = survey.contents(ctx)
        limit = int(budget("collision-faces"))
        for path, uses in survey.by_file(ctx, role="collision").items():
            facts = contents.get(path)
            if facts is None or isinstance(facts, MeshError) or facts.faces <= limit:
                continue
            first = uses[0]
            yield self.diagnostic(
                f"{first.describe} has {facts.faces} triangles, {_fmt(facts.faces / limit)}× "
                f"the collision budget of {limit}",
                first.location,
                element=first.element,
                help="use a convex hull, a decimated copy (a few thousand triangles at most) or "
                f"primitive shapes for <collision>{survey.other_places(uses)}"
                + ("" if limit == FACE_BUDGET else f" (the collision-faces budget is {limit})"),
                data={
                    "uri": first.mesh.filename,
                    "faces": facts.faces,
                    "budget": limit,
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
    as warnings: an invisible marker is odd but harmless. A flat collision
    mesh in an SDF model is a warning too: Gazebo, which reads SDF, collides
    with its triangles as they are.)
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

        contents = survey.contents(ctx)
        # An SDF model is read by Gazebo, whose ODE, Bullet and DART collide with a triangle
        # mesh as it is (a sign, a wall panel); only the convex hull MuJoCo and PyBullet build
        # needs a volume, and they read URDF
        sdf = ctx.robot.format == "sdf"
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
                help=("collision engines need a solid: use a thin box, or give the mesh thickness"
                      if not sdf else "Gazebo collides with its triangles as they are; MuJoCo and "
                      "PyBullet (after convert) need a solid: use a thin box, or give the mesh "
                      "thickness") + survey.other_places(uses),
                data={"uri": first.mesh.filename, "extents_m": list(_extents(facts))},
                severity=Severity.WARNING if sdf else None,
            )


def _extents(facts: MeshFacts) -> tuple[float, float, float]:
    # the same subtractions NumPy did on the bounds, on the floats themselves
    lo, hi = facts.bounds_min, facts.bounds_max
    return (hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2])


def _is_flat(facts: MeshFacts) -> bool:
    extents = _extents(facts)
    return facts.volume <= 0.0 or min(extents) <= 1e-9 * max(max(extents), 1e-300)
