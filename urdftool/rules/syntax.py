"""Syntax and structure (S) of a loaded robot: names, references, roots and loops."""

from __future__ import annotations

from collections.abc import Iterator

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.catalogue.suggest import did_you_mean
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts.context import CheckContext
from urdftool.model import JointType


class _Syntax(Rule):
    family = Family.SYNTAX




@register
class DuplicateLinkName(_Syntax):
    """Two links have the same name.

    ## What it does
    Reports every link after the first whose name is already taken.

    ## Why it matters
    Joints refer to links by name; urdfdom refuses the model, and other loaders
    silently keep one of the two, attaching the subtree to the wrong body.
    Often the result of instantiating a xacro macro twice with the same prefix.

    ## Example
    ```xml
    <link name="wheel"/> <link name="wheel"/>
    ```

    ## Fix
    Give each link a unique name, e.g. `left_wheel` and `right_wheel`.
    """

    code = "S011"
    name = "duplicate-link-name"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        seen: dict[str, object] = {}
        for link in ctx.robot.links:
            if link.name in seen:
                first = seen[link.name]
                yield self.diagnostic(
                    f"link '{link.name}' is defined more than once (first at {first})",
                    link.span,
                    element=f"link[{link.name}]",
                    data={"first": str(first)},
                )
            else:
                seen[link.name] = link.span


@register
class DuplicateJointName(_Syntax):
    """Two joints have the same name.

    ## What it does
    Reports every joint after the first whose name is already taken.

    ## Why it matters
    Controllers, transmissions and joint-state messages address joints by name;
    urdfdom refuses the model.

    ## Example
    ```xml
    <joint name="wheel_joint" type="continuous">…</joint>
    <joint name="wheel_joint" type="continuous">…</joint>
    ```

    ## Fix
    Give each joint a unique name.
    """

    code = "S012"
    name = "duplicate-joint-name"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        seen: dict[str, object] = {}
        for joint in ctx.robot.joints:
            if joint.name in seen:
                yield self.diagnostic(
                    f"joint '{joint.name}' is defined more than once (first at {seen[joint.name]})",
                    joint.span,
                    element=f"joint[{joint.name}]",
                )
            else:
                seen[joint.name] = joint.span


@register
class DuplicateMaterialName(_Syntax):
    """Two top-level materials have the same name.

    ## What it does
    Reports a top-level `<material>` whose name is already defined. It is an
    error when the two definitions differ, a warning when they are identical.

    ## Why it matters
    urdfdom refuses a repeated material name; other loaders keep the first or
    the last, so the robot's colours depend on the tool.

    ## Example
    ```xml
    <material name="blue"><color rgba="0 0 1 1"/></material>
    <material name="blue"><color rgba="0 0 0.8 1"/></material>
    ```

    ## Fix
    Delete the repeated definition or rename one of them.
    """

    code = "S013"
    name = "duplicate-material-name"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        seen: dict[str, object] = {}
        for material in ctx.robot.materials:
            if material.name is None:
                continue
            if material.name in seen:
                first = seen[material.name]
                same = first == material
                yield self.diagnostic(
                    f"material '{material.name}' is defined again"
                    + (" with the same colour" if same else " differently"),
                    material.span,
                    element=f"material[{material.name}]",
                    severity=Severity.WARNING if same else Severity.ERROR,
                )
            else:
                seen[material.name] = material


@register
class UndefinedMaterial(_Syntax):
    """A visual refers to a material name that is defined nowhere.

    ## What it does
    Reports `<material name="…"/>` inside a visual, with no colour or texture
    of its own, whose name matches no top-level material and no material
    defined with a colour in another visual.

    ## Why it matters
    The colour the author meant is lost: urdfdom 1.0.4 and later (ROS Noetic
    and every ROS 2) logs "material '…' undefined" and leaves the visual
    without material, so RViz and simulators draw it in a default colour.
    Older urdfdom (ROS Melodic and before) refused the whole model on it.
    Gazebo material names (`Gazebo/Grey`) belong in a `<gazebo>` block, not in
    the URDF visual.

    ## Example
    ```xml
    <visual> <geometry><box size="1 1 1"/></geometry> <material name="grey"/> </visual>
    ```

    ## Fix
    ```xml
    <material name="grey"><color rgba="0.5 0.5 0.5 1"/></material>
    ```
    """

    code = "S014"
    name = "undefined-material"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        robot = ctx.robot
        defined = {m.name for m in robot.materials if m.name}
        for link in robot.links:
            for visual in link.visuals:
                m = visual.material
                if m and m.name and (m.color is not None or m.texture is not None):
                    defined.add(m.name)
        for link in robot.links:
            for visual in link.visuals:
                m = visual.material
                if m is None or m.name is None or m.color is not None or m.texture is not None:
                    continue
                if m.name not in defined:
                    yield self.diagnostic(
                        f"link '{link.name}': material '{m.name}' is not defined"
                        + did_you_mean(m.name, defined),
                        m.span or visual.span,
                        element=f"link[{link.name}]/visual/material",
                        help="define it at the top level: "
                        f'<material name="{m.name}"><color rgba="r g b a"/></material>',
                    )


@register
class UnknownLinkReference(_Syntax):
    """A joint's parent or child names a link that does not exist.

    ## What it does
    Reports `<parent link>` and `<child link>` values that match no link, with
    the closest existing link name as a suggestion.

    ## Why it matters
    The joint cannot be placed; urdfdom refuses the model and other loaders
    drop the joint and the subtree below it.

    ## Example
    ```xml
    <link name="forearm"/>
    <joint name="elbow" type="revolute"> <parent link="upper_arm"/> <child link="fore_arm"/> </joint>
    ```

    ## Fix
    Use the link's exact name (`forearm`).
    """

    code = "S016"
    name = "unknown-link-reference"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        names = {link.name for link in ctx.robot.links}
        for joint in ctx.robot.joints:
            for role, target in (("parent", joint.parent), ("child", joint.child)):
                if target and target not in names:
                    yield self.diagnostic(
                        f"joint '{joint.name}': {role} link '{target}' does not exist"
                        + did_you_mean(target, names),
                        joint.span,
                        element=f"joint[{joint.name}]/{role}",
                    )


