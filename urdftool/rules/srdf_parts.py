"""MoveIt SRDF (P), continued: end effectors, virtual joints and the collision matrix."""

from __future__ import annotations

from collections.abc import Iterator

from urdftool.catalogue.registry import register
from urdftool.catalogue.suggest import did_you_mean
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts import srdf as facts
from urdftool.facts.context import CheckContext
from urdftool.parse.srdf import KNOWN_REASONS, VIRTUAL_JOINT_TYPES
from urdftool.rules.srdf import _Srdf


@register
class SrdfEndEffectorInvalid(_Srdf):
    """An end effector's parent group does not hold its parent link, or is its own group.

    ## What it does
    For each `<end_effector>` with a `parent_group` whose names exist: the
    parent group must hold `parent_link` (the link the effector hangs from)
    and must not be the effector's own `group`. A parent group that shares
    joints with the effector's group is reported as a warning.

    ## Why it matters
    MoveIt logs an error ("was specified as parent group for end-effector
    ... but it does not include the parent link", "cannot be its own
    parent") and the effector has no parent group: RViz's interactive marker
    and pick-and-place pipelines cannot tell which arm carries the gripper.

    ## Example
    ```xml
    <end_effector name="hand" parent_link="panda_link8" group="hand" parent_group="hand"/>
    ```

    ## Fix
    Name the arm's group as `parent_group`, and as `parent_link` a link of
    that arm which the gripper hangs from.
    """

    code = "P009"
    name = "srdf-end-effector-invalid"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        found = facts.srdf(ctx)
        if found is None:
            return
        for effector in found.end_effectors:
            group = found.group(effector.group.name)
            parent = found.group(effector.parent_group.name) if effector.parent_group else None
            if group is None or parent is None:
                continue  # srdf-unknown-group
            link = effector.parent_link.name
            where = f"end_effector[{effector.name}]"
            if parent.name == group.name:
                yield self.diagnostic(
                    f"end effector '{effector.name}': group '{group.name}' cannot be its own parent group",
                    effector.span, element=where, help="name the arm's group as parent_group",
                    data={"end_effector": effector.name},
                )
                continue
            held = facts.contents(ctx, group)
            parent_held = facts.contents(ctx, parent)
            if link not in parent_held.links:
                yield self.diagnostic(
                    f"end effector '{effector.name}': parent group '{parent.name}' does not hold its parent "
                    f"link '{link}'",
                    effector.span, element=where,
                    help="pick the group whose last link carries the effector as parent_group",
                    data={"end_effector": effector.name, "parent_group": parent.name},
                )
            shared = sorted(held.joints & parent_held.joints)
            if shared:
                yield self.diagnostic(
                    f"end effector '{effector.name}': groups '{group.name}' and '{parent.name}' share "
                    f"joint(s) {', '.join(shared[:4])}",
                    effector.span, element=where, severity=Severity.WARNING,
                    help="the effector's group and its parent group should be disjoint",
                    data={"end_effector": effector.name, "shared": shared},
                )


@register
class SrdfVirtualJointInvalid(_Srdf):
    """A virtual joint has an unknown type, or does not attach the robot's root.

    ## What it does
    Checks that `<virtual_joint type>` is `fixed`, `floating` or `planar`,
    that `child_link` is the URDF's root link, and that `parent_frame` is not
    one of the robot's own links.

    ## Why it matters
    MoveIt refuses any other type, and only a virtual joint on the root link
    places the robot in the world; a parent frame inside the robot makes a loop.

    ## Example
    ```xml
    <virtual_joint name="world_joint" type="fix" parent_frame="world" child_link="base_link"/>
    ```

    ## Fix
    Use one of the three types, and the URDF's root link as `child_link`.
    """

    code = "P010"
    name = "srdf-virtual-joint-invalid"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        found = facts.srdf(ctx)
        if found is None:
            return
        links = {link.name for link in ctx.robot.links}
        root = ctx.tree.root if len(ctx.tree.roots) == 1 else None
        for virtual in found.virtual_joints:
            where = f"virtual_joint[{virtual.name}]"
            if virtual.type not in VIRTUAL_JOINT_TYPES:
                yield self.diagnostic(
                    f"virtual joint '{virtual.name}' has type '{virtual.type}'; MoveIt knows fixed, floating "
                    "and planar" + did_you_mean(virtual.type, VIRTUAL_JOINT_TYPES),
                    virtual.span, element=where, help="write type=\"fixed\", \"floating\" or \"planar\"",
                    data={"type": virtual.type},
                )
            child = virtual.child_link.name
            if root is not None and child in links and child != root:
                yield self.diagnostic(
                    f"virtual joint '{virtual.name}' attaches link '{child}', not the root link '{root}'",
                    virtual.span, element=where, help=f"write child_link=\"{root}\"",
                    data={"child_link": child, "root": root},
                )
            if virtual.parent_frame in links:
                yield self.diagnostic(
                    f"virtual joint '{virtual.name}' hangs the robot from its own link "
                    f"'{virtual.parent_frame}'",
                    virtual.span, element=where,
                    help="name a frame outside the robot (\"world\", \"odom\") as parent_frame",
                    data={"parent_frame": virtual.parent_frame},
                )


@register
class SrdfCollisionPairInvalid(_Srdf):
    """A `<disable_collisions>` entry pairs a link with itself or gives an unknown reason.

    ## What it does
    Reports a pair whose `link1` and `link2` are the same link, and a
    `reason` other than MoveIt Setup Assistant's `Adjacent`, `Default`,
    `Always`, `Never` and `User`.

    ## Why it matters
    A link is never checked against itself, so the entry does nothing and
    probably stands for another pair; an unknown reason usually means a
    hand-edited matrix whose provenance is lost.

    ## Example
    ```xml
    <disable_collisions link1="panda_link3" link2="panda_link3" reason="Never"/>
    ```

    ## Fix
    Write the pair meant, and one of the Setup Assistant's reasons (`User` for
    a pair disabled by hand).
    """

    code = "P011"
    name = "srdf-collision-pair-invalid"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        found = facts.srdf(ctx)
        if found is None:
            return
        # Most SRDFs have no such pair: their names are tested first, without building the pairs.
        if not any(link1 == link2 or (not enable and reason is not None and reason not in KNOWN_REASONS)
                   for link1, link2, reason, enable in found.collision_names):
            return
        for pair in found.collisions:
            where = f"disable_collisions[{pair.link1.name},{pair.link2.name}]"
            if pair.link1.name == pair.link2.name:
                yield self.diagnostic(
                    f"collision pair names link '{pair.link1.name}' twice; a link is never checked against "
                    "itself", pair.span, element=where, help="write the other link of the pair",
                    data={"link": pair.link1.name},
                )
            if not pair.enable and pair.reason is not None and pair.reason not in KNOWN_REASONS:
                yield self.diagnostic(
                    f"collision pair ({pair.link1.name}, {pair.link2.name}) has reason '{pair.reason}'"
                    + did_you_mean(pair.reason, KNOWN_REASONS),
                    pair.span, element=where,
                    help="use Adjacent, Default, Always, Never or User",
                    data={"reason": pair.reason},
                )

