"""Inertia (I) that does not fit the link: density, centre of mass, root and mass ratios.

The plausibility half of the inertia family: the tensors here are valid (the
validity rules are in :mod:`urdftool.rules.inertia`) but disagree with the
link's own geometry or with the rest of the robot. Thresholds and the reasons
for them are in ``docs/inertia.md``.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable, Iterator
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
else:
    # NumPy is imported on first use: a structural check must not pay for it.
    from urdftool.lazy import numpy as np

from urdftool.catalogue.registry import register
from urdftool.diagnostics import Diagnostic, Related, Severity
from urdftool.facts import link_mass
from urdftool.facts.context import CheckContext
from urdftool.model import Link
from urdftool.physics.bodies import MIN_VALUE, RigidBody
from urdftool.physics.describe import (
    fmt,
)
from urdftool.physics.linkmass import (
    bounds_diagonal,
    density,
    distance_outside,
)
from urdftool.physics.massprops import SolidProperties
from urdftool.rules.inertia import _Inertia, _where, bodies, body_of_link

#: Densities (kg/m³) outside this range are not a solid part: lighter than
#: structural foam, or denser than osmium, the densest element.
DENSITY_RANGE = (10.0, 22_600.0)
#: A centre of mass may sit this far outside the geometry's bounds (m, and a
#: fraction of the bounds' diagonal) before it is reported: geometry often
#: leaves out motors and cables.
COM_MARGIN = 0.01
COM_MARGIN_FRACTION = 0.1
#: Moving bodies this many times lighter or heavier than the body they hang from.
MASS_RATIO = 1000.0

#: A welded link's share of its body's mass below which its density is not judged.
TRACE_SHARE = 0.01


def _trace_in_body(ctx: CheckContext, link: Link) -> bool:
    """Whether *link* is welded below another link and carries under 1 % of that body's mass.

    Every consumer weighs and pushes the welded body, not the link: Baxter's 0.1 g
    `display` and `sonar_ring` frames welded into a 100 kg torso change nothing anyone
    computes, whatever their shapes' volumes. A body's head is always judged on its own.
    """
    body = body_of_link(ctx, link.name)
    if body is None or body.head == link.name or link.inertial is None:
        return False
    return link.inertial.mass < TRACE_SHARE * body.mass



@register
class ImplausibleDensity(_Inertia):
    """The link's mass and geometric volume give a density no solid part has.

    ## What it does
    Divides the declared mass by the volume of the link's collision geometry
    and of its visual geometry, and reports when every one is below
    10 kg/m³ (lighter than structural foam) or above 22,600 kg/m³ (denser
    than osmium, the densest element). A link welded below another one that
    carries under 1 % of that rigid body's mass is not judged: consumers weigh
    and push the body, not the trace.

    ## Why it matters
    The mass is usually a placeholder (`1e-6`, `0.001`, `1`) or the geometry
    is in the wrong units. Either way the robot's weight, its centre of mass
    and the load on every joint are wrong; a 1 g "sensor" inside a 20 cm box
    also gets pushed around by contacts like a feather.

    ## Example
    ```xml
    <link name="imu_link">
      <inertial><mass value="0.001"/>…</inertial>
      <collision><geometry><box size="0.001 0.001 0.001"/></geometry></collision>
    </link>
    ```

    ## Fix
    Use the part's real mass (its data sheet, or CAD with the right
    material), or fix the geometry's size or the mesh's `scale`.
    """

    code = "I007"
    name = "implausible-density"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        low, high = DENSITY_RANGE
        for link in ctx.robot.links:
            if link.inertial is None or link.inertial.mass <= MIN_VALUE or _trace_in_body(ctx, link):
                continue
            found: list[tuple[float, str, SolidProperties]] = []
            plausible = False
            for source, solid in link_mass.geometry_sources(ctx, link):
                value = density(link, solid)
                if value is None:
                    continue
                if low <= value <= high:
                    plausible = True  # one source with a plausible density is enough
                    break
                found.append((value, source, solid))
            if plausible or not found:
                continue
            value, source, solid = min(found, key=lambda f: abs(np.log10(f[0] / 1000.0)))
            side = "lighter than foam" if value < low else "denser than any metal"
            yield self.diagnostic(
                f"link '{link.name}': {fmt(link.inertial.mass)} kg in the {fmt(solid.volume)} m³ "
                f"{solid.label} is {fmt(value)} kg/m³, {side}",
                link.inertial.mass_span or link.inertial.span or link.span,
                element=_where(link, "inertial", "mass"),
                help=f"at 1000 kg/m³ (plastic) this {source} geometry weighs "
                f"{fmt(solid.volume * 1000.0)} kg, at 2700 kg/m³ (aluminium) "
                f"{fmt(solid.volume * 2700.0)} kg",
                data={
                    "density": value,
                    "volume": solid.volume,
                    "source": source,
                    "geometry": solid.label,
                    "range": list(DENSITY_RANGE),
                },
            )


@register
class ComOutsideGeometry(_Inertia):
    """The centre of mass lies outside the link's geometry.

    ## What it does
    Compares the `<inertial><origin xyz>` (the centre of mass, link frame)
    with the bounding box of the link's collision geometry and of its visual
    geometry, and reports when it lies outside both by more than 1 cm and
    10% of the part's size.

    ## Why it matters
    A body's centre of mass is always inside the convex hull of the body.
    One outside is a sign of an offset written in the wrong frame, in
    millimetres, or copied from another link; the robot then tips, sags and
    needs torques it never needs in reality.

    ## Example
    ```xml
    <inertial><origin xyz="0 0 0.5"/><mass value="1"/>…</inertial>
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
    ```

    ## Fix
    Put the centre of mass where CAD gives it, in the link frame (the frame
    of the joint that carries the link, not the mesh's or the parent's).
    """

    code = "I008"
    name = "com-outside-geometry"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for link in ctx.robot.links:
            if link.inertial is None or link.inertial.mass <= MIN_VALUE:
                continue
            com = link.inertial.origin.xyz
            found: list[tuple[float, str, SolidProperties]] = []
            inside = False
            for source, solid in link_mass.geometry_sources(ctx, link):
                outside = distance_outside(com, solid)
                if outside <= max(COM_MARGIN, COM_MARGIN_FRACTION * bounds_diagonal(solid)):
                    inside = True  # inside one source's bounds (with the margin) is enough
                    break
                found.append((outside, source, solid))
            if inside or not found:
                continue
            outside, source, solid = min(found, key=lambda f: f[0])
            lo, hi = solid.bounds_min, solid.bounds_max
            yield self.diagnostic(
                f"link '{link.name}': centre of mass ({fmt_vec(com)}) m is {fmt(outside)} m "
                "outside "
                f"its {solid.label}",
                link.inertial.span or link.span,
                element=_where(link, "inertial", "origin"),
                help=f"the {source} geometry spans x {fmt(lo[0])}..{fmt(hi[0])}, "
                f"y {fmt(lo[1])}..{fmt(hi[1])}, "
                f"z {fmt(lo[2])}..{fmt(hi[2])} m in the link frame; its centroid is "
                f"({fmt_vec(solid.center)}) m",
                data={
                    "com": list(com),
                    "distance": outside,
                    "source": source,
                    "bounds": [list(lo), list(hi)],
                    "centroid": list(solid.center),
                },
            )


def fmt_vec(values: Iterable[float]) -> str:
    return " ".join(fmt(float(v)) for v in values)


@register
class RootLinkInertia(_Inertia):
    """The root link has an inertia, which KDL ignores.

    ## What it does
    Reports a root link that has mass when it has children (it is then a
    robot's base, not a loose object).

    ## Why it matters
    KDL (`robot_state_publisher`, MoveIt's KDL solvers, many ROS
    controllers) does not support inertia on the root link and drops it with
    a warning, so those tools see a robot lighter than the simulator does.
    For a fixed-base arm this is harmless; for a mobile base it means KDL's
    dynamics miss the base.

    ## Example
    ```xml
    <robot name="arm">
      <link name="base_link"><inertial><mass value="4"/>…</inertial></link>
      …
    ```

    ## Fix
    Add a massless root above it, which every tool accepts:
    ```xml
    <link name="base_footprint"/>
    <joint name="base_joint" type="fixed">
      <parent link="base_footprint"/><child link="base_link"/>
    </joint>
    ```
    """

    code = "I009"
    name = "root-link-inertia"
    severity = Severity.INFO

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for root in ctx.tree.roots:
            link = ctx.robot.link(root)
            if link is None or link.inertial is None or link.inertial.mass <= MIN_VALUE:
                continue
            if not ctx.tree.child_joints.get(root):
                continue
            yield self.diagnostic(
                f"root link '{root}' has {fmt(link.inertial.mass)} kg; KDL ignores the root link's "
                "inertia",
                link.inertial.span or link.span,
                element=_where(link, "inertial"),
                help=f"add a massless root link joined to '{root}' by a fixed joint",
                data={"mass": link.inertial.mass},
            )


#: A body lighter than this (kg) is a placeholder for the typical body's sake: Pepper's 30
#: fingers of 2 mg made the median a finger, and its wrist "out of line".
PLACEHOLDER_MASS = 1e-3


def _typical_mass(ctx: CheckContext) -> float:
    """The robot's typical body mass (kg): the median of its bodies of a gram or more, or of all
    its bodies with a mass when none weighs that much (a model of a tiny device)."""
    masses = sorted(b.mass for b in bodies(ctx) if b.mass > MIN_VALUE)
    real = [m for m in masses if m >= PLACEHOLDER_MASS] or masses
    return real[len(real) // 2] if real else 1.0


def _suspect(body: RigidBody, parent: RigidBody, typical: float) -> tuple[RigidBody, str]:
    """Which of a joint's two bodies has the mass to check, and why (the message's words). A
    placeholder (a gram or less) against a real body is the placeholder: RexROV's 1 g sensors
    outnumber its real bodies, so the median is 1 g and the 1.86 t hull looked out of line.
    Otherwise the one out of line with the robot's typical body (_typical_mass): a link made 1e4
    times heavier, not its neighbours."""
    light = [b for b in (body, parent) if b.mass <= PLACEHOLDER_MASS]
    if len(light) == 1:
        placeholder = light[0]
        return placeholder, (f"'{placeholder.head}' is the one to check: {fmt(placeholder.mass)} kg "
                             "reads as a placeholder")
    suspect = max((body, parent), key=lambda b: abs(math.log(b.mass / typical)))
    return suspect, f"'{suspect.head}' is the one out of line with the robot's typical {fmt(typical)} kg body"


@register
class ExtremeMassRatio(_Inertia):
    """A moving body is 1000× lighter or heavier than the body it hangs from.

    ## What it does
    For every moving joint, compares the mass of the rigid body it carries
    (the child link with everything welded to it by fixed joints) with the
    rigid body it hangs from, and reports ratios beyond 1000.

    ## Why it matters
    The joint-space mass matrix then spans many orders of magnitude: explicit
    integrators need tiny time steps, iterative solvers converge slowly and
    small numerical errors in the light body become large accelerations. The
    cause is usually a placeholder mass (`1e-6` on a "virtual" link between
    two joints) rather than a real design.

    ## Example
    ```xml
    <link name="hip_virtual"><inertial><mass value="1e-6"/>…</inertial></link>
    ```

    ## Fix
    Give the light body a realistic mass, or merge joints that meet in one
    point into a single spherical or universal joint where the target
    supports it.
    """

    code = "I010"
    name = "extreme-mass-ratio"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        typical = _typical_mass(ctx)
        for body in bodies(ctx):
            if not body.moves or body.mass <= MIN_VALUE:
                continue
            joint = ctx.robot.joint(body.joint or "")
            parent = body_of_link(ctx, joint.parent) if joint else None
            if joint is None or parent is None or parent.mass <= MIN_VALUE:
                continue
            ratio = body.mass / parent.mass
            if 1 / MASS_RATIO <= ratio <= MASS_RATIO:
                continue
            lighter = "lighter" if ratio < 1 else "heavier"
            factor = 1 / ratio if ratio < 1 else ratio
            suspect, why = _suspect(body, parent, typical)
            link = ctx.robot.link(suspect.head)
            inertial = link.inertial if link is not None else None
            location = (inertial.mass_span or inertial.span) if inertial is not None else None
            finding = self.diagnostic(
                f"joint '{joint.name}' carries {fmt(body.mass)} kg ('{body.head}'), {fmt(factor)}× "
                f"{lighter} than the {fmt(parent.mass)} kg it hangs from ('{parent.head}'); {why}",
                location or joint.span,
                element=f"joint[{joint.name}]",
                help=f"check the mass of '{suspect.head}'",
                data={"child_mass": body.mass, "parent_mass": parent.mass, "ratio": ratio,
                      "suspect": suspect.head},
            )
            if joint.span is not None:
                joint_note = Related(joint.span, f"joint '{joint.name}'")
                finding = dataclasses.replace(finding, related=(joint_note,))
            yield finding
