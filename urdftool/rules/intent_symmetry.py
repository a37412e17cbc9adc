"""Symmetry (N2xx): left/right pairs that should mirror and do not.

Pairs are found by name (:mod:`urdftool.rules.mirror_names`), on different branches of the
tree (names on one chain are axis letters, not sides). A pair's two members are judged
against each other two ways, and a rule fires only when both disagree:

* *as written*: the absolute values of the components (a mirror flips signs
  only), in each member's own parent frame;
* *in the robot*: mirrored through the root link's x-z plane at home (REP 103:
  x forward, y left), for poses and axes.

Every finding names the other member and carries its location as a related
span.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Callable, Iterator, Sequence
from typing import TypeVar

from urdftool.catalogue.registry import register
from urdftool.diagnostics import Diagnostic, Related, Severity
from urdftool.facts.context import CheckContext
from urdftool.facts.home import Frame, angle_between_frames, home_frames
from urdftool.model import Joint, JointType, Link
from urdftool.model.geometry import Mesh
from urdftool.model.pose import Vec3
from urdftool.physics import vec3
from urdftool.physics.describe import fmt
from urdftool.rules.intent_common import (
    IntentRule,
    on_one_chain,
    option,
    shape_dims,
    where_joint,
    where_link,
)
from urdftool.rules.mirror_names import pairs
from urdftool.source import Span

_T = TypeVar("_T")
_LIMIT_WORDS = ("limits", "effort", "veloci")
_SENSOR = re.compile(r"imu|camera|stereo|sensor|fsr|optical|laser|lidar|sonar|kinect", re.IGNORECASE)
def settled(
    candidates: Sequence[tuple[_T, _T]],
    name: Callable[[_T], str],
    judge: Callable[[_T, _T], Diagnostic | None],
) -> Iterator[Diagnostic]:
    """The findings of *judge* on pairs whose members have no candidate that mirrors them.

    Each member is reported once, with its first disagreeing candidate.
    """
    results = [(a, b, judge(a, b)) for a, b in candidates]
    clean = {name(m) for a, b, d in results if d is None for m in (a, b)}
    reported: set[str] = set()
    for a, b, diag in results:
        if diag is None:  # most pairs
            continue
        names = {name(a), name(b)}
        if names & clean or names & reported:
            continue
        reported |= names
        yield diag


def _all_close(a: Sequence[float], b: Sequence[float], ctx: CheckContext) -> bool:
    """Whether every pair of *a*'s and *b*'s numbers (m) agrees within the mirror tolerance:
    ``mirror_length_tolerance`` plus ``mirror_relative_tolerance`` of the larger."""
    absolute, relative = option(ctx, "mirror_length_tolerance"), option(ctx, "mirror_relative_tolerance")
    return all(abs(x - y) <= absolute + relative * max(abs(x), abs(y)) for x, y in zip(a, b, strict=False))


def _abs_match(a: Sequence[float], b: Sequence[float], ctx: CheckContext) -> bool:
    return _all_close([abs(x) for x in a], [abs(y) for y in b], ctx)


def _with_other(diag: Diagnostic, span: Span | None, label: str) -> Diagnostic:
    if span is None:
        return diag
    return dataclasses.replace(diag, related=(*diag.related, Related(span, label)))


def _vec(values: Sequence[float]) -> str:
    return " ".join(fmt(float(v)) for v in values)


def _mount(ctx: CheckContext, joint: Joint) -> bool:
    """Whether the joint places a sensor or a bare frame: placed where the hardware fits, not mirrored."""
    if _SENSOR.search(joint.name) or _SENSOR.search(joint.child):
        return True
    return _bare_frame(ctx, joint.child)


def _bare_frame(ctx: CheckContext, name: str) -> bool:
    """Whether link *name* is a frame only: no mass, no shape."""
    link = ctx.robot.link(name)
    return link is not None and link.inertial is None and not link.visuals and not link.collisions


def _joint_pairs(ctx: CheckContext) -> list[tuple[Joint, Joint]]:
    """Joints named as mirrors that sit on different branches: a joint that moves the other
    is the next axis of one chain (Motoman's `joint_l` and `joint_r` are its L and R axes).
    Found once per check: two rules judge them."""
    if "symmetry-joint-pairs" not in ctx.cache:
        out = []
        # the joints' and the links' names share their tokens' swaps (``left``, ``FL``)
        for a, b in pairs([j.name for j in ctx.robot.joints], ctx.cache.setdefault("symmetry-swaps", {})):
            ja, jb = ctx.robot.joint(a), ctx.robot.joint(b)
            if ja is not None and jb is not None and not on_one_chain(ctx.tree, ja.child, jb.child):
                out.append((ja, jb))
        ctx.cache["symmetry-joint-pairs"] = out
    found: list[tuple[Joint, Joint]] = ctx.cache["symmetry-joint-pairs"]
    return found


def _named_by_slot(ctx: CheckContext, ja: Joint, jb: Joint, frames: dict[str, Frame], middle: float) -> bool:
    """Whether each joint's child, mirrored, lands where a child of its own parent is.

    A row of parts named by slot, not by mirror: the Create 3's seven IR sensors run
    `side_left`, `left`, `front_left`, `front_center_left` (on the centre line),
    `front_center_right`, `front_right`, `right`, so `left` mirrors `front_right` and the row
    is symmetric as a whole. Positions at home, in the root frame (metres); *middle* is the
    lateral offset of the mirror plane, doubled (non-zero only for two parts on a bare frame).
    """
    for joint, partner in ((ja, jb), (jb, ja)):
        frame = frames.get(joint.child)
        if frame is None:
            return False
        flipped = _flipped(frame[1], middle)
        row = [frames.get(j.child) for j in ctx.robot.joints if j.parent == joint.parent and j is not partner]
        if not any(
            other is not None and _all_close(other[1], flipped, ctx)
            for other in row
        ):
            return False
    return True


@register
class MirroredPoseMismatch(IntentRule):
    """A left/right pair of joints is not placed as mirror images.

    ## What it does
    For each pair of joints named as each other's mirror (see
    docs/intent.md), compares their `<origin>` offsets. It reports when the
    absolute values of the offsets differ by more than 2 mm + 5 % (options
    `mirror_length_tolerance`, `mirror_relative_tolerance`) **and** the
    child frames, at home, are not mirror images through the root's x-z
    plane either (for two joints on one bare frame, such as a `world`
    link, through the plane parallel to it midway between the children);
    or when both children sit on the same side of that plane
    at the same place with the same orientation (a part copied and not
    mirrored; prismatic joints, whose fingers start together, excepted). Sensor mounts (names with
    `imu`, `camera`, `stereo`, `sensor`, `fsr`, `optical`, `laser`,
    `lidar`…) and bare frames (no mass, no shape) are not compared for
    offsets: sensors sit where the hardware fits, a stereo pair's right
    camera is offset from its left one by design. Nor is a pair whose
    members each mirror onto another part of their own parent: a row
    named by slot (`left`, `front_left`, `front_center_left` … `right`)
    that is symmetric as a whole.

    ## Why it matters
    A copied leg or arm whose offset was edited on one side only walks
    crooked, and a part copied without flipping the sign of y sits inside
    its twin. Both look fine in a file and cost hours on the real robot.

    ## Example
    ```xml
    <joint name="left_hip" type="revolute"><origin xyz="0 0.12 0"/>…</joint>
    <joint name="right_hip" type="revolute"><origin xyz="0 -0.21 0"/>…</joint>
    ```

    ## Fix
    Make the offsets mirror (`0 -0.12 0`). A robot that is really
    asymmetric: silence the joint with
    `<!-- urdftool: ignore[mirrored-pose-mismatch] -->`.
    """

    code = "N201"
    name = "mirrored-pose-mismatch"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        yield from settled(_joint_pairs(ctx), lambda j: j.name, lambda a, b: self._judge(ctx, a, b))

    def _judge(self, ctx: CheckContext, ja: Joint, jb: Joint) -> Diagnostic | None:
        frames = home_frames(ctx)
        if True:
            fa, fb = frames.get(ja.child), frames.get(jb.child)
            if fa is None or fb is None:
                return None
            wa, wb = fa[1], fb[1]
            written = _abs_match(ja.origin.xyz, jb.origin.xyz, ctx)
            lateral = option(ctx, "mirror_length_tolerance")
            turned = math.radians(option(ctx, "angle_tolerance_deg"))
            # prismatic fingers start at one point and slide apart: coinciding is their design
            same_side = (
                JointType.PRISMATIC not in (ja.type, jb.type)
                and abs(wa[1]) > 10 * lateral
                and wa[1] * wb[1] > 0
                and _all_close(wa, wb, ctx)
                # a copy keeps its orientation too; two frames at one point turned apart are a
                # design (Robonaut's arms both start at one shoulder point, turned left and right)
                and angle_between_frames(fa[0], fb[0]) <= turned
            )
            if same_side:
                message = (
                    f"joints '{ja.name}' and '{jb.name}' put their children at the same place, "
                    f"{_vec(wa)} m, on the same side (y {fmt(wa[1])} m): copied, not mirrored"
                )
            elif (
                not written
                and not _mirrored_world(ctx, ja, jb, wa, wb)
                and not (_mount(ctx, ja) or _mount(ctx, jb))
                and not _named_by_slot(ctx, ja, jb, frames, _middle(ctx, ja, jb, wa, wb))
            ):
                message = (
                    f"joint '{jb.name}' at xyz=\"{_vec(jb.origin.xyz)}\" does not mirror "
                    f"'{ja.name}' at xyz=\"{_vec(ja.origin.xyz)}\""
                )
            else:
                return None
            diag = self.diagnostic(
                message,
                jb.span,
                element=where_joint(jb, "origin"),
                help="mirrored parts have offsets equal up to sign",
                data={
                    "joint": jb.name,
                    "other": ja.name,
                    "xyz": list(jb.origin.xyz),
                    "other_xyz": list(ja.origin.xyz),
                    "same_side": same_side,
                },
            )
            return _with_other(diag, ja.span, f"the mirrored joint '{ja.name}'")


def _middle(ctx: CheckContext, ja: Joint, jb: Joint, wa: Vec3, wb: Vec3) -> float:
    """Twice the lateral offset (m) of the plane the children at *wa* and *wb* mirror through.

    Two parts set down on one bare frame (a `world` link) mirror through the plane between
    them: that frame's origin is where the author put it, not the robot's middle (xArm's dual
    arm: bases at y = 0 and y = 1 m). Otherwise the root's x-z plane (0).
    """
    return wa[1] + wb[1] if ja.parent == jb.parent and _bare_frame(ctx, ja.parent) else 0.0


def _mirrored_world(ctx: CheckContext, ja: Joint, jb: Joint, wa: Vec3, wb: Vec3) -> bool:
    """Whether the children at home (*wa*, *wb*, root frame, m) are mirror images; asked only
    of a pair whose offsets do not mirror as written (most pairs do)."""
    return _all_close(wa, _flipped(wb, _middle(ctx, ja, jb, wa, wb)), ctx)


@register
class MirroredJointMismatch(IntentRule):
    """A left/right pair of joints differs in type, axis or limits.

    ## What it does
    For each mirrored pair of joints, reports a different joint type; an
    axis whose components differ in absolute value as written **and** in
    the robot at home; or limits that are neither equal nor mirrored
    (`[l, u]` against `[-u, -l]`), or different `effort`/`velocity`, beyond
    5 % (option `mirror_relative_tolerance`) plus 0.01. The effort and
    velocity of a pair where one joint mimics the other are not compared:
    the follower is driven through its leader.

    ## Why it matters
    A limit edited on one side only lets one knee bend backwards; a
    mistyped axis turns one wheel or finger the wrong way. Controllers tuned
    on one side misbehave on the other.

    ## Example
    ```xml
    <joint name="l_knee" type="revolute"><limit lower="0" upper="2.4" …/></joint>
    <joint name="r_knee" type="revolute"><limit lower="0" upper="0.24" …/></joint>
    ```

    ## Fix
    Copy the limits across (negated and swapped when the axis is mirrored).
    Silence with `<!-- urdftool: ignore[mirrored-joint-mismatch] -->`.
    """

    code = "N202"
    name = "mirrored-joint-mismatch"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        yield from settled(_joint_pairs(ctx), lambda j: j.name, lambda a, b: self._judge(ctx, a, b))

    def _judge(self, ctx: CheckContext, ja: Joint, jb: Joint) -> Diagnostic | None:
        frames = home_frames(ctx)
        rel = option(ctx, "mirror_relative_tolerance")
        if True:
            problems = []
            if ja.type is not jb.type:
                problems.append(f"type {jb.type.value} against {ja.type.value}")
            elif ja.type.is_moving and not self._axes_mirror(ja, jb, frames):
                problems.append(f"axis {_vec(jb.axis)} against {_vec(ja.axis)}")
            la, lb = ja.limit, jb.limit
            if la is not None and lb is not None and ja.type is jb.type:
                a = (la.lower or 0.0, la.upper or 0.0)
                b = (lb.lower or 0.0, lb.upper or 0.0)
                if not (_near_pair(a, b, rel) or _near_pair(a, (-b[1], -b[0]), rel)):
                    problems.append(f"limits {fmt(b[0])} .. {fmt(b[1])} against {fmt(a[0])} .. {fmt(a[1])}")
                # a mimic follower is driven through its leader: its effort and velocity are
                # not a second actuator's (Kinova's Gen3 Lite finger: 1000 against 50)
                follower = ja.mimic is not None or jb.mimic is not None
                for label, x, y in (("effort", la.effort, lb.effort), ("velocity", la.velocity, lb.velocity)):
                    if not follower and x is not None and y is not None and not _near(x, y, rel):
                        problems.append(f"{label} {fmt(y)} against {fmt(x)}")
            if not problems:
                return None
            diag = self.diagnostic(
                f"joint '{jb.name}' does not mirror '{ja.name}': " + "; ".join(problems),
                # only the <limit> disagrees: point there (and at where its numbers were written)
                (jb.limit.span if jb.limit and problems[0][:6] in _LIMIT_WORDS else None) or jb.span,
                element=where_joint(jb),
                help="mirrored joints share type and limits (negated and swapped when mirrored)",
                data={"joint": jb.name, "other": ja.name, "problems": problems},
            )
            return _with_other(diag, ja.span, f"the mirrored joint '{ja.name}'")

    @staticmethod
    def _axes_mirror(ja: Joint, jb: Joint, frames: dict[str, Frame]) -> bool:
        tol = 0.02
        ua, ub = _unit(ja.axis), _unit(jb.axis)
        if all(abs(abs(x) - abs(y)) <= tol for x, y in zip(ua, ub, strict=True)):
            return True
        fa, fb = frames.get(ja.parent), frames.get(jb.parent)
        if fa is None or fb is None:
            return True
        # each axis in the robot: its joint frame's rotation, then its parent link's at home
        wa = vec3.apply(fa[0], vec3.apply(vec3.rotation(ja.origin.rpy), ua))
        wb = vec3.apply(fb[0], vec3.apply(vec3.rotation(jb.origin.rpy), ub))
        return all(abs(abs(x) - abs(y)) <= tol for x, y in zip(wa, wb, strict=True))


def _unit(axis: Vec3) -> Vec3:
    """*axis* divided by its length (a zero axis as it is)."""
    x, y, z = axis
    n = math.sqrt(x * x + y * y + z * z)
    return (x / n, y / n, z / n) if n > 0 else (x, y, z)


def _flipped(origin: Vec3, middle: float) -> Vec3:
    """*origin* mirrored through the root's x-z plane, moved by *middle* (twice the plane's y, m)."""
    return (origin[0], -origin[1] + middle, origin[2])


def _near(a: float, b: float, rel: float) -> bool:
    return abs(a - b) <= 0.01 + rel * max(abs(a), abs(b))


def _near_pair(a: tuple[float, float], b: tuple[float, float], rel: float) -> bool:
    return _near(a[0], b[0], rel) and _near(a[1], b[1], rel)


def _link_pairs(ctx: CheckContext) -> list[tuple[Link, Link]]:
    """Links named as mirrors that sit on different branches (see :func:`_joint_pairs`).
    Found once per check: two rules judge them."""
    if "symmetry-link-pairs" not in ctx.cache:
        out = []
        for a, b in pairs([k.name for k in ctx.robot.links], ctx.cache.setdefault("symmetry-swaps", {})):
            la, lb = ctx.robot.link(a), ctx.robot.link(b)
            if la is not None and lb is not None and not on_one_chain(ctx.tree, a, b):
                out.append((la, lb))
        ctx.cache["symmetry-link-pairs"] = out
    found: list[tuple[Link, Link]] = ctx.cache["symmetry-link-pairs"]
    return found


@register
class MirroredMassMismatch(IntentRule):
    """A left/right pair of links differs in mass.

    ## What it does
    For each pair of links named as each other's mirror, reports masses
    that differ by more than 10 % of the larger (option
    `mirror_mass_tolerance`) and by more than 10 g.

    ## Why it matters
    Mirrored parts weigh the same. A mass typed on one side only (or one
    left at a placeholder) shifts the centre of mass sideways: a biped
    leans, a quadruped's gait controller fights a phantom load.

    ## Example
    ```xml
    <link name="FL_calf"><inertial><mass value="0.2"/>…</inertial></link>
    <link name="FR_calf"><inertial><mass value="2.0"/>…</inertial></link>
    ```

    ## Fix
    Copy the inertial across (mirroring the off-diagonal products and the
    centre of mass). Silence with
    `<!-- urdftool: ignore[mirrored-mass-mismatch] -->`.
    """

    code = "N203"
    name = "mirrored-mass-mismatch"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        yield from settled(_link_pairs(ctx), lambda k: k.name, lambda a, b: self._judge(ctx, a, b))

    def _judge(self, ctx: CheckContext, la: Link, lb: Link) -> Diagnostic | None:
        tolerance = option(ctx, "mirror_mass_tolerance")
        if True:
            if la.inertial is None or lb.inertial is None:
                return None
            ma, mb = la.inertial.mass, lb.inertial.mass
            if not (math.isfinite(ma) and math.isfinite(mb)):
                return None
            if abs(ma - mb) <= max(0.01, tolerance * max(ma, mb)):
                return None
            diag = self.diagnostic(
                f"link '{lb.name}' weighs {fmt(mb)} kg, its mirror '{la.name}' {fmt(ma)} kg",
                lb.inertial.mass_span or lb.inertial.span or lb.span,
                element=where_link(lb, "inertial", "mass"),
                help="mirrored parts weigh the same",
                data={"link": lb.name, "other": la.name, "mass": mb, "other_mass": ma},
            )
            return _with_other(diag, la.inertial.mass_span or la.span, f"the mirrored link '{la.name}'")


@register
class MirroredGeometryMismatch(IntentRule):
    """A left/right pair of links has collision shapes of different size.

    ## What it does
    For each pair of links named as each other's mirror with the same number
    of collision elements, compares them in order: the same primitive kind
    with sizes (sorted, so a rotated copy matches) equal within 2 mm + 5 %,
    and meshes with the same absolute `scale`.

    ## Why it matters
    A collision shape resized on one side only makes one foot touch the
    ground early or one finger miss the object; a mesh scaled on one side
    only is a thousand times too big or small there.

    ## Example
    ```xml
    <link name="left_foot"><collision><geometry><box size="0.2 0.1 0.05"/></geometry></collision></link>
    <link name="right_foot"><collision><geometry><box size="0.2 0.1 0.5"/></geometry></collision></link>
    ```

    ## Fix
    Give both the same shape. Silence with
    `<!-- urdftool: ignore[mirrored-geometry-mismatch] -->`.
    """

    code = "N204"
    name = "mirrored-geometry-mismatch"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        yield from settled(_link_pairs(ctx), lambda k: k.name, lambda a, b: self._judge(ctx, a, b))

    def _judge(self, ctx: CheckContext, la: Link, lb: Link) -> Diagnostic | None:
        if True:
            if len(la.collisions) != len(lb.collisions):
                return None
            for ca, cb in zip(la.collisions, lb.collisions, strict=False):
                problem = _geometry_problem(ca.geometry, cb.geometry, ctx)
                if problem is None:
                    continue
                diag = self.diagnostic(
                    f"link '{lb.name}' collision {problem} of its mirror '{la.name}'",
                    getattr(cb.geometry, "span", None) or cb.span or lb.span,
                    element=where_link(lb, "collision", "geometry"),
                    help="mirrored parts have the same shape",
                    data={"link": lb.name, "other": la.name},
                )
                return _with_other(
                    diag,
                    getattr(ca.geometry, "span", None) or ca.span or la.span,
                    f"the mirrored link '{la.name}'",
                )
            return None


def _geometry_problem(a: object, b: object, ctx: CheckContext) -> str | None:
    if isinstance(a, Mesh) and isinstance(b, Mesh):
        if _abs_match(a.scale, b.scale, ctx):
            return None
        return f"mesh scale {_vec(b.scale)} differs from the scale {_vec(a.scale)}"
    da, db = shape_dims(a), shape_dims(b)  # type: ignore[arg-type]
    if da is None or db is None:
        return None
    kind_a, kind_b = getattr(a, "kind", ""), getattr(b, "kind", "")
    if kind_a != kind_b:
        return f"{kind_b} differs from the {kind_a}"
    if _all_close(sorted(da), sorted(db), ctx):
        return None
    return f"{kind_b} of {_vec(db)} m differs from the {kind_a} of {_vec(da)} m"
