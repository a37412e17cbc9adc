"""Inertia (I): masses and tensors a simulator can use, and that match the geometry.

Which links must have mass is decided per rigid body (links welded by fixed
joints, see :mod:`urdftool.physics.bodies`): a body that moves needs mass and
inertia; a massless link welded to a body that has mass is carried by it, and
is only worth a warning when it has collision geometry (it collides but weighs
nothing); a massless root is the usual world or footprint frame and is fine.
Thresholds are calibrated on example-robot-data and pybullet_data; the
numbers and the reasons are in ``docs/inertia.md``.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
else:
    # NumPy is imported on first use: a structural check must not pay for it.
    from urdftool.lazy import numpy as np

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.model import Link
from urdftool.physics.bodies import MIN_VALUE, MassRole, RigidBody, body_of, mass_role, rigid_bodies
from urdftool.physics.describe import (
    fmt,
    fmt_tensor,
    is_zero_tensor,
    suggested_mass,
    tensor_data,
    valid_tensor_help,
)
from urdftool.physics.inertia import MIN_MOMENT, assess
from urdftool.physics.linkmass import (
    InertiaComparison,
    bounds_diagonal,
    compare_with_geometry,
    density,
    distance_outside,
    geometry_sources,
)
from urdftool.physics.massprops import SolidProperties
from urdftool.rules.context import CheckContext

#: inertia-geometry-mismatch fires when the declared inertia is this many times
#: larger or smaller (trace ratio) than the geometry's. At √10 ≈ 3.16 or below,
#: any link the rule accepts still gets caught when its inertia is made 10×
#: larger or smaller; 3 leaves a little room for that.
INERTIA_FACTOR = 3.0
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


class _Inertia(Rule):
    family = Family.INERTIA


def _where(link: Link, *parts: str) -> str:
    return "/".join((f"link[{link.name}]", *parts))


def bodies(ctx: CheckContext) -> list[RigidBody]:
    """The robot's rigid bodies, computed once per check run."""
    if "inertia.bodies" not in ctx.cache:
        found = rigid_bodies(ctx.tree)
        ctx.cache["inertia.bodies"] = found
        ctx.cache["inertia.body_of"] = body_of(found)
    return ctx.cache["inertia.bodies"]  # type: ignore[no-any-return]


def body_of_link(ctx: CheckContext, name: str) -> RigidBody | None:
    bodies(ctx)
    return ctx.cache["inertia.body_of"].get(name)  # type: ignore[no-any-return]


def _role(ctx: CheckContext, link: Link) -> MassRole | None:
    return mass_role(link, body_of_link(ctx, link.name))


_SEVERITY = {"error": Severity.ERROR, "warning": Severity.WARNING}


@register
class MissingInertial(_Inertia):
    """A link that moves or collides has no `<inertial>`.

    ## What it does
    Reports links without `<inertial>` that need one: an error when the link
    heads a moving body (its joint is not fixed) and nothing welded to it by
    fixed joints has mass; a warning when the link has collision geometry and
    is carried by a body with mass. Massless roots (`world`,
    `base_footprint`) and frame-only links (no collision geometry) welded to a
    body are not reported.

    ## Why it matters
    URDF reads a missing `<inertial>` as 0 kg. Gazebo drops such links (and
    everything below a moving one), PyBullet silently gives them 1 kg and a
    unit inertia, MuJoCo computes a mass from the geometry at 1000 kg/m³: the
    same file is three different robots.

    ## Example
    ```xml
    <joint name="wrist" type="revolute">…<child link="hand"/></joint>
    <link name="hand">
      <collision><geometry><box size="0.08 0.08 0.04"/></geometry></collision>
    </link>
    ```

    ## Fix
    Add the link's real mass and inertia (from CAD, or the formula of its
    collision shape):
    ```xml
    <inertial>
      <mass value="0.26"/>
      <inertia ixx="1.7e-4" ixy="0" ixz="0" iyy="1.7e-4" iyz="0" izz="2.8e-4"/>
    </inertial>
    ```
    """

    code = "I001"
    name = "missing-inertial"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for link in ctx.robot.links:
            if link.inertial is not None:
                continue
            role = _role(ctx, link)
            if role is None:
                continue
            yield self.diagnostic(
                f"link '{link.name}' {role.why} but has no <inertial> (URDF reads 0 kg; "
                "PyBullet assumes 1 kg, MuJoCo computes one from the geometry)",
                link.span,
                element=_where(link),
                severity=_SEVERITY[role.severity],
                help=suggested_mass(link) or "add <inertial> with the link's mass and inertia",
                data={
                    "joint": role.joint,
                    "carrier": role.carrier,
                    "carrier_mass": role.carrier_mass,
                },
            )


