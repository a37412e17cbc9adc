"""Units with evidence (N0xx): numbers only plausible in another unit.

URDF and SDF are SI: radians, metres, kilograms (REP 103). Each rule here
fires only when the number is implausible in SI *and* plausible in the unit an
author slipped into, and says both readings. Thresholds are in
:mod:`urdftool.rules.intent_common` and docs/intent.md.
"""

from __future__ import annotations

import bisect
import math
import statistics
from collections.abc import Iterator

from urdftool.catalogue.registry import register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts import link_mass
from urdftool.facts.context import CheckContext
from urdftool.model import Joint, JointType
from urdftool.physics.describe import fmt
from urdftool.physics.linkmass import density
from urdftool.rules.intent_common import (
    IntentRule,
    option,
    robot_extent,
    shape_dims,
    where_joint,
    where_link,
    written,
)

#: The densest element (osmium) and the lightest structural solid (foam), kg/m³.
DENSITY_PLAUSIBLE = (100.0, 22_600.0)
#: Degrees beyond this are not a limit anyone writes (ten turns).
DEGREES_MAX = 3600.0


@register
class LimitsLookLikeDegrees(IntentRule):
    """A revolute joint's limits are only plausible as degrees.

    ## What it does
    Reports a `revolute` joint (and either axis of a `universal` or
    `revolute2` joint) whose `lower` or `upper` lies beyond one turn (2π ≈
    6.28 rad; option `degree_turns`) while every non-zero limit is a whole or
    half number (option `degree_step`, 0.5) of at most 3600: `-90`/`90`,
    `0`/`180`, Franka's `-166`/`166` and `-1`/`215`. The placeholders authors
    write for "unlimited" stay quiet: symmetric powers of ten (`±10` as in
    solo and bolt, `±100`, `±1000`) and anything beyond 3600 (`±1e16`,
    `±3.4e38`). So do radian values written to a few decimals (ANYmal's
    `±9.42`), and `continuous` joints. The message gives the radian reading
    (`90 → 1.5708 rad`).

    ## Why it matters
    URDF and SDF angles are radians (REP 103; urdfdom, MoveIt, Gazebo and the
    SDFormat specification read `lower`/`upper` in rad). A limit of 166 rad is
    more than 26 turns: the joint is effectively unlimited, so planners send it
    through the robot and simulators never stop it (a degree/radian slip:
    kth-ros-pkg/yumi#10). Multi-turn joints exist, but their limits are not
    whole degree numbers.

    ## Example
    ```xml
    <joint name="elbow" type="revolute">
      <limit lower="-166" upper="166" effort="87" velocity="2.175"/>
    </joint>
    ```

    ## Fix
    Write radians (`lower="-2.8973" upper="2.8973"`, or `${radians(166)}` in
    xacro). If the joint really turns many times, write the radian values
    or make it `continuous`. Silence one joint with
    `<!-- urdftool: ignore[limits-look-like-degrees] -->`.
    """

    code = "N001"
    name = "limits-look-like-degrees"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        turns = option(ctx, "degree_turns")
        step = option(ctx, "degree_step")
        for joint in ctx.robot.joints:
            if joint.type not in _ROTARY:
                continue
            for limit, axis in ((joint.limit, ""), (joint.limit2, "axis2 ")):
                if limit is None or not _degree_limits(limit.lower, limit.upper, turns, step):
                    continue
                values = [v for v in (limit.lower, limit.upper) if v is not None]
                widest = max(abs(v) for v in values)
                readings = ", ".join(f"{written(v)} → {math.radians(v):.4f} rad" for v in values)
                yield self.diagnostic(
                    f"joint '{joint.name}': {axis}limits {_range(limit.lower, limit.upper)} look like "
                    f"degrees: {readings}",
                    limit.span or joint.span,
                    element=where_joint(joint, "limit2" if axis else "limit"),
                    help=f"as radians this joint turns over {fmt(widest / (2 * math.pi))} "
                    "turns; write radians (xacro: ${radians(…)})",
                    data={
                        "lower": limit.lower,
                        "upper": limit.upper,
                        "lower_rad": None if limit.lower is None else math.radians(limit.lower),
                        "upper_rad": None if limit.upper is None else math.radians(limit.upper),
                    },
                )


