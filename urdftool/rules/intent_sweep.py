"""Joint ranges wider than the geometry allows (N305).

The sweep itself is a fact (:mod:`urdftool.facts.range_sweep`): each limited
revolute joint turned from its lower to its upper limit, with the share of the
child's collision volume inside the parent's and the penetration depth at each
sampled angle. This rule judges it. Adjacent links overlap around their joint
at every angle, so what counts is the overlap *beyond* the one at home: a
range end is reported when, on the way from home to it, the child sinks a
further ``sweep_share`` of its volume and ``sweep_depth_min`` deeper into the
parent, and the end lies ``sweep_margin_deg`` beyond the angle where that
starts. Decisions and the corpus review: docs/intent.md.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import replace

from urdftool.catalogue.registry import register
from urdftool.diagnostics import Diagnostic, Related, Severity
from urdftool.facts.context import CheckContext
from urdftool.facts.range_sweep import Sweep, range_sweeps, share_at
from urdftool.physics.describe import fmt
from urdftool.records import record
from urdftool.rules.intent_common import IntentRule, option, where_joint


@record
class Passing:
    """Where a joint's child passes into its parent on the way from home to one limit.

    ``start`` (rad) is the first sampled angle where the child is
    ``share_min`` more of its volume and ``depth_min`` deeper inside the
    parent than at home. Between ``start`` and the limit, ``depth`` (m) is
    the deepest penetration, and ``share`` the largest share of the child's
    volume inside the parent, reached at ``fullest`` (rad); ``home_share``
    is the share at home.
    """

    side: str
    limit: float
    start: float
    fullest: float
    depth: float
    share: float
    home_share: float


def passings(sweep: Sweep, share: Callable[[float], float | None], share_min: float, depth_min: float,
             margin: float, home_share_max: float = 1.0) -> list[Passing]:
    """The limits of *sweep* that lie more than *margin* (rad) beyond where the child passes into
    the parent (see :class:`Passing`). *share* gives the share of the child's volume inside the
    parent at an angle (``None``: unknown, nothing is reported); it is asked only where the depth
    is already *depth_min* beyond home's. A child more than *home_share_max* inside its parent at
    home is not judged: its geometry overlaps by design, or is too coarse to tell."""
    out = []
    for side, limit in (("lower", sweep.lower), ("upper", sweep.upper)):
        order = [k for k, a in enumerate(sweep.angles)
                 if (a < sweep.home if side == "lower" else a > sweep.home)]
        if side == "lower":
            order.reverse()
        deeper = [k for k in order if sweep.depths[k] >= sweep.home_depth + depth_min]
        home_share = share(sweep.home) if deeper else None
        if home_share is None or home_share > home_share_max:
            continue
        start = next((k for k in deeper if (share(sweep.angles[k]) or 0.0) >= home_share + share_min), None)
        if start is None or abs(limit - sweep.angles[start]) < margin:
            continue
        beyond = order[order.index(start):]
        shares = {k: share(sweep.angles[k]) or 0.0 for k in beyond}
        most = max(beyond, key=lambda k: shares[k])
        out.append(Passing(side, limit, sweep.angles[start], sweep.angles[most],
                           max(sweep.depths[k] for k in beyond), shares[most], home_share))
    return out


@register
class RangePassesThroughParent(IntentRule):
    """A joint's range turns its link through the link it is mounted on.

    ## What it does
    Turns each limited `revolute` joint whose child and parent links both
    have collision geometry from its lower to its upper limit (2° steps,
    every other joint at home, mimic joints following) and measures how
    deep the child's collision geometry sinks into the parent's and what
    share of its volume lies inside it (meshes as their own closed
    triangle meshes). Adjacent links overlap around their joint at every
    angle, so only the overlap beyond the one at home counts: a limit is
    reported when, on the way from home to it, the child sinks a further
    30 % of its volume and 1 cm deeper into the parent, and the limit lies
    more than 5° beyond the angle where that starts. Not judged: prismatic
    joints (a telescoping stage lies inside its parent by design),
    continuous joints, mimic followers, links with an open (not
    watertight) collision mesh, a parent that collides as one convex mesh
    (a hull, which fills the notches its child turns into), and a child
    already more than 25 % inside its parent at home (its geometry is too
    coarse to tell passing from overlap).

    ## Why it matters
    The limits are what planners, controllers and simulators allow. A range
    that turns a forearm through the upper arm lets MoveIt plan through the
    arm when the adjacent pair is not collision-checked (the default), and a
    simulator, which ignores parent-child contacts, plays it out. Usually a
    limit was widened to ±π as a placeholder, or copied from another joint.

    ## Example
    ```xml
    <joint name="elbow" type="revolute">
      <parent link="upper_arm"/><child link="forearm"/>
      <limit lower="-3.1416" upper="3.1416" effort="150" velocity="3"/>  <!-- folds through the upper arm -->
    </joint>
    ```

    ## Fix
    Set the limit to the hardware's range (the datasheet's, or where the
    links meet). If the collision geometry is what is wrong (a box far
    larger than the part), fix the geometry instead. The finding points at
    the `lower` or `upper` attribute (at the `<limit>` when the attribute is
    on a later line of the tag), so `<!-- urdftool: ignore[N305] -->` on the
    line before the `<limit>` silences it.
    """

    code = "N305"
    name = "range-passes-through-parent"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        sweeps = range_sweeps(ctx, step=math.radians(option(ctx, "sweep_step_deg")))
        if not isinstance(sweeps, list):
            return
        share_min, depth_min = option(ctx, "sweep_share"), option(ctx, "sweep_depth_min")
        margin = math.radians(option(ctx, "sweep_margin_deg"))
        home_share_max = option(ctx, "sweep_home_share_max")
        for sweep in sweeps:
            joint = ctx.robot.joint(sweep.joint)
            if joint is None or joint.limit is None:
                continue
            def share(angle: float, sweep: Sweep = sweep) -> float | None:
                return share_at(ctx, sweep, angle)

            for passing in passings(sweep, share, share_min, depth_min, margin, home_share_max):
                span = joint.limit.lower_span if passing.side == "lower" else joint.limit.upper_span
                if span is None or joint.limit.span is None or span.line != joint.limit.span.line:
                    # an attribute on a later line of the tag could carry no ignore comment
                    span = joint.limit.span
                finding = self.diagnostic(
                    f"joint '{joint.name}' range [{fmt(sweep.lower)}, {fmt(sweep.upper)}] rad: "
                    f"beyond {fmt(passing.start)} rad the link '{sweep.child}' passes "
                    f"{fmt(passing.depth * 1000)} mm into '{sweep.parent}' (at {fmt(passing.fullest)} rad, "
                    f"with {fmt(passing.share * 100)} % of its collision volume inside it against "
                    f"{fmt(passing.home_share * 100)} % at home)",
                    span or joint.span,
                    element=where_joint(joint, "limit", passing.side),
                    help=f"set the {passing.side} limit to the hardware's range; the links collide "
                    f"from {fmt(passing.start)} rad on",
                    # rounded (depths to 0.1 mm): the last digits of coal's EPA depths differ between builds
                    data={"joint": joint.name, "side": passing.side, "limit": passing.limit,
                          "start": round(passing.start, 6), "fullest": round(passing.fullest, 6),
                          "depth": round(passing.depth, 4), "share": round(passing.share, 4),
                          "home_share": round(passing.home_share, 4),
                          "home_depth": round(sweep.home_depth, 4), "step": round(sweep.step, 6),
                          "child": sweep.child, "parent": sweep.parent},
                )
                parent = ctx.robot.link(sweep.parent)
                where = parent.collisions[0].span if parent and parent.collisions else None
                if where is not None:
                    label = f"the collision of link '{sweep.parent}'"
                    finding = replace(finding, related=(Related(where, label),))
                yield finding
