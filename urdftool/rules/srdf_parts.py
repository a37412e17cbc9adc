"""MoveIt SRDF (P), continued: end effectors, virtual joints and the collision matrix."""

from __future__ import annotations

from collections.abc import Iterator

from urdftool.catalogue.registry import register
from urdftool.catalogue.suggest import did_you_mean
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts import srdf as facts
from urdftool.facts.context import CheckContext
from urdftool.model import JointType
from urdftool.parse.srdf import KNOWN_REASONS, VIRTUAL_JOINT_TYPES
from urdftool.rules.srdf import _Srdf


@register
class SrdfEndEffectorInvalid(_Srdf):
    """An end effector's parent group does not hold its parent link, or is its own group.

    ## What it does
    For each `<end_effector>` with a `parent_group` whose names exist: the
    parent group must hold `parent_link` (the link the effector hangs from)
    and must not be the effector's own `group`. A parent group that shares
    moving joints with the effector's group is reported as a warning (fixed
    joints have no variable, and both groups often hold the flange's).

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
        fixed = {j.name for j in ctx.robot.joints if j.type is JointType.FIXED}
        fixed.update(v.name for v in found.virtual_joints if v.type == "fixed")
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
            # a fixed joint has no variable to fight over (the Setup Assistant puts a flange's
            # fixed joint in both groups, as in the Panda's and KUKA's official configurations)
            shared = sorted(name for name in held.joints & parent_held.joints if name not in fixed)
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
    that `child_link` is the URDF's root link, and that a floating or planar
    virtual joint's `parent_frame` is not one of the robot's own links.

    A fixed virtual joint on another link is a warning: MoveIt skips it ("does
    not match the URDF frame") and fixes the root link in place, which is what
    a fixed virtual joint asks for. It is not reported at all when the URDF
    itself starts at the virtual joint's parent frame and fixes `child_link`
    to it (`world` → `base_link`, as Gazebo needs to pin an arm): MoveIt 2.11
    silences its warning for that setup. A fixed virtual joint's parent frame
    is not used (MoveIt keeps the root link as the model frame), so it may be
    a robot link.

    ## Why it matters
    MoveIt refuses any other type. A floating or planar virtual joint that
    MoveIt skips leaves the base fixed: a mobile robot is planned as if it
    could not move. A floating or planar parent frame inside the robot
    becomes the model frame, and the robot moves relative to itself.

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
            fixed = virtual.type == "fixed"
            if (root is not None and child in links and child != root
                    and not (fixed and _pinned_by_the_urdf(ctx, child, root, virtual.parent_frame))):
                yield self.diagnostic(
                    f"virtual joint '{virtual.name}' attaches link '{child}', not the root link '{root}'"
                    + ("; MoveIt skips it and fixes the root in place" if fixed else
                       f"; MoveIt skips it, and the robot's base cannot move ({virtual.type} is lost)"
                       if virtual.type in VIRTUAL_JOINT_TYPES else ""),
                    virtual.span, element=where, help=f"write child_link=\"{root}\"",
                    severity=Severity.WARNING if fixed else Severity.ERROR,
                    data={"child_link": child, "root": root},
                )
            if not fixed and virtual.parent_frame in links:
                yield self.diagnostic(
                    f"virtual joint '{virtual.name}' hangs the robot from its own link "
                    f"'{virtual.parent_frame}'",
                    virtual.span, element=where,
                    help="name a frame outside the robot (\"world\", \"odom\") as parent_frame",
                    data={"parent_frame": virtual.parent_frame},
                )


def _pinned_by_the_urdf(ctx: CheckContext, child: str, root: str, parent_frame: str) -> bool:
    """The URDF starts at *parent_frame* and fixes *child* to it: the virtual joint repeats the
    URDF's own first joint (Gazebo's fixed ``world`` joint)."""
    joint = ctx.tree.parent_joint.get(child)
    return (root == parent_frame and joint is not None and joint.parent == root
            and joint.type is JointType.FIXED)


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

