"""Joints (J): axes, limits and the home configuration (mimic chains: :mod:`urdftool.rules.joint_mimic`).

Limits follow urdfdom: revolute and prismatic joints need a ``<limit>``, and any
``<limit>`` needs ``effort`` and ``velocity``; ``lower`` and ``upper`` default
to 0 and are ignored on continuous joints. Decisions are in ``docs/joints.md``.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts.context import CheckContext
from urdftool.model import Joint, JointType, Limit, Robot
from urdftool.physics.describe import fmt

#: Joint types whose position is bounded by ``lower``/``upper``.
LIMITED = (JointType.REVOLUTE, JointType.PRISMATIC)
#: Joint types that move along or about ``axis``.
AXIAL = (JointType.REVOLUTE, JointType.CONTINUOUS, JointType.PRISMATIC, JointType.PLANAR)
#: An axis whose length differs from 1 by more than this is reported; three
#: written digits (``0.707 0.707 0``) stay quiet.
AXIS_TOLERANCE = 1e-3
#: Positions (rad or m) this close to a limit count as inside it.
LIMIT_TOLERANCE = 1e-9


class _Joints(Rule):
    family = Family.JOINTS


def _where(joint: Joint, *parts: str) -> str:
    return "/".join((f"joint[{joint.name}]", *parts))


def _unit(joint: Joint) -> str:
    return "m" if joint.type is JointType.PRISMATIC else "rad"


@register
class MissingJointLimit(_Joints):
    """A revolute or prismatic joint has no `<limit>`.

    ## What it does
    Reports `revolute` and `prismatic` joints without a `<limit>` element.
    URDF only: in SDF an unwritten limit means unlimited (a revolute joint
    without one is read as continuous).

    ## Why it matters
    urdfdom refuses the model ("joint is of type REVOLUTE but it does not
    specify limits"), so `robot_state_publisher`, MoveIt and Gazebo do not
    load it; tools that accept it invent limits of their own (0 to 0, or
    none at all).

    ## Example
    ```xml
    <joint name="elbow" type="revolute">
      <parent link="upper_arm"/><child link="forearm"/><axis xyz="0 1 0"/>
    </joint>
    ```

    ## Fix
    ```xml
    <limit lower="-2.6" upper="2.6" effort="40" velocity="3.1"/>
    ```
    or make the joint `continuous` if it turns without end.
    """

    code = "J001"
    name = "missing-joint-limit"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        if ctx.robot.format == "sdf":
            return  # SDFormat's defaults: lower -1e16, upper 1e16, i.e. unlimited
        for joint in ctx.robot.joints:
            if joint.type not in LIMITED or joint.limit is not None:
                continue
            unit = _unit(joint)
            yield self.diagnostic(
                f"{joint.type.value} joint '{joint.name}' has no <limit>",
                joint.span,
                element=_where(joint),
                help='add <limit lower="…" upper="…" effort="…" velocity="…"/> '
                f"(positions in {unit})"
                + (", or make it continuous" if joint.type is JointType.REVOLUTE else ""),
                data={"type": joint.type.value},
            )


@register
class LimitMissingEffortOrVelocity(_Joints):
    """A `<limit>` has no `effort` or no `velocity`.

    ## What it does
    Reports every `<limit>` element that leaves out `effort` or `velocity`,
    on any joint type.

    ## Why it matters
    Both are required: urdfdom refuses the model ("joint limit: no effort"),
    and ros_control and Gazebo read the missing value as 0, a joint that
    cannot be driven.

    ## Example
    ```xml
    <limit lower="-1.57" upper="1.57"/>
    ```

    ## Fix
    ```xml
    <limit lower="-1.57" upper="1.57" effort="20" velocity="2.0"/>
    ```
    """

    code = "J002"
    name = "limit-missing-effort-or-velocity"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        if ctx.robot.format == "sdf":
            return  # SDF: an unwritten effort or velocity means unlimited (the spec's -1)
        for joint in ctx.robot.joints:
            limit = joint.limit
            if limit is None:
                continue
            missing = [name for name in ("effort", "velocity") if getattr(limit, name) is None]
            if not missing:
                continue
            yield self.diagnostic(
                f"joint '{joint.name}': <limit> has no {' and no '.join(missing)}",
                limit.span or joint.span,
                element=_where(joint, "limit"),
                help="effort (N·m or N) and velocity (rad/s or m/s) are required; write the "
                "actuator's rated values",
                data={"missing": missing},
            )


def _bounds(ctx: CheckContext, limit: Limit) -> tuple[float, float] | None:
    """(lower, upper) as loaders read them: a bound a URDF leaves out is 0 (urdfdom); an SDF one
    is no bound (±1e16, kept as None by the reader), so there is no range to judge (None)."""
    if ctx.robot.format == "sdf" and (limit.lower is None or limit.upper is None):
        return None
    return (limit.lower or 0.0, limit.upper or 0.0)


@register
class ZeroEffortOrVelocity(_Joints):
    """A moving joint's `effort` or `velocity` limit is zero or negative.

    ## What it does
    Reports `effort` or `velocity` at or below zero on revolute, continuous
    and prismatic joints. A joint locked by equal limits (`lower == upper`,
    RotorS' and UUV Simulator's sensor mounts) is left to `inverted-limits`,
    which reports the lock: a joint that cannot move needs no actuator.

    ## Why it matters
    Gazebo, ros_control and MoveIt clamp commands to these limits: a zero
    effort joint cannot hold itself against gravity and a zero velocity joint
    never moves. It is usually a placeholder written before the actuator was
    chosen. (A deliberately passive joint is better modelled with damping and
    no actuator.)

    ## Example
    ```xml
    <limit lower="-1" upper="1" effort="0" velocity="0"/>
    ```

    ## Fix
    Write the actuator's rated torque (N·m) or force (N) and speed.
    """

    code = "J003"
    name = "zero-effort-or-velocity"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for joint in ctx.robot.joints:
            limit = joint.limit
            if limit is None or joint.type not in (*LIMITED, JointType.CONTINUOUS):
                continue
            bounds = _bounds(ctx, limit) if joint.type in LIMITED else None
            if bounds is not None and bounds[0] == bounds[1]:
                continue  # locked: InvertedLimits says so once, and no effort moves it anyway
            bad = {
                name: value
                for name in ("effort", "velocity")
                if (value := getattr(limit, name)) is not None and value <= 0
            }
            if not bad:
                continue
            text = ", ".join(f"{name} {fmt(value)}" for name, value in bad.items())
            yield self.diagnostic(
                f"joint '{joint.name}' has {text}: it cannot be driven",
                limit.span or joint.span,
                element=_where(joint, "limit"),
                help="write the actuator's rated effort and velocity (positive)",
                data=dict(bad),
            )


@register
class InvertedLimits(_Joints):
    """A joint's lower limit is above its upper limit (or equal to it).

    ## What it does
    Reports revolute and prismatic joints with `lower > upper` (error), and
    with `lower == upper` (warning: the joint cannot move). In SDF a bound
    left out (or ±1e16) is no bound, not 0.

    ## Why it matters
    An empty range has no valid position: planners reject every state,
    Gazebo and PyBullet clamp the joint against one limit or the other, and
    MuJoCo ignores the range. Equal limits lock the joint, which a `fixed`
    joint says more clearly.

    ## Example
    ```xml
    <limit lower="1.57" upper="-1.57" effort="10" velocity="1"/>
    ```

    ## Fix
    Swap the values, or check the sign convention of the axis:
    ```xml
    <limit lower="-1.57" upper="1.57" effort="10" velocity="1"/>
    ```
    """

    code = "J004"
    name = "inverted-limits"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for joint in ctx.robot.joints:
            limit = joint.limit
            bounds = _bounds(ctx, limit) if limit is not None and joint.type in LIMITED else None
            if limit is None or bounds is None:
                continue
            lower, upper = bounds
            if lower < upper:
                continue
            unit = _unit(joint)
            data = {"lower": lower, "upper": upper}
            if lower > upper:
                yield self.diagnostic(
                    f"joint '{joint.name}': lower limit {fmt(lower)} {unit} is above upper limit "
                    f"{fmt(upper)} {unit}",
                    limit.span or joint.span,
                    element=_where(joint, "limit"),
                    help=f'swap them: lower="{fmt(upper)}" upper="{fmt(lower)}"',
                    data=data,
                )
            else:
                yield self.diagnostic(
                    f"joint '{joint.name}': lower and upper limits are both {fmt(lower)} {unit}, "
                    "so the joint cannot move",
                    limit.span or joint.span,
                    element=_where(joint, "limit"),
                    help="make it a fixed joint (Gazebo keeps a fixed joint's child link "
                    "for its sensors and plugins with <preserveFixedJoint>true</preserveFixedJoint> "
                    "in a <gazebo reference> block naming the joint), or write its real range",
                    data=data,
                    severity=Severity.WARNING,
                )


@register
class ContinuousWithLimits(_Joints):
    """A continuous joint has `lower`/`upper` limits, which are ignored.

    ## What it does
    Reports `continuous` joints whose `<limit>` sets a non-zero `lower` or
    `upper`.

    ## Why it matters
    A continuous joint turns without end: urdfdom, Gazebo, MuJoCo and
    PyBullet ignore its position limits. Writing them usually means the
    joint was meant to be `revolute`, and the robot will turn past the
    intended range in simulation and on hardware driven from the model.

    ## Example
    ```xml
    <joint name="pan" type="continuous">
      <limit lower="-3.14" upper="3.14" effort="5" velocity="2"/>
    </joint>
    ```

    ## Fix
    Make it `revolute` to keep the range, or drop `lower`/`upper`:
    ```xml
    <limit effort="5" velocity="2"/>
    ```
    """

    code = "J005"
    name = "continuous-with-limits"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for joint in ctx.robot.joints:
            limit = joint.limit
            if joint.type is not JointType.CONTINUOUS or limit is None:
                continue
            written = {k: v for k, v in (("lower", limit.lower), ("upper", limit.upper)) if v}
            if not written:
                continue
            text = " ".join(f"{k}={fmt(v)}" for k, v in written.items())
            yield self.diagnostic(
                f"continuous joint '{joint.name}' has position limits ({text} rad) that every "
                "loader ignores",
                limit.span or joint.span,
                element=_where(joint, "limit"),
                help="make the joint revolute to keep the range, or remove lower and upper",
                data=written,
            )


@register
class ZeroAxis(_Joints):
    """A moving joint's axis is the zero vector.

    ## What it does
    Reports `<axis xyz="0 0 0">` on revolute, continuous, prismatic and
    planar joints.

    ## Why it matters
    A zero axis gives no direction to turn about or slide along: urdfdom and
    KDL normalise it to NaN, MuJoCo refuses it, PyBullet silently makes the
    joint immobile.

    ## Example
    ```xml
    <axis xyz="0 0 0"/>
    ```

    ## Fix
    Write the direction in the joint frame, e.g. `<axis xyz="0 0 1"/>`.
    """

    code = "J006"
    name = "zero-axis"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for joint in ctx.robot.joints:
            if joint.type not in AXIAL or any(joint.axis):
                continue
            yield self.diagnostic(
                f"{joint.type.value} joint '{joint.name}' has a zero axis",
                joint.axis_span or joint.span,
                element=_where(joint, "axis"),
                help='write the unit direction in the joint frame, e.g. xyz="0 0 1"',
                data={"axis": list(joint.axis)},
            )


@register
class NonUnitAxis(_Joints):
    """A joint axis is not a unit vector.

    ## What it does
    Reports a non-zero `<axis xyz>` whose length differs from 1 by more than
    0.1%, and gives the normalised axis that loaders use instead.

    ## Why it matters
    urdfdom, KDL, MuJoCo and Gazebo normalise the axis, but tools that use it
    as written scale prismatic motion and joint velocities by its length, so
    the robot differs between tools. It often betrays a typo (`0 1 1` for
    `0 1 0`).

    ## Example
    ```xml
    <axis xyz="0 0 2"/>
    ```

    ## Fix
    ```xml
    <axis xyz="0 0 1"/>
    ```
    """

    code = "J007"
    name = "non-unit-axis"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for joint in ctx.robot.joints:
            if joint.type not in AXIAL:
                continue
            length = math.sqrt(sum(c * c for c in joint.axis))
            if length == 0 or abs(length - 1.0) <= AXIS_TOLERANCE:
                continue
            unit = [c / length for c in joint.axis]
            written = " ".join(_axis_number(c) for c in unit)
            yield self.diagnostic(
                f"joint '{joint.name}': axis ({' '.join(fmt(c) for c in joint.axis)}) has length "
                f"{fmt(length)}; it is used as ({written})",
                joint.axis_span or joint.span,
                element=_where(joint, "axis"),
                help=f'write <axis xyz="{written}"/>',
                data={"axis": list(joint.axis), "length": length, "normalized": unit},
            )


def _axis_number(value: float) -> str:
    text = f"{value:.7g}"
    return "0" if text in ("0", "-0") else text


@register
class HomeOutsideLimits(_Joints):
    """The robot's home configuration puts a joint outside its limits.

    ## What it does
    Takes the home configuration (the model's named home pose when it has
    one, otherwise every joint at 0; mimic joints at `multiplier · q + offset`)
    and reports revolute and prismatic joints whose position there lies
    outside `[lower, upper]`.

    ## Why it matters
    Simulators spawn the robot in that configuration: MuJoCo and PyBullet
    start with a violated limit and kick the joint back with a large
    constraint force at the first step, Gazebo snaps it, and a controller
    started from the model's zero pose commands an unreachable position.

    ## Example
    ```xml
    <joint name="knee" type="revolute">…
      <limit lower="0.1" upper="2.6" effort="40" velocity="5"/>
    </joint>
    ```

    ## Fix
    Shift the joint's zero (its `<origin>`) so that 0 is a reachable
    position, widen the range if 0 is physically reachable, or give the
    robot a named home pose inside the limits (e.g. an SRDF group state).
    """

    code = "J010"
    name = "home-outside-limits"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        named = ctx.robot.home is not None
        for joint in ctx.robot.joints:
            limit = joint.limit
            bounds = _bounds(ctx, limit) if limit is not None and joint.type in LIMITED else None
            if limit is None or bounds is None or bounds[0] > bounds[1]:
                continue  # no range (SDF), or inverted-limits reports it
            lower, upper = bounds
            position = home_position(ctx.robot, joint)
            if lower - LIMIT_TOLERANCE <= position <= upper + LIMIT_TOLERANCE:
                continue
            unit = _unit(joint)
            nearest = lower if position < lower else upper
            pose = "the home pose" if named else "the zero configuration"
            yield self.diagnostic(
                f"{pose} puts joint '{joint.name}' at {fmt(position)} {unit}, outside its limits "
                f"[{fmt(lower)}, {fmt(upper)}] {unit}",
                limit.span or joint.span,
                element=_where(joint, "limit"),
                help=f"the nearest position within the limits is {fmt(nearest)} {unit}; shift the "
                "joint's zero or give the robot a home pose inside the limits",
                data={"position": position, "lower": lower, "upper": upper, "nearest": nearest,
                      "named_home": named},
            )


def home_position(robot: Robot, joint: Joint) -> float:
    """The joint's position (rad or m) in the robot's home configuration (0 where unnamed).

    Mimic joints follow their targets; chains are followed without recursion
    and a cycle counts as 0 (``mimic-cycle`` reports it).
    """
    home = robot.home or {}
    scale, shift = 1.0, 0.0
    seen: set[str] = set()
    current: Joint | None = joint
    while current is not None and current.mimic is not None and current.name not in seen:
        seen.add(current.name)
        scale, shift = scale * current.mimic.multiplier, shift + scale * current.mimic.offset
        current = robot.joint(current.mimic.joint)
    if current is None or current.name in seen:
        return shift
    return scale * float(home.get(current.name, 0.0)) + shift