@register
class MultipleRoots(_Syntax):
    """More than one link has no parent joint.

    ## What it does
    Reports a robot whose links form several disconnected trees, listing each
    root and the size of its tree. In an SDF model a link without a joint is a
    free body, which the spec allows: there it is one `info` naming the free
    bodies (a link that is the child of two joints is a closed chain, see
    `closed-chain`).

    ## Why it matters
    A URDF robot is one tree: urdfdom refuses several roots ("Two root links
    found"), and simulators drop or free-float the disconnected parts.

    ## Example
    ```xml
    <link name="base"/> <link name="camera"/>  <!-- no joint connects them -->
    ```

    ## Fix
    Connect the loose links with a joint (often a fixed joint was forgotten
    or misnamed).
    """

    code = "S017"
    name = "multiple-roots"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        roots = ctx.tree.roots
        if len(roots) < 2:
            return
        sizes = {root: sum(1 for _ in ctx.tree.walk(root)) for root in roots}
        largest = max(roots, key=lambda r: sizes[r])
        listing = ", ".join(f"'{r}' ({sizes[r]} links)" for r in roots)
        if ctx.robot.format == "sdf":
            # SDF models are not trees: a link without a joint is a free body.
            free = [r for r in roots if r != roots[0]]
            yield self.diagnostic(
                f"{len(free)} free bod{'y' if len(free) == 1 else 'ies'} beside the tree of '{roots[0]}': "
                + ", ".join(f"'{r}'" for r in free),
                ctx.robot.span,
                element="model",
                help="in SDF a link without a joint moves freely; join it with a joint if it should not",
                data={"roots": roots, "sizes": sizes, "free": free},
                severity=Severity.INFO,
            )
            return
        for root in roots:
            if root == largest:
                continue
            link = ctx.robot.link(root)
            yield self.diagnostic(
                f"link '{root}' is a second root: no joint has it as child (roots: {listing})",
                link.span if link else None,
                element=f"link[{root}]",
                help=f"connect '{root}' to the tree of '{largest}' with a joint",
                data={"roots": roots, "sizes": sizes},
            )


@register
class KinematicLoop(_Syntax):
    """The joints form a cycle, which URDF cannot express.

    ## What it does
    Reports each joint that closes a cycle of links and joints in a URDF model,
    listing the cycle. (A link with two parents is reported by
    `link-multiple-parents`; SDF models may have closed chains, see `closed-chain`.)

    ## Why it matters
    URDF is a tree. urdfdom refuses cycles, `check_urdf` loops, and other loaders
    silently drop a joint of their choice.

    ## Example
    ```xml
    <joint name="a" type="fixed"><parent link="l1"/><child link="l2"/></joint>
    <joint name="b" type="fixed"><parent link="l2"/><child link="l1"/></joint>
    ```

    ## Fix
    Remove the joint that closes the loop; model the closed chain in SDF or as
    an MJCF equality constraint.
    """

    code = "S018"
    name = "kinematic-loop"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        if ctx.robot.format == "sdf":
            return
        tree = ctx.tree
        for joint in tree.cycle_joints:
            if joint.parent == joint.child:
                continue  # self-loop-joint
            # A second parent that does not close a directed cycle is a
            # multiple-parent problem, reported by link-multiple-parents.
            if (
                joint.child in tree.parent_joint
                and tree.parent_joint[joint.child] is not joint
                and not tree._is_ancestor(joint.child, joint.parent)
            ):
                continue
            path = tree.path_to_root(joint.parent)
            cycle = [joint.name]
            for j in path:
                cycle.append(j.name)
                if j.parent == joint.child:
                    break
            yield self.diagnostic(
                f"joint '{joint.name}' closes a kinematic loop through joints "
                + " → ".join(f"'{n}'" for n in cycle),
                joint.span,
                element=f"joint[{joint.name}]",
                data={"cycle": cycle},
            )




@register
class FloatingJointNotAtRoot(_Syntax):
    """A `floating` joint that does not hang from the root link.

    ## What it does
    Reports floating joints whose parent is not the robot's root link, and
    every floating or planar joint after the first.

    ## Why it matters
    A floating joint stands for a free-flying base. Deeper in the tree it makes
    a body with six unconstrained DOF that most simulators and IK solvers
    cannot handle (KDL ignores floating joints, MuJoCo only accepts free joints
    on top-level bodies).

    ## Example
    ```xml
    <joint name="tool" type="floating"><parent link="forearm"/><child link="tool"/></joint>
    ```

    ## Fix
    Use a fixed joint for a rigidly mounted part, or make the floating joint
    connect the world (or root) link to the robot's base.
    """

    code = "S022"
    name = "floating-joint-not-at-root"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        if not any(joint.type is JointType.FLOATING for joint in ctx.robot.joints):
            return  # most robots: no floating joint, and no walk of the tree to order them
        roots = set(ctx.tree.roots)
        for joint in ctx.tree.joints_in_order:
            if joint.type is not JointType.FLOATING or joint.parent in roots:
                continue
            yield self.diagnostic(
                f"floating joint '{joint.name}' hangs from '{joint.parent}', not from the root "
                f"link '{ctx.tree.root}'",
                joint.span,
                element=f"joint[{joint.name}]",
                help="a floating joint should connect the world or root link to the base",
            )
