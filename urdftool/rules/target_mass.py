"""Consumers (T), the mass half: what a consumer fills in for a link without mass or inertia.

Split from :mod:`urdftool.rules.targets` (which holds the shared helpers and the joint,
structure and companion-file rules): PyBullet's 1 kg, MuJoCo's and Isaac Sim's mass from the
collision geometry, Drake's zero, Gazebo's dropped links, and PyBullet's inertia from the
collision shapes.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping

from urdftool.catalogue.registry import register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts.context import CheckContext
from urdftool.model import Box, JointType, Link, Mesh, Sphere
from urdftool.physics.inertia import principal_moments
from urdftool.physics.massprops import geometry_properties
from urdftool.rules.targets import _moving, _parent_joint, _Targets, targets
from urdftool.targets import Target

#: PyBullet's inertia from the collision shapes is reported when a principal moment differs
#: from the file's by more than this factor.
INERTIA_FACTOR = 2.0


def _descendants(ctx: CheckContext, link: str) -> list[str]:
    out: list[str] = []
    todo = list(ctx.tree.children(link))
    while todo:
        name = todo.pop()
        if name in out:
            continue
        out.append(name)
        todo.extend(ctx.tree.children(name))
    return out


def _lumped_mass(ctx: CheckContext, link: str) -> float:
    """The mass of *link* with every link hanging from it by fixed joints (Gazebo's lumping)."""
    links = {lk.name: lk for lk in ctx.robot.links}
    total, todo, seen = 0.0, [link], set()
    while todo:
        name = todo.pop()
        if name in seen or name not in links:
            continue
        seen.add(name)
        inertial = links[name].inertial
        total += inertial.mass if inertial is not None and inertial.mass > 0 else 0.0
        todo.extend(j.child for j in ctx.robot.joints if j.parent == name and j.type is JointType.FIXED)
    return total


def _collision_volume(link: Link) -> float | None:
    """The summed volume (m³) of the link's collision shapes, ``None`` when one is unknown."""
    total = 0.0
    for item in link.collisions:
        solid = geometry_properties(item.geometry)
        if solid is None:
            return None
        total += solid.volume
    return total


def _open_collision_mesh(link: Link) -> str | None:
    """The file name of the first collision mesh of *link* that is not a closed surface (its
    volume was measured by its convex hull), else ``None``."""
    for item in link.collisions:
        if isinstance(item.geometry, Mesh):
            solid = geometry_properties(item.geometry)
            if solid is not None and solid.approximate:
                return item.geometry.filename
    return None


@register
class TargetDefaultMass(_Targets):
    """A consumer fills in the mass of a link that has none.

    ## What it does
    For each target of `--target`, reports links without `<inertial>` (or
    with zero mass) and what the consumer gives them: PyBullet 1 kg; MuJoCo
    and Isaac Sim the mass of the collision geometry at 1000 kg/m³ (when a
    collision mesh is not closed, no number: the volume of an open mesh is not
    the part's; MuJoCo gives a lidless 2 kg box 1.61 kg); Pinocchio,
    KDL and Drake zero; Gazebo (classic and gz-sim) leaves the link out, with
    every link below it, when the link is not attached by a fixed joint.
    Drake also floats a root link that is not welded to the world, and stops
    a simulation whose mass matrix a massless link leaves singular: a warning
    when the link is not welded to its parent and nothing on fixed joints
    below it carries mass.

    ## Why it matters
    The same file then weighs different amounts in each program: a sensor
    mount that weighs nothing in RViz weighs 1 kg in PyBullet, in Gazebo
    the arm below a massless link simply disappears, and in Drake the first
    simulation step stops with "mass matrix ... is not positive-definite".

    ## Example
    ```xml
    <link name="arm"><collision>…</collision></link>  <!-- no <inertial> -->
    ```

    ## Fix
    Give every link that moves an `<inertial>` with its real mass and inertia
    (`urdftool check` rule `missing-inertial` suggests one from the geometry).
    """

    code = "T001"
    name = "target-default-mass"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for target in targets(ctx):
            if target.missing_inertial is None:
                continue
            for link in ctx.robot.links:
                if link.name == "world":
                    continue
                massless = link.inertial is None or link.inertial.mass == 0
                if not massless:
                    continue
                found = self._effect(ctx, target, link)
                if found is not None:
                    yield found

    def _zero(
        self, ctx: CheckContext, target: Target, link: Link, what: str, data: Mapping[str, object]
    ) -> Diagnostic:
        """Zero mass and inertia; for Drake, a simulation that stops when nothing below carries mass."""
        floats = target.floating_root and link.name == ctx.tree.root
        parent = _parent_joint(ctx, link.name)
        joined = floats or (parent is not None and parent.type is not JointType.FIXED)  # not welded
        stops = target.massless_stops and joined and _lumped_mass(ctx, link.name) == 0
        message = f"{target.label} will give link '{link.name}' zero mass and inertia (it {what})"
        if floats:
            message += " and make it a free body unless it is welded to the world"
        if stops:
            message += "; a simulation stops at its first step (a mass matrix that is not positive-definite)"
            if ctx.tree.children(link.name):
                message += " unless the links below it carry inertia about each way it moves"
        return self.diagnostic(
            message, link.span, element=f"link[{link.name}]",
            severity=Severity.WARNING if stops else Severity.INFO,
            help="give the link an <inertial> if it carries any mass"
            + (" (or weld it to the world: plant.WeldFrames)" if floats else ""),
            data={**data, "mass": 0.0, "floats": floats, "stops": stops},
        )

    def _effect(self, ctx: CheckContext, target: Target, link: Link) -> Diagnostic | None:
        kind = target.missing_inertial
        what = "has no <inertial>" if link.inertial is None else "has zero mass"
        data = {"target": target.name, "link": link.name, "effect": kind}
        if kind == "dropped":
            parent = _parent_joint(ctx, link.name)
            if parent is not None and parent.type is JointType.FIXED:
                return None  # lumped into its parent, not dropped
            if _lumped_mass(ctx, link.name) > 0:
                return None  # links on fixed joints below it are lumped in first and give it mass
            below = _descendants(ctx, link.name)
            tail = f", with the {len(below)} link(s) below it" if below else ""
            return self.diagnostic(
                f"{target.label} will leave link '{link.name}' out of the model{tail} "
                f"(it {what}; the URDF-to-SDF conversion drops such links)",
                link.span, element=f"link[{link.name}]", severity=Severity.ERROR,
                help="give the link an <inertial> with a positive mass",
                data={**data, "dropped": [link.name, *below]},
            )
        if kind == "one-kg":
            if link.inertial is not None:  # PyBullet keeps an explicit zero (a static base)
                return None
            return self.diagnostic(
                f"{target.label} will give link '{link.name}' mass 1 kg (it {what}), "
                "with an inertia computed from its collision shapes",
                link.span, element=f"link[{link.name}]", help="give the link an <inertial>",
                data={**data, "mass": 1.0},
            )
        if not _moving(ctx, link.name, target):
            return None
        if kind == "zero":
            return self._zero(ctx, target, link, what, data)
        open_mesh = _open_collision_mesh(link)
        if open_mesh is not None:
            return self.diagnostic(
                f"{target.label} will give link '{link.name}' a mass computed from its collision "
                f"mesh '{open_mesh}', which is not closed: the volume of an open mesh is not the "
                f"part's, so neither is the mass (it {what})",
                link.span, element=f"link[{link.name}]",
                help="give the link an <inertial>, or close the mesh",
                data={**data, "mass": None, "open_mesh": open_mesh},
            )
        volume = _collision_volume(link)
        if volume is None or volume <= 0:
            return None
        mass = 1000.0 * volume
        return self.diagnostic(
            f"{target.label} will give link '{link.name}' the mass of its collision geometry at "
            f"1000 kg/m³: {mass:.3g} kg (it {what})",
            link.span, element=f"link[{link.name}]", help="give the link an <inertial>",
            data={**data, "mass": mass, "volume": volume},
        )


@register
class TargetInertiaFromCollision(_Targets):
    """PyBullet replaces a link's inertia by one computed from its collision shapes.

    ## What it does
    With `--target pybullet`, predicts the inertia PyBullet's `loadURDF`
    uses without the `URDF_USE_INERTIA_FROM_FILE` flag (that of the link's
    collision box or sphere at the link's mass, and nearly zero for a link
    without collision shapes) and reports links where a principal moment
    differs from the file's by more than a factor of 2.

    ## Why it matters
    A link's rotational dynamics in PyBullet are then not those written in
    the file: a sensor head without collision shapes spins freely, a
    long link with a small collision box swings too fast.

    ## Example
    A camera link with an `<inertial>` and no `<collision>`.

    ## Fix
    Load with `p.loadURDF(path, flags=p.URDF_USE_INERTIA_FROM_FILE)`.
    """

    code = "T010"
    name = "target-inertia-from-collision"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        if not any(t.inertia_from_collision for t in targets(ctx)):
            return
        for link in ctx.robot.links:
            inertial = link.inertial
            if inertial is None or inertial.mass <= 0:
                continue
            predicted = _bullet_inertia(link, inertial.mass)
            if predicted is None:
                continue
            moments, _ = principal_moments(inertial.inertia_matrix)
            written = sorted(abs(float(v)) for v in moments)
            if min(written) <= 0:
                continue
            ratios = [max(p, 1e-300) / w for p, w in zip(sorted(predicted), written, strict=True)]
            if all(1 / INERTIA_FACTOR <= r <= INERTIA_FACTOR for r in ratios):
                continue
            shown = ", ".join(f"{v:.3g}" for v in predicted)
            yield self.diagnostic(
                f"PyBullet will give link '{link.name}' the inertia of its collision shapes "
                f"(diagonal {shown} kg·m²) instead of the file's, unless loaded with "
                "URDF_USE_INERTIA_FROM_FILE",
                link.span, element=f"link[{link.name}]",
                help="load it with flags=p.URDF_USE_INERTIA_FROM_FILE",
                data={"target": "pybullet", "link": link.name, "predicted": list(predicted)},
            )


def _bullet_inertia(link: Link, mass: float) -> tuple[float, float, float] | None:
    """Bullet's local inertia for the link's collision shape, where it can be predicted exactly."""
    if not link.collisions:
        return (0.0, 0.0, 0.0)  # an empty compound: Bullet's near-zero inertia
    if len(link.collisions) != 1:
        return None
    geometry = link.collisions[0].geometry
    if isinstance(geometry, Sphere):
        value = 0.4 * mass * geometry.radius**2
        return (value, value, value)
    if isinstance(geometry, Box):
        x, y, z = geometry.size
        return (mass * (y * y + z * z) / 12, mass * (x * x + z * z) / 12, mass * (x * x + y * y) / 12)
    return None
