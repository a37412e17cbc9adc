"""Inertia (I) that does not fit the link: geometry, density, centre of mass, root and mass ratios.

The plausibility half of the inertia family: the tensors here are valid (the
validity rules are in :mod:`urdftool.rules.inertia`) but disagree with the
link's own geometry or with the rest of the robot. Thresholds and the reasons
for them are in ``docs/inertia.md``.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator
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
from urdftool.model.pose import rotate_tensor
from urdftool.physics.bodies import MIN_VALUE, RigidBody
from urdftool.physics.describe import (
    fmt,
    fmt_tensor,
)
from urdftool.physics.linkmass import (
    InertiaComparison,
    bounds_diagonal,
    density,
    distance_outside,
)
from urdftool.physics.massprops import SolidProperties
from urdftool.rules.inertia import _Inertia, _where, bodies, body_of_link

#: inertia-geometry-mismatch fires when the declared inertia is this many times
#: larger or smaller (trace ratio) than the geometry's. At √10 ≈ 3.16 or below,
#: any link the rule accepts still gets caught when its inertia is made 10×
#: larger or smaller; 3 leaves a little room for that.
INERTIA_FACTOR = 3.0
#: A declared inertia larger than the geometry's is reported only when no mass
#: distribution inside the geometry's bounds, grown by this factor in every
#: direction, could have it (see _possible_for_bounds).
BOUNDS_MARGIN = 1.0
#: Right moments, wrong axes: principal moments within this factor of the
#: geometry's, while the moment about some geometric axis is off by the next.
SAME_MOMENTS = 1.15
AXIS_FACTOR = 1.4
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


@register
class InertiaGeometryMismatch(_Inertia):
    """The declared inertia is far from what the link's geometry has at its mass.

    ## What it does
    Computes the inertia of the link's collision geometry, and of its visual
    geometry, as uniform solids of the declared mass: boxes, cylinders,
    spheres and capsules by formula, meshes from their enclosed volume (or
    their convex hull when they are not closed), several shapes composed with
    their origins; the collision geometry is used, the visual one when the
    collision geometry cannot be measured. The result is rotated into the
    inertial frame of `<inertial><origin rpy>`. The finding is reported when
    the declared tensor is 3× smaller (ratio of traces) than the geometry's,
    or larger than any distribution of the declared mass inside the
    geometry's bounds could have; and when the principal moments agree but
    sit on the wrong axes (a wheel whose spin moment is on an axis it does
    not spin about; a product of inertia of the wrong sign, when flipping it
    is the whole difference, is said so: a mirrored part's values). A link
    welded below another is judged with its body: when its own tensor,
    declared or fitted, leaves the body's inertia within 3×, nothing a
    consumer computes depends on it and it is not reported.

    ## Why it matters
    Placeholder inertias (`0.1` everywhere, `1e-3` on a 20 g finger) and
    moments pasted in the wrong frame make controllers and simulators
    accelerate the link wrongly: joints oscillate, grippers fling objects,
    a 60× too large inertia hides contact dynamics entirely.

    ## Example
    ```xml
    <link name="lidar">
      <inertial>
        <mass value="1e-5"/>
        <inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="1e-6"/>
      </inertial>
      <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
    </link>
    ```

    ## Fix
    Use the tensor from CAD, or the one in the finding's `help` (the
    geometry's at the declared mass, in the inertial frame). For a wheel
    whose cylinder is rolled onto the axle, either roll the inertial frame
    the same way or write the spin moment on the axle's axis.
    """

    code = "I006"
    name = "inertia-geometry-mismatch"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        judged = (
            link
            for link in ctx.robot.links
            if link.inertial is not None
            and not link.inertial.mass <= MIN_VALUE  # as written: a NaN mass is judged
            and link_mass.declared_verdict(ctx, link.inertial).valid
        )
        for link, comparison in link_mass.comparisons(ctx, judged):
            if comparison is None:
                continue
            if comparison.factor >= INERTIA_FACTOR:
                if not _possible_for_bounds(link, comparison) and not _lost_in_body(
                    ctx, link, comparison
                ):
                    yield self._scale_finding(link, comparison)
                continue
            factor = _wrong_axes(link, comparison)
            if factor is not None:
                yield self._axes_finding(link, comparison, factor)

    def _scale_finding(self, link: Link, best: InertiaComparison) -> Diagnostic:
        assert link.inertial is not None
        times = f"{fmt(best.ratio)}×" if best.ratio >= 1 else f"1/{fmt(1 / best.ratio)} of"
        return self.diagnostic(
            f"link '{link.name}': declared inertia is {times} the {best.solid.label} at "
            f"{fmt(link.inertial.mass)} kg ({fmt_tensor(best.computed)})",
            link.inertial.inertia_span or link.inertial.span or link.span,
            element=_where(link, "inertial", "inertia"),
            help=f"a uniform {best.solid.label} ({best.source} geometry) of "
            f"{fmt(link.inertial.mass)} kg "
            f"has, in the inertial frame, {fmt_tensor(best.computed)}"
            + (" (mesh not closed: measured by its convex hull)" if best.solid.approximate else ""),
            data={
                "ratio": best.ratio,
                "source": best.source,
                "geometry": best.solid.label,
                "computed": best.computed.tolist(),
                "declared": link.inertial.inertia_matrix.tolist(),
            },
        )

    def _axes_finding(self, link: Link, comparison: InertiaComparison, factor: float) -> Diagnostic:
        assert link.inertial is not None
        flipped = _flipped_products(link.inertial.inertia_matrix, comparison.computed)
        if flipped:
            declared, computed = link.inertial.inertia_matrix, comparison.computed
            values = ", ".join(f"{name} {fmt(float(declared[i, j]))} against {fmt(float(computed[i, j]))}"
                               for name, (i, j) in flipped)
            names = " and ".join(name for name, _ in flipped)
            return self.diagnostic(
                f"link '{link.name}': declared inertia has the moments of the {comparison.solid.label}, "
                f"but {names} {'has' if len(flipped) == 1 else 'have'} the opposite sign "
                f"({values} kg·m²): a mirrored part's values, or the other side's",
                link.inertial.inertia_span or link.inertial.span or link.span,
                element=_where(link, "inertial", "inertia"),
                help=f"flip the sign of {names}; in the inertial frame the {comparison.source} geometry "
                f"has {fmt_tensor(comparison.computed)}",
                data={
                    "axis_factor": factor,
                    "flipped": [name for name, _ in flipped],
                    "source": comparison.source,
                    "geometry": comparison.solid.label,
                    "computed": comparison.computed.tolist(),
                    "declared": link.inertial.inertia_matrix.tolist(),
                },
            )
        return self.diagnostic(
            f"link '{link.name}': declared inertia has the moments of the {comparison.solid.label} "
            f"on the wrong axes (off by {fmt(factor)}× about one of its axes in the inertial "
            "frame)",
            link.inertial.inertia_span or link.inertial.span or link.span,
            element=_where(link, "inertial", "inertia"),
            help=f"in the inertial frame the {comparison.source} geometry has "
            f"{fmt_tensor(comparison.computed)}; rotate <inertial><origin rpy> like the geometry's "
            "origin, or write these values",
            data={
                "axis_factor": factor,
                "source": comparison.source,
                "geometry": comparison.solid.label,
                "computed": comparison.computed.tolist(),
                "declared": link.inertial.inertia_matrix.tolist(),
            },
        )


def _possible_for_bounds(link: Link, comparison: InertiaComparison) -> bool:
    """Whether a declared inertia *larger* than the uniform solid's could still be the link's.

    Geometry is a stand-in for the part: CAD tensors include motors, cables and
    flanges that a collision hull or a primitive leaves out, so "3× the uniform
    solid" alone is no evidence. Evidence is a tensor that no distribution of
    the declared mass inside the geometry's bounds can have: about the centre
    of mass, trace(I) = 2·Σ mᵢ·|rᵢ|² ≤ 2·m·R², R the distance from the centre
    of mass to the farthest corner of the bounds, enlarged by BOUNDS_MARGIN.
    """
    assert link.inertial is not None
    if comparison.ratio < 1:
        return False
    solid = comparison.solid
    com = np.asarray(link.inertial.origin.xyz, dtype=float)
    corners = np.array(
        [[(solid.bounds_min, solid.bounds_max)[k >> axis & 1][axis] for axis in range(3)] for k in range(8)]
    )
    reach = float(np.max(np.linalg.norm(corners - com, axis=1))) * BOUNDS_MARGIN
    declared = float(np.trace(link.inertial.inertia_matrix))
    return declared <= 2.0 * link.inertial.mass * reach**2


def _lost_in_body(ctx: CheckContext, link: Link, comparison: InertiaComparison) -> bool:
    """Whether *link* is welded below another link and its own inertia, declared or fitted to
    its geometry, leaves the welded body's inertia within INERTIA_FACTOR.

    Every consumer that matters here (Pinocchio, MuJoCo's import, Gazebo's
    lumping) sees the body, not the link: a 1 g IMU link with a placeholder
    1e-4 kg·m² welded into a 10 kg trunk changes nothing anyone computes. The
    head of a body is always judged on its own, so a planted mistake in a
    moving link is always caught.
    """
    body = body_of_link(ctx, link.name)
    if body is None or body.head == link.name or link.inertial is None:
        return False
    declared = float(np.trace(body.declared_inertia))
    own = rotate_tensor(comparison.computed, link.inertial.origin.rpy)
    fitted = float(np.trace(body.composite_inertia({link.name: own})))
    if declared <= 0 or fitted <= 0:
        return False
    return max(declared / fitted, fitted / declared) < INERTIA_FACTOR


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


def _wrong_axes(link: Link, comparison: InertiaComparison) -> float | None:
    """The off-axis factor when the principal moments match the geometry's but their axes do not."""
    assert link.inertial is not None
    if comparison.worst > SAME_MOMENTS:
        return None
    factor = _axis_factor(link.inertial.inertia_matrix, comparison.computed)
    return factor if factor >= AXIS_FACTOR else None


def _axis_factor(declared: np.ndarray, computed: np.ndarray) -> float:
    """How far *declared*'s moment about one of *computed*'s principal axes is from *computed*'s."""
    _, axes = np.linalg.eigh(computed)
    along = [float(axes[:, k] @ declared @ axes[:, k]) for k in range(3)]
    moments = [float(axes[:, k] @ computed @ axes[:, k]) for k in range(3)]
    return max(max(d / c, c / d) for d, c in zip(along, moments, strict=True))


_PRODUCTS = (("ixy", (0, 1)), ("ixz", (0, 2)), ("iyz", (1, 2)))


def _flipped_products(declared: np.ndarray, computed: np.ndarray) -> list[tuple[str, tuple[int, int]]]:
    """The products of inertia whose sign, flipped, puts *declared* on *computed*'s axes (a CAD
    export of the mirrored part, or the left side's values on the right), when its diagonal is the
    geometry's already; else empty, and the axes themselves are wrong."""
    diagonal = [(float(declared[k, k]), float(computed[k, k])) for k in range(3)]
    if any(d <= 0 or c <= 0 or max(d / c, c / d) > SAME_MOMENTS for d, c in diagonal):
        return []
    flipped = [(name, (i, j)) for name, (i, j) in _PRODUCTS if declared[i, j] * computed[i, j] < 0]
    if not flipped:
        return []
    fixed = declared.copy()
    for _, (i, j) in flipped:
        fixed[i, j] = fixed[j, i] = -declared[i, j]
    return flipped if _axis_factor(fixed, computed) < AXIS_FACTOR else []


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
            for source, solid in link_mass.geometry_sources(ctx, link):
                value = density(link, solid)
                if value is None:
                    continue
                found.append((value, source, solid))
                if low <= value <= high:
                    break
            if not found or any(low <= value <= high for value, _, _ in found):
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
            com = np.asarray(link.inertial.origin.xyz, dtype=float)
            found: list[tuple[float, float, str, SolidProperties]] = []
            for source, solid in link_mass.geometry_sources(ctx, link):
                margin = max(COM_MARGIN, COM_MARGIN_FRACTION * bounds_diagonal(solid))
                outside = distance_outside(com, solid)
                found.append((outside, margin, source, solid))
                if outside <= margin:
                    break
            if not found or any(outside <= margin for outside, margin, _, _ in found):
                continue
            outside, _, source, solid = min(found, key=lambda f: f[0])
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
                    "com": com.tolist(),
                    "distance": outside,
                    "source": source,
                    "bounds": [lo.tolist(), hi.tolist()],
                    "centroid": solid.center.tolist(),
                },
            )


def fmt_vec(values: np.ndarray) -> str:
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