#: Joints whose limits are angles (rad).
_ROTARY = frozenset({JointType.REVOLUTE, JointType.UNIVERSAL, JointType.REVOLUTE2})
#: Symmetric limits authors write for "unlimited" (solo and bolt write ±10): never read as degrees.
_PLACEHOLDERS = frozenset({10.0, 100.0, 1000.0})


def _degree_limits(lower: float | None, upper: float | None, turns: float, step: float) -> bool:
    """*lower* and *upper* (rad as written) read as degrees: one of them beyond *turns* turns, every
    non-zero one a multiple of *step* of at most :data:`DEGREES_MAX`, and not a placeholder."""
    nonzero = [v for v in (lower, upper) if v is not None and v != 0]
    if not nonzero or max(abs(v) for v in nonzero) <= 2 * math.pi * turns:
        return False
    if not all(abs(v) <= DEGREES_MAX and _multiple(v, step) for v in nonzero):
        return False
    return not (lower is not None and upper is not None and lower == -upper and upper in _PLACEHOLDERS)


def _multiple(value: float, step: float) -> bool:
    return step > 0 and abs(value / step - round(value / step)) < 1e-9


def _range(lower: float | None, upper: float | None) -> str:
    return f"{written(lower or 0.0)} .. {written(upper or 0.0)}"


def _slip(value: float, reference: float, fit: float = 2.0) -> tuple[str, float] | None:
    """The unit (``cm`` or ``mm``) that brings *value* (m) within *fit* times *reference* (m)."""
    for unit, factor in (("cm", 100.0), ("mm", 1000.0)):
        if value / factor <= fit * reference:
            return unit, factor
    return None


@register
class TravelLooksLikeMillimetres(IntentRule):
    """A prismatic joint's travel is only plausible in millimetres or centimetres.

    ## What it does
    Compares a `prismatic` joint's travel (`upper - lower`) with the robot's
    own extent at home (the box around every link frame and primitive
    shape). It reports a travel longer than 2 m (option `length_min`) and
    more than 20 times the extent (option `length_factor`) when, read as
    centimetres or millimetres, it fits within twice the extent, unless the
    joint's parent link carries a primitive shape at least 90 % as
    long as the travel (a rail drawn to scale), or the joint moves a bare
    frame (a child link with no geometry and no mass: one axis of a virtual
    floating base spelled out joint by joint, such as Cassie's
    `map → x → y → z` chain with ±1000 m of travel).

    ## Why it matters
    URDF lengths are metres (REP 103). A gripper whose fingers travel 40 m
    explodes in a simulator and makes a planner's sampling useless.

    ## Example
    ```xml
    <joint name="finger" type="prismatic">
      <limit lower="0" upper="40" effort="20" velocity="0.1"/>
    </joint>
    ```

    ## Fix
    Write metres (`upper="0.04"`). Silence with
    `<!-- urdftool: ignore[travel-looks-like-millimetres] -->` on a real long rail.
    """

    code = "N002"
    name = "travel-looks-like-millimetres"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        factor, minimum = option(ctx, "length_factor"), option(ctx, "length_min")
        for joint in ctx.robot.joints:
            limit = joint.limit
            if joint.type is not JointType.PRISMATIC or limit is None:
                continue
            travel = abs((limit.upper or 0.0) - (limit.lower or 0.0))
            extent = robot_extent(ctx)
            if not math.isfinite(travel) or extent < 0.01 or travel <= max(minimum, factor * extent):
                continue
            slip = _slip(travel, extent)
            if slip is None or _rides_a_rail(ctx, joint, travel) or _moves_a_bare_frame(ctx, joint):
                continue
            unit, scale = slip
            yield self.diagnostic(
                f"joint '{joint.name}': a travel of {fmt(travel)} m on a robot {fmt(extent)} m across "
                f"looks like {_unit_name(unit)}: {written(travel)} → {written(travel / scale)} m",
                limit.span or joint.span,
                element=where_joint(joint, "limit"),
                help=f'write metres: lower="{fmt((limit.lower or 0) / scale)}" '
                f'upper="{fmt((limit.upper or 0) / scale)}"',
                data={"travel": travel, "extent": extent, "unit": unit, "meant": travel / scale},
            )