@register
class ZeroMass(_Inertia):
    """A link that moves or collides has zero mass.

    ## What it does
    Reports `<mass value="0"/>` (or below 1e-15 kg, what MuJoCo treats as
    zero) on a link that needs mass: an error when the link heads a moving
    body with no mass anywhere in it, a warning when the link has collision
    geometry and is welded by fixed joints to a body that has mass. A massless
    root and massless frame-only links are fine.

    ## Why it matters
    A moving body without mass cannot be accelerated: MuJoCo refuses the model
    ("mass and inertia of moving bodies must be larger than mjMINVAL"), Gazebo
    drops the link and what hangs from it. A colliding sensor with no mass
    leaves its weight out of the robot's dynamics.

    ## Example
    ```xml
    <link name="lidar">
      <inertial>
        <mass value="0"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>
      </inertial>
      <collision><geometry><cylinder radius="0.035" length="0.04"/></geometry></collision>
    </link>
    ```

    ## Fix
    Give the link its real mass (the data sheet of a sensor gives it) and the
    matching inertia, e.g. a 0.17 kg lidar: `<mass value="0.17"/>` with
    `ixx=iyy=7.5e-5 izz=1.0e-4`.
    """

    code = "I002"
    name = "zero-mass"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for link in ctx.robot.links:
            inertial = link.inertial
            if inertial is None or not 0 <= inertial.mass <= MIN_VALUE:
                continue
            role = _role(ctx, link)
            if role is None:
                continue
            what = (
                "zero mass and zero inertia"
                if is_zero_tensor(inertial.inertia_matrix)
                else "zero mass"
            )
            yield self.diagnostic(
                f"link '{link.name}' has {what} but {role.why}",
                inertial.mass_span or inertial.span or link.span,
                element=_where(link, "inertial", "mass"),
                severity=_SEVERITY[role.severity],
                help=suggested_mass(link) or "set the link's real mass and inertia",
                data={
                    "mass": inertial.mass,
                    "joint": role.joint,
                    "carrier": role.carrier,
                    "carrier_mass": role.carrier_mass,
                },
            )


@register
class NegativeMass(_Inertia):
    """A link has a negative mass.

    ## What it does
    Reports every `<mass>` below zero.

    ## Why it matters
    There is no negative mass: MuJoCo refuses the model ("mass and inertia
    cannot be negative"); dynamics libraries that accept it compute forces in
    the wrong direction and simulations blow up.

    ## Example
    ```xml
    <mass value="-1.2"/>
    ```

    ## Fix
    Write the magnitude (a sign slipped in from a script or a copy):
    ```xml
    <mass value="1.2"/>
    ```
    """

    code = "I003"
    name = "negative-mass"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for link in ctx.robot.links:
            inertial = link.inertial
            if inertial is None or inertial.mass >= 0:
                continue
            yield self.diagnostic(
                f"link '{link.name}' has negative mass {fmt(inertial.mass)} kg",
                inertial.mass_span or inertial.span or link.span,
                element=_where(link, "inertial", "mass"),
                help=f"mass must be positive; did you mean {fmt(-inertial.mass)} kg?",
                data={"mass": inertial.mass, "suggested": -inertial.mass},
            )


