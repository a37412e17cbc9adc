"""Self-consistency (N3xx): a model that contradicts itself.

Two descriptions of one thing in one file must agree: the visual and the
collision shape of a link, the inertia of a wheel and the axis it turns
about, the range a mimic joint is driven over and its own limits.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
else:
    from urdftool.lazy import numpy as np

from urdftool.catalogue.registry import register
from urdftool.diagnostics import Diagnostic, Related, Severity
from urdftool.facts.context import CheckContext
from urdftool.model import JointType, Link
from urdftool.model.geometry import Geometry, Mesh
from urdftool.physics.describe import fmt
from urdftool.physics.inertia import principal_moments
from urdftool.rules.intent_common import (
    IntentRule,
    angle_between,
    option,
    shape_dims,
    where_joint,
    where_link,
)

_SPINNING = re.compile(r"wheel|tire|tyre", re.IGNORECASE)
#: The unique principal axis of a wheel's inertia may be this far from its joint axis.
SPIN_AXIS_TOLERANCE_DEG = 10.0
#: ... and is unique when the third moment differs from the other two by this much.
DISTINCT_MOMENT = 0.10


def _slip_factor(a: tuple[float, ...], b: tuple[float, ...], tol: float) -> int | None:
    """The power of ten (±1..3) by which every size of *b* differs from *a*, or ``None``."""
    if len(a) != len(b) or any(x <= 0 or y <= 0 for x, y in zip(a, b, strict=False)):
        return None
    ratios = [y / x for x, y in zip(sorted(a), sorted(b), strict=False)]
    for k in (1, 2, 3, -1, -2, -3):
        if all(abs(r / 10.0**k - 1.0) <= tol for r in ratios):
            return k
    return None


def _sizes(geometry: Geometry | None) -> tuple[str, tuple[float, ...]] | None:
    if isinstance(geometry, Mesh):  # most shapes: the scale's three numbers written out
        x, y, z = geometry.scale
        return geometry.filename, (abs(float(x)), abs(float(y)), abs(float(z)))
    dims = shape_dims(geometry)
    if dims is None or geometry is None:
        return None
    return geometry.kind, dims


@register
class CollisionVisualScaleSlip(IntentRule):
    """A link's collision geometry is its visual geometry scaled by 10, 100 or 1000.

    ## What it does
    Compares each collision element of a link with the visual elements of
    the same link: the same primitive kind whose every size differs by one
    factor within 15 % (option `scale_slip_tolerance`) of 10, 100 or 1000
    (either way), or the same mesh file with such a `scale` ratio. It stays
    quiet when another visual matches that collision at its own size.

    ## Why it matters
    Visual and collision geometry describe one part. A factor of exactly a
    power of ten is a unit slip (millimetres against metres, a `scale`
    copied from another export), not a simplification: the robot looks
    right in RViz and collides with the air, or not at all, in simulation.

    ## Example
    ```xml
    <visual><geometry>
      <mesh filename="package://arm/meshes/link.stl" scale="0.001 0.001 0.001"/>
    </geometry></visual>
    <collision><geometry><mesh filename="package://arm/meshes/link.stl"/></geometry></collision>
    ```

    ## Fix
    Give the collision the visual's size or `scale`. Silence with
    `<!-- urdftool: ignore[collision-visual-scale-slip] -->`.
    """

    code = "N301"
    name = "collision-visual-scale-slip"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        tol = option(ctx, "scale_slip_tolerance")
        for link in ctx.robot.links:
            if not link.collisions:
                continue
            visuals = [(v, _sizes(v.geometry)) for v in link.visuals]
            for collision in link.collisions:
                mine = _sizes(collision.geometry)
                if mine is None:
                    continue
                same = [(v, s) for v, s in visuals if s is not None and s[0] == mine[0]]
                if any(_equal(s[1], mine[1], 0.01) for _, s in same):
                    continue
                for visual, sizes in same:
                    assert sizes is not None
                    k = _slip_factor(sizes[1], mine[1], tol)
                    if k is None:
                        continue
                    what = "mesh scale" if isinstance(collision.geometry, Mesh) else mine[0]
                    yield Diagnostic(
                        code=self.code,
                        name=self.name,
                        severity=self.severity,
                        message=f"link '{link.name}': collision {what} {_vec(mine[1])} is "
                        f"{'×' if k > 0 else '÷'}{10 ** abs(k)} the visual's {_vec(sizes[1])}",
                        location=getattr(collision.geometry, "span", None) or collision.span or link.span,
                        element=where_link(link, "collision", "geometry"),
                        help="a factor of a power of ten is a unit slip; give both the same size",
                        data={"factor": 10.0**k, "collision": list(mine[1]), "visual": list(sizes[1])},
                        related=_related(visual.span, "the visual it disagrees with"),
                    )
                    break


def _equal(a: tuple[float, ...], b: tuple[float, ...], tol: float) -> bool:
    return len(a) == len(b) and all(
        abs(x - y) <= tol * max(abs(x), abs(y)) for x, y in zip(sorted(a), sorted(b), strict=False)
    )


def _vec(values: tuple[float, ...]) -> str:
    return " ".join(fmt(v) for v in values)


def _related(span: object, label: str) -> tuple[Related, ...]:
    return (Related(span, label),) if span is not None else ()  # type: ignore[arg-type]


@register
class SpinInertiaOffAxis(IntentRule):
    """A wheel's inertia is symmetric about an axis other than the one it turns about.

    ## What it does
    For a link named like a wheel (`wheel`, `tire`, `tyre`) on a continuous
    or revolute joint, finds the axis its inertia is symmetric about as a
    disc: two principal moments equal within 2 % (option
    `axisymmetric_tolerance`) and the third over 10 % larger. It reports
    when that axis is more than 10° from the joint axis. Rotors and
    propellers are left out: a blade is a rod, whose symmetry axis lies
    across the spin axis by design.

    ## Why it matters
    A disc spins about its symmetry axis. An inertia computed for a
    cylinder standing along z while the wheel turns about y gives the
    simulator the wrong moment for spinning (wheel slip, odometry error)
    and gyroscopic effects that tip a fast rotor over.

    ## Example
    ```xml
    <joint name="wheel_joint" type="continuous"><axis xyz="0 1 0"/>…</joint>
    <link name="wheel"><inertial><mass value="1"/>
      <inertia ixx="0.0027" iyy="0.0027" izz="0.005" ixy="0" ixz="0" iyz="0"/></inertial></link>
    ```

    ## Fix
    Rotate the inertia (or the inertial `rpy`) so the large moment lies on
    the joint axis: here `ixx="0.0027" iyy="0.005" izz="0.0027"`.
    """

    code = "N302"
    name = "spin-inertia-off-axis"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        tol = option(ctx, "axisymmetric_tolerance")
        for joint in ctx.robot.joints:
            if joint.type not in (JointType.CONTINUOUS, JointType.REVOLUTE) or not _SPINNING.search(
                joint.child
            ):
                continue
            link = ctx.robot.link(joint.child)
            if link is None or link.inertial is None:
                continue
            axis = _symmetry_axis(link, tol)
            if axis is None:
                continue
            error = angle_between(axis, np.asarray(joint.axis, dtype=float))
            if error <= math.radians(SPIN_AXIS_TOLERANCE_DEG):
                continue
            yield Diagnostic(
                code=self.code,
                name=self.name,
                severity=self.severity,
                message=f"link '{link.name}': its inertia is symmetric about "
                f"({', '.join(fmt(float(v)) for v in axis)}) but joint '{joint.name}' turns it about "
                f"({', '.join(fmt(v) for v in joint.axis)}), {fmt(math.degrees(error))}° apart",
                location=link.inertial.inertia_span or link.inertial.span or link.span,
                element=where_link(link, "inertial", "inertia"),
                help="rotate the inertia so its distinct moment lies on the joint axis",
                data={
                    "symmetry_axis": [float(v) for v in axis],
                    "joint_axis": list(joint.axis),
                    "error_deg": math.degrees(error),
                },
                related=_related(joint.axis_span or joint.span, f"the axis of joint '{joint.name}'"),
            )


def _symmetry_axis(link: Link, tol: float) -> np.ndarray | None:
    assert link.inertial is not None
    tensor = link.inertial.inertia_in_link_frame
    if not np.all(np.isfinite(tensor)):
        return None
    moments, axes = principal_moments(tensor)
    moments = np.asarray(moments, dtype=float)
    if not np.all(moments > 0):
        return None
    for i in range(3):
        j, k = [n for n in range(3) if n != i]
        pair_close = abs(moments[j] - moments[k]) <= tol * max(moments[j], moments[k])
        # a disc: the distinct moment is the largest (a rod's, the smallest, is its length axis)
        distinct = moments[i] > (1.0 + DISTINCT_MOMENT) * max(moments[j], moments[k])
        if pair_close and distinct:
            return np.asarray(axes, dtype=float)[:, i]
    return None


@register
class MimicBeyondFollowerLimits(IntentRule):
    """A mimic joint is driven outside its own limits over its leader's range.

    ## What it does
    For a limited joint with `<mimic joint="leader" multiplier="m"
    offset="o"/>`, maps the leader's limits through `m·q + o` and reports
    when the result leaves the follower's own `lower`..`upper` by more than
    0.001 rad or m (option `mimic_tolerance`).

    ## Why it matters
    The follower's position is not free: moving the leader to its limit
    drives the follower past its own, which MoveIt reports as an invalid
    state, a simulator clamps (the gripper jams half-open), and a real
    linkage would break.

    ## Example
    ```xml
    <joint name="finger_left"><limit lower="0" upper="0.8" …/></joint>
    <joint name="finger_right"><limit lower="0" upper="0.4" …/>
      <mimic joint="finger_left" multiplier="1"/></joint>
    ```

    ## Fix
    Make the follower's limits cover `m·[lower, upper] + o`, or correct the
    multiplier (often a sign) or offset.
    """

    code = "N303"
    name = "mimic-beyond-follower-limits"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        tol = option(ctx, "mimic_tolerance")
        limited = (JointType.REVOLUTE, JointType.PRISMATIC)
        for joint in ctx.robot.joints:
            mimic, own = joint.mimic, joint.limit
            if mimic is None or own is None or joint.type not in limited:
                continue
            leader = ctx.robot.joint(mimic.joint)
            if leader is None or leader.type not in limited or leader.limit is None:
                continue
            ends = [
                mimic.multiplier * (v or 0.0) + mimic.offset for v in (leader.limit.lower, leader.limit.upper)
            ]
            lo, hi = min(ends), max(ends)
            lower, upper = own.lower or 0.0, own.upper or 0.0
            if not all(math.isfinite(v) for v in (lo, hi, lower, upper)) or lower > upper:
                continue
            if lo >= lower - tol and hi <= upper + tol:
                continue
            yield Diagnostic(
                code=self.code,
                name=self.name,
                severity=self.severity,
                message=f"joint '{joint.name}' follows '{leader.name}' as {fmt(mimic.multiplier)}·q + "
                f"{fmt(mimic.offset)}: over the leader's {fmt(leader.limit.lower or 0.0)} .. "
                f"{fmt(leader.limit.upper or 0.0)} it moves {fmt(lo)} .. {fmt(hi)}, outside its own "
                f"{fmt(lower)} .. {fmt(upper)}",
                location=own.span or joint.span,
                element=where_joint(joint, "limit"),
                help="widen the follower's limits to the mimicked range, "
                "or fix the multiplier's sign or the offset",
                data={"driven": [lo, hi], "limits": [lower, upper], "leader": leader.name},
                related=_related(leader.limit.span or leader.span, f"the limits of leader '{leader.name}'"),
            )