def _rides_a_rail(ctx: CheckContext, joint: Joint, travel: float) -> bool:
    """The joint's parent link carries a primitive shape about as long as the travel (m): a real
    rail, such as gz_ros2_control's cart on a 30 m slide bar, not a slip of units."""
    parent = ctx.robot.link(joint.parent)
    if parent is None:
        return False
    shapes = [c.geometry for c in parent.collisions] + [v.geometry for v in parent.visuals]
    lengths = [max(dims) for shape in shapes if (dims := shape_dims(shape)) is not None]
    return any(length >= 0.9 * travel for length in lengths)


def _moves_a_bare_frame(ctx: CheckContext, joint: Joint) -> bool:
    """The joint's child has no visual, no collision and no mass: a virtual axis of a floating
    base (its huge travel stands for "unbounded"), not a part whose length was written in the
    wrong unit, which would be drawn or weighed."""
    child = ctx.robot.link(joint.child)
    if child is None or child.visuals or child.collisions:
        return False
    return child.inertial is None or not child.inertial.mass > 0.0


def _unit_name(unit: str) -> str:
    return {"mm": "millimetres", "cm": "centimetres"}[unit]


@register
class LengthLooksLikeMillimetres(IntentRule):
    """A joint offset or a shape's size is only plausible in millimetres or centimetres.

    ## What it does
    Takes the median length of the robot's joint offsets as its scale.
    Reports a joint `<origin>` offset or a primitive shape (box, cylinder,
    sphere…) longer than 2 m (option `length_min`) and more than 20 times
    that median (option `length_factor`) when, read as centimetres or
    millimetres, it fits within five times the median. At least three other
    offsets are needed to have a scale.

    ## Why it matters
    URDF lengths are metres (REP 103). One offset copied from a CAD drawing
    in millimetres puts a link metres away from its parent: the robot flies
    apart in the viewer and every transform below it is wrong.

    ## Example
    ```xml
    <origin xyz="0 0 333" rpy="0 0 0"/>  <!-- 333 mm -->
    ```

    ## Fix
    Write metres (`xyz="0 0 0.333"`). Silence with
    `<!-- urdftool: ignore[length-looks-like-millimetres] -->`.
    """

    code = "N003"
    name = "length-looks-like-millimetres"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        factor, minimum = option(ctx, "length_factor"), option(ctx, "length_min")
        offsets = {j.name: math.hypot(*j.origin.xyz) for j in ctx.robot.joints}
        finite = [d for d in offsets.values() if math.isfinite(d) and d > 1e-6]
        if len(finite) < 4:
            return
        ordered = sorted(finite)
        for joint in ctx.robot.joints:
            length = offsets[joint.name]
            if not length > minimum:  # what _judge() says first, without the median
                continue
            # the median of the other joints' offsets, without sorting again per joint (chains
            # of thousands of joints)
            counted = math.isfinite(length) and length > 1e-6
            scale = _median_without(ordered, length) if counted else statistics.median(ordered)
            found = _judge(length, scale, factor, minimum)
            if found is not None:
                yield self._report(joint.name, "origin offset", length, scale, found, joint, None)
        scale = statistics.median(finite)
        for link in ctx.robot.links:
            for kind, elements in (("collision", link.collisions), ("visual", link.visuals)):
                for element in elements:
                    dims = shape_dims(element.geometry)
                    if dims is None or not max(dims) > minimum:  # _judge()'s first test
                        continue
                    found = _judge(max(dims), scale, factor, minimum)
                    if found is not None:
                        label = f"{getattr(element.geometry, 'kind', 'shape')} of link '{link.name}'"
                        span = getattr(element.geometry, "span", None) or element.span or link.span
                        yield self.diagnostic(
                            f"{kind} {label}: {fmt(max(dims))} m across on a robot whose joints are "
                            f"{fmt(scale)} m apart looks like {_unit_name(found[0])}: "
                            f"{written(max(dims))} → {written(max(dims) / found[1])} m",
                            span,
                            element=where_link(link, kind, "geometry"),
                            help="write metres",
                            data={
                                "length": max(dims),
                                "scale": scale,
                                "unit": found[0],
                                "meant": max(dims) / found[1],
                            },
                        )

    def _report(
        self,
        name: str,
        what: str,
        length: float,
        scale: float,
        found: tuple[str, float],
        joint: Joint,
        _: None,
    ) -> Diagnostic:
        unit, div = found
        return self.diagnostic(
            f"joint '{name}': an {what} of {fmt(length)} m on a robot whose joints are "
            f"{fmt(scale)} m apart looks like {_unit_name(unit)}: "
            f"{written(length)} → {written(length / div)} m",
            joint.span,
            element=where_joint(joint, "origin"),
            help=f'write metres: xyz="{" ".join(fmt(v / div) for v in joint.origin.xyz)}"',
            data={"length": length, "scale": scale, "unit": unit, "meant": length / div},
        )