@register
class InertiaNotPositiveDefinite(_Inertia):
    """An inertia tensor has a zero or negative principal moment.

    ## What it does
    Computes the principal moments (eigenvalues) of every `<inertia>` and
    reports a tensor whose smallest moment is at or below 1e-6 of the trace:
    negative diagonal entries, products of inertia larger than the moments,
    a tensor filled with one placeholder value. A tensor of all zeros is
    reported when the link has mass and heads a moving body whose welded
    links have no inertia either (a point mass on a joint). Massless links
    with an all-zero tensor are left to `zero-mass`.

    ## Why it matters
    Every real body has three positive principal moments. MuJoCo refuses the
    model ("inertia must have positive eigenvalues", or "mass and inertia of
    moving bodies must be larger than mjMINVAL"); other engines divide by the
    missing moment and the link spins up without bound.

    ## Example
    ```xml
    <mass value="1e-6"/>
    <inertia ixx="1e-6" ixy="1e-6" ixz="1e-6" iyy="1e-6" iyz="1e-6" izz="1e-6"/>
    ```

    ## Fix
    Use the link's real tensor (from CAD), or a diagonal one with positive
    moments from its shape; the finding's `help` gives the tensor of the
    link's geometry at its mass when there is one.
    """

    code = "I004"
    name = "inertia-not-positive-definite"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for link in ctx.robot.links:
            inertial = link.inertial
            if inertial is None:
                continue
            tensor = inertial.inertia_matrix
            location = inertial.inertia_span or inertial.span or link.span
            if is_zero_tensor(tensor):
                finding = self._point_mass(ctx, link)
                if finding is not None:
                    yield finding
                continue
            verdict = assess(tensor, abs_tol=MIN_MOMENT)
            if verdict.positive_definite:
                continue
            a, b, c = verdict.moments
            yield self.diagnostic(
                f"link '{link.name}': inertia is not positive definite, principal moments "
                f"{fmt(a)}, {fmt(b)}, {fmt(c)} kg·m² (all three must be positive)",
                location,
                element=_where(link, "inertial", "inertia"),
                help=valid_tensor_help(link),
                data={"moments": [a, b, c], **tensor_data(tensor)},
            )

    def _point_mass(self, ctx: CheckContext, link: Link) -> Diagnostic | None:
        """A link with mass and an all-zero tensor, when something must rotate it.

        An error when its moving body has no rotational inertia at all (what
        MuJoCo refuses); a warning when the link's own joint moves but links
        welded to it give the body inertia, or when it is the robot's base.
        Point masses welded to a body with inertia (a tool frame, a force
        sensor) are fine: the body carries them.
        """
        inertial = link.inertial
        body = body_of_link(ctx, link.name)
        if inertial is None or inertial.mass <= MIN_VALUE or body is None:
            return None
        heads = body.head == link.name
        head = body.links[0][0]
        head_has_mass = head.inertial is not None and head.inertial.mass > MIN_VALUE
        if body.moves and float(np.linalg.eigvalsh(body.composite_inertia())[0]) <= MIN_VALUE:
            if not heads and head_has_mass:
                return None  # reported once, at the head of the body
            why, severity = f"it moves with joint '{body.joint}'", Severity.ERROR
        elif body.moves and heads:
            why = (
                f"it moves with joint '{body.joint}' (only the links welded to it give it inertia)"
            )
            severity = Severity.WARNING
        elif heads and ctx.tree.child_joints.get(link.name):
            why, severity = (
                "it is the robot's base (a floating base cannot turn without inertia)",
                Severity.WARNING,
            )
        else:
            return None
        return self.diagnostic(
            f"link '{link.name}' has {fmt(inertial.mass)} kg but zero inertia, and {why}",
            inertial.inertia_span or inertial.span or link.span,
            element=_where(link, "inertial", "inertia"),
            severity=severity,
            help=valid_tensor_help(link),
            data={
                "mass": inertial.mass,
                "joint": body.joint,
                **tensor_data(inertial.inertia_matrix),
            },
        )


