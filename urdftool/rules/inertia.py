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
from urdftool.facts import link_mass
from urdftool.facts.context import CheckContext
from urdftool.model import Link
from urdftool.physics import vec3
from urdftool.physics.bodies import (
    MIN_VALUE,
    MassRole,
    RigidBody,
    body_of,
    kinematics_only,
    mass_role,
    rigid_bodies,
)
from urdftool.physics.describe import (
    fmt,
    is_zero_inertia,
    suggested_mass,
    tensor_data,
    valid_tensor_help,
)
from urdftool.physics.inertia import MIN_MOMENT


class _Inertia(Rule):
    family = Family.INERTIA


def _where(link: Link, *parts: str) -> str:
    return "/".join((f"link[{link.name}]", *parts))


def bodies(ctx: CheckContext) -> list[RigidBody]:
    """The robot's rigid bodies, computed once per check run."""
    if "inertia.bodies" not in ctx.cache:
        found = rigid_bodies(ctx.tree, vec3.compose)  # in floats: see physics/vec3.py
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
    body are not reported. In an SDF model it is always a warning: SDFormat's
    default `<inertial>` is 1 kg with a unit inertia, which every SDF reader
    uses, so the link is not massless, only not weighed by its author.

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
        if kinematics_only(ctx.robot):
            return  # one kinematics-only finding says it for the whole robot
        for link in ctx.robot.links:
            if link.inertial is not None:
                continue
            role = _role(ctx, link)
            if role is None:
                continue
            if ctx.robot.format == "sdf":
                # SDFormat's default <inertial> is 1 kg with a unit inertia, and libsdformat,
                # gz-sim and Gazebo classic all use it: the link has mass, just not its own.
                consequence = "SDF readers give it 1 kg and 1 kg·m² about each axis"
                severity = Severity.WARNING
            else:
                consequence = "URDF reads 0 kg; PyBullet assumes 1 kg, MuJoCo computes one from the geometry"
                severity = _SEVERITY[role.severity]
            yield self.diagnostic(
                f"link '{link.name}' {role.why} but has no <inertial> ({consequence})",
                link.span,
                element=_where(link),
                severity=severity,
                help=suggested_mass(link, link_mass.geometry_sources(ctx, link))
                or "add <inertial> with the link's mass and inertia",
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
            if inertial is None or not 0 <= inertial.mass < MIN_VALUE:
                continue
            role = _role(ctx, link)
            if role is None:
                continue
            what = (
                "zero mass and zero inertia"
                if is_zero_inertia(inertial)
                else "zero mass"
            )
            yield self.diagnostic(
                f"link '{link.name}' has {what} but {role.why}",
                inertial.mass_span or inertial.span or link.span,
                element=_where(link, "inertial", "mass"),
                severity=_SEVERITY[role.severity],
                help=suggested_mass(link, link_mass.geometry_sources(ctx, link))
                or "set the link's real mass and inertia",
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
    reports a tensor whose smallest moment is at or below 1e-9 of the trace
    (numerically zero; a 1 m rod of 1 mm diameter has 1.5e-6, and is fine):
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
            if is_zero_inertia(inertial):
                finding = self._point_mass(ctx, link)
                if finding is not None:
                    yield finding
                continue
            if link_mass.declared_valid(ctx, inertial, abs_tol=MIN_MOMENT):
                continue
            verdict = link_mass.declared_verdict(ctx, inertial, abs_tol=MIN_MOMENT)
            if verdict.positive_definite:
                continue
            a, b, c = verdict.moments
            yield self.diagnostic(
                f"link '{link.name}': inertia is not positive definite, principal moments "
                f"{fmt(a)}, {fmt(b)}, {fmt(c)} kg·m² (all three must be positive)",
                inertial.inertia_span or inertial.span or link.span,
                element=_where(link, "inertial", "inertia"),
                help=valid_tensor_help(link, link_mass.geometry_sources(ctx, link)),
                data={"moments": [a, b, c], **tensor_data(inertial.inertia_matrix)},
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
        if body.moves and float(np.linalg.eigvalsh(body.declared_inertia)[0]) <= MIN_VALUE:
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
            help=valid_tensor_help(link, link_mass.geometry_sources(ctx, link)),
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
            if (
                inertial is None
                or is_zero_inertia(inertial)
                or link_mass.declared_valid(ctx, inertial, abs_tol=MIN_MOMENT)
            ):
                continue
            verdict = link_mass.declared_verdict(ctx, inertial, abs_tol=MIN_MOMENT)
            if not verdict.positive_definite or verdict.triangle_violation is None:
                continue
            a, b, c = verdict.triangle_violation
            scale = c / (a + b)
            yield self.diagnostic(
                f"link '{link.name}': principal moments {fmt(a)}, {fmt(b)}, {fmt(c)} kg·m² break "
                f"A + B ≥ C ({fmt(a)} + {fmt(b)} < {fmt(c)})",
                inertial.inertia_span or inertial.span or link.span,
                element=_where(link, "inertial", "inertia"),
                help=valid_tensor_help(link, link_mass.geometry_sources(ctx, link))
                or f"no body has these moments; scaling the two smaller ones by {fmt(scale)} "
                f"({fmt(a * scale)}, {fmt(b * scale)}) would make A + B = C",
                data={"moments": [a, b, c], **tensor_data(inertial.inertia_matrix)},
            )


@register
class KinematicsOnly(_Inertia):
    """No link has an `<inertial>`: a kinematic model, which cannot be simulated as it is.

    ## What it does
    Recognises a robot with moving joints and no `<inertial>` anywhere, and
    reports it once, at the robot, instead of a `missing-inertial` error per
    link. The dynamics pass is skipped for it (there is nothing to compute),
    and `convert` to MJCF or PyBullet and `sim` refuse it with this one reason
    unless `--repair-inertia` gives every moving link a minimal mass.

    ## Why it matters
    MoveIt, RViz and IK solvers need only the kinematics, and many
    description packages (ROS-Industrial support packages, MoveIt test
    robots) are written that way on purpose; urdfdom, yourdfpy and Pinocchio
    accept them. A simulator cannot: Gazebo drops massless links, PyBullet
    gives each 1 kg, MuJoCo refuses them.

    ## Example
    ```xml
    <link name="link_1"><visual>…</visual><collision>…</collision></link>
    <joint name="joint_1" type="revolute">…</joint>   <!-- and no <inertial> in any link -->
    ```

    ## Fix
    Nothing, for a kinematic model. To simulate it, add each link's mass and
    inertia (from CAD, or the formulas of its collision shapes), or convert
    with `--repair-inertia` for a rough stand-in. Silence it with
    `--ignore kinematics-only`.
    """

    code = "I011"
    name = "kinematics-only"
    severity = Severity.INFO

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        if not kinematics_only(ctx.robot):
            return
        moving = sum(1 for joint in ctx.robot.joints if joint.type.is_moving)
        yield self.diagnostic(
            f"robot '{ctx.robot.name}' has no <inertial> in any of its {len(ctx.robot.links)} links: a "
            f"kinematic model ({moving} moving joints); MoveIt, RViz and IK solvers use it as it is, "
            "while simulation (convert to MJCF or PyBullet, sim, Gazebo) and the dynamics pass need "
            "mass and inertia",
            ctx.robot.span,
            element="robot",
            help="add <inertial> to every link to simulate it, or convert with --repair-inertia for a "
            "minimal stand-in",
            data={"links": len(ctx.robot.links), "moving_joints": moving},
        )