def _judge(length: float, scale: float, factor: float, minimum: float) -> tuple[str, float] | None:
    if not math.isfinite(length) or length <= max(minimum, factor * scale):
        return None
    return _slip(length, scale, 5.0)


@register
class MassLooksLikeGrams(IntentRule):
    """A link's mass is only plausible as grams for the link's volume.

    ## What it does
    Divides the mass by the volume of the link's collision geometry and of
    its visual geometry (as `implausible-density` does). When every reading
    is above 100,000 kg/m³ (option `grams_density`, over four times osmium),
    the mass is at least 10 (option `grams_min_mass`: a placeholder `1` is
    not grams) and the mass read as grams gives a density between 100 and
    22,600 kg/m³, it reports the mass with its gram reading
    (`1200 → 1.2 kg`).

    ## Why it matters
    URDF masses are kilograms (REP 103). A 1200 kg forearm pulls the robot
    over in simulation, saturates every torque check, and makes a
    controller's gravity compensation fight a phantom load.

    ## Example
    ```xml
    <link name="forearm">
      <inertial><mass value="1200"/>…</inertial>
      <collision><geometry><cylinder radius="0.04" length="0.3"/></geometry></collision>
    </link>
    ```

    ## Fix
    Write kilograms (`value="1.2"`) and scale the inertia by the same 1/1000.
    Silence with `<!-- urdftool: ignore[mass-looks-like-grams] -->`.
    """

    code = "N004"
    name = "mass-looks-like-grams"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        threshold, minimum = option(ctx, "grams_density"), option(ctx, "grams_min_mass")
        low, high = DENSITY_PLAUSIBLE
        for link in ctx.robot.links:
            inertial = link.inertial
            if inertial is None or not inertial.mass >= minimum:
                continue
            readings = []
            for source, solid in link_mass.geometry_sources(ctx, link):
                value = density(link, solid)
                if value is not None:
                    readings.append((value, source, solid))
            if not readings or any(value <= threshold for value, _, _ in readings):
                continue
            value, source, solid = min(readings, key=lambda r: r[0])
            if not low <= value / 1000.0 <= high:
                continue
            yield self.diagnostic(
                f"link '{link.name}': {written(inertial.mass)} kg in its {fmt(solid.volume)} m³ {source} "
                f"geometry is {fmt(value)} kg/m³; it looks like grams: "
                f"{written(inertial.mass)} → {written(inertial.mass / 1000.0)} kg "
                f"({fmt(value / 1000.0)} kg/m³)",
                inertial.mass_span or inertial.span or link.span,
                element=where_link(link, "inertial", "mass"),
                help="write kilograms, and divide the inertia by 1000 as well",
                data={
                    "mass": inertial.mass,
                    "meant": inertial.mass / 1000.0,
                    "density": value,
                    "volume": solid.volume,
                    "source": source,
                },
            )


def _median_without(ordered: list[float], value: float) -> float:
    """The median of sorted *ordered* with one occurrence of *value* (which it holds) left out."""
    index = bisect.bisect_left(ordered, value)

    def at(k: int) -> float:
        return ordered[k] if k < index else ordered[k + 1]

    remaining = len(ordered) - 1
    if remaining % 2:
        return at(remaining // 2)
    return (at(remaining // 2 - 1) + at(remaining // 2)) / 2.0