@register
class InertiaTriangleInequality(_Inertia):
    """The principal moments break the triangle inequality A + B ≥ C.

    ## What it does
    Reports a positive definite tensor whose two smaller principal moments add
    up to less than the largest (beyond 1e-6 of the trace, to absorb
    rounding).

    ## Why it matters
    For any real mass distribution the moments obey A + B ≥ C (equality only
    for a flat plate). A tensor that breaks it belongs to no body: MuJoCo
    refuses the model ("inertia must satisfy A + B >= C"), and engines that
    accept it produce motion no real part can have. The usual cause is a
    moment copied to the wrong axis or mistyped by a factor of ten.

    ## Example
    ```xml
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.3"/>
    ```

    ## Fix
    Correct the tensor from CAD or the shape's formula; the finding's `help`
    gives the tensor of the link's geometry at its mass when there is one,
    and otherwise the smallest change of the two smaller moments that makes
    the tensor valid.
    """

    code = "I005"
    name = "inertia-triangle-inequality"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for link in ctx.robot.links:
            inertial = link.inertial
            if inertial is None or is_zero_tensor(inertial.inertia_matrix):
                continue
            verdict = assess(inertial.inertia_matrix, abs_tol=MIN_MOMENT)
            if not verdict.positive_definite or verdict.triangle_violation is None:
                continue
            a, b, c = verdict.triangle_violation
            scale = c / (a + b)
            yield self.diagnostic(
                f"link '{link.name}': principal moments {fmt(a)}, {fmt(b)}, {fmt(c)} kg·m² break "
                f"A + B ≥ C ({fmt(a)} + {fmt(b)} < {fmt(c)})",
                inertial.inertia_span or inertial.span or link.span,
                element=_where(link, "inertial", "inertia"),
                help=valid_tensor_help(link)
                or f"no body has these moments; scaling the two smaller ones by {fmt(scale)} "
                f"({fmt(a * scale)}, {fmt(b * scale)}) would make A + B = C",
                data={"moments": [a, b, c], **tensor_data(inertial.inertia_matrix)},
            )


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
    the declared tensor is 3× larger or smaller (ratio of traces) than the
    geometry's, and when the principal moments agree but sit on the wrong
    axes (a wheel whose spin moment is on an axis it does not spin about).

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
        for link in ctx.robot.links:
            inertial = link.inertial
            if (
                inertial is None
                or inertial.mass <= MIN_VALUE
                or not assess(inertial.inertia_matrix).valid
            ):
                continue
            comparison = compare_with_geometry(link)
            if comparison is None:
                continue
            if comparison.factor >= INERTIA_FACTOR:
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


def _wrong_axes(link: Link, comparison: InertiaComparison) -> float | None:
    """The off-axis factor when the principal moments match the geometry's but their axes do not."""
    assert link.inertial is not None
    if comparison.worst > SAME_MOMENTS:
        return None
    declared = link.inertial.inertia_matrix
    _, axes = np.linalg.eigh(comparison.computed)
    along = [float(axes[:, k] @ declared @ axes[:, k]) for k in range(3)]
    computed = [float(axes[:, k] @ comparison.computed @ axes[:, k]) for k in range(3)]
    factor = max(max(d / c, c / d) for d, c in zip(along, computed, strict=True))
    return factor if factor >= AXIS_FACTOR else None


@register
class ImplausibleDensity(_Inertia):
    """The link's mass and geometric volume give a density no solid part has.

    ## What it does
    Divides the declared mass by the volume of the link's collision geometry
    and of its visual geometry, and reports when every one is below
    10 kg/m³ (lighter than structural foam) or above 22,600 kg/m³ (denser
    than osmium, the densest element).

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
            if link.inertial is None or link.inertial.mass <= MIN_VALUE:
                continue
            found: list[tuple[float, str, SolidProperties]] = []
            for source, solid in geometry_sources(link):
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
            for source, solid in geometry_sources(link):
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
            yield self.diagnostic(
                f"joint '{joint.name}' carries {fmt(body.mass)} kg ('{body.head}'), {fmt(factor)}× "
                f"{lighter} than the {fmt(parent.mass)} kg it hangs from ('{parent.head}')",
                joint.span,
                element=f"joint[{joint.name}]",
                help="check the masses of "
                + (f"'{body.head}'" if ratio < 1 else f"'{parent.head}'"),
                data={"child_mass": body.mass, "parent_mass": parent.mass, "ratio": ratio},
            )
