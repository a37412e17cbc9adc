"""Self-collision (P1xx): link pairs whose collision geometries overlap at the home configuration.

The overlaps come from :mod:`urdftool.facts.collisions` (Pinocchio and coal;
meshes as their convex hulls). Adjacent links, links welded by fixed joints and
pairs the SRDF disables are left out. Decisions and the corpus review:
docs/collisions.md.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import replace

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Diagnostic, Related, Severity
from urdftool.facts.collisions import DEPTH_TOLERANCE, MAX_GEOMETRIES, NotChecked, home_overlaps
from urdftool.facts.context import CheckContext
from urdftool.physics.describe import fmt


class _SelfCollision(Rule):
    family = Family.SRDF
    kind = "model"
    since = "0.2.0"


@register
class SelfCollisionAtHome(_SelfCollision):
    """Two links' collision geometries overlap at the home configuration.

    ## What it does
    Places every `<collision>` at the home configuration (every joint at 0,
    clamped into its limits; with an SRDF, the values of its first
    `<group_state>`) and reports each pair of links whose geometries
    interpenetrate by more than 1 mm, with the depth. Meshes count as their
    convex hulls. Parent and child links (also across a link without
    collision geometry), links welded together by fixed joints, and pairs the
    SRDF disables are not checked. In an SDF model a pair is checked only when
    the model's or one of the links' `<self_collide>` is true: both default to
    false, and gz-sim then computes no contact between links of one model.

    ## Why it matters
    A planner starts from a state in collision and refuses to plan ("start
    state in collision"); a simulator pushes the links apart at the first step
    and the robot jumps. Usually a collision shape is too large or misplaced,
    or the pair needs a `<disable_collisions>` in the SRDF.

    ## Example
    ```xml
    <joint name="j2" type="revolute">
      <parent link="upper"/><child link="gripper"/>  <!-- gripper box reaches into the base -->
    ```

    ## Fix
    Shrink or move the collision shape; if the links can never really touch,
    disable the pair in the SRDF (`urdftool collisions MODEL -o robot.srdf`
    writes the matrix MoveIt Setup Assistant would).
    """

    code = "P101"
    name = "self-collision-at-home"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        found = home_overlaps(ctx)
        if not isinstance(found, list):
            return
        for overlap in found:
            # the pair in name order: the same finding however the file orders its links
            name1, name2 = sorted((overlap.link1, overlap.link2))
            first = ctx.robot.link(name1)
            other = ctx.robot.link(name2)
            where = (first.collisions[0].span if first and first.collisions else None) or \
                (first.span if first else None)
            elsewhere = (other.collisions[0].span if other and other.collisions else None) or \
                (other.span if other else None)
            finding = self.diagnostic(
                f"links '{name1}' and '{name2}' overlap at home: the collision "
                f"geometries interpenetrate by {fmt(overlap.depth * 1000)} mm",
                where,
                element=f"link[{name1}]/collision",
                help="shrink or move a collision shape, or disable the pair in the SRDF",
                data={"link1": name1, "link2": name2, "depth": round(overlap.depth, 6),
                      "tolerance": DEPTH_TOLERANCE},
            )
            if elsewhere is not None:
                label = f"the collision of link '{name2}'"
                finding = replace(finding, related=(Related(elsewhere, label),))
            yield finding


@register
class SelfCollisionNotChecked(_SelfCollision):
    """Self-collision at home was not checked for this model.

    ## What it does
    Says why `self-collision-at-home` did not run: more collision geometries
    than the check handles (200; the pair count grows as its square), or a
    joint type without a Pinocchio model here.

    ## Why it matters
    A silent skip would read as "no overlaps".

    ## Example
    ```xml
    <!-- a model with 400 <collision> elements -->
    ```

    ## Fix
    Nothing to fix in the model; `urdftool collisions` computes the full matrix.
    """

    code = "P102"
    name = "self-collision-not-checked"
    severity = Severity.INFO

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        found = home_overlaps(ctx)
        if isinstance(found, NotChecked):
            yield self.diagnostic(f"self-collision at home not checked: {found.reason}", ctx.robot.span,
                                  element="robot", data={"reason": found.reason, "limit": MAX_GEOMETRIES})
