"""Syntax and structure (S): the file is XML, is a robot, and its tree is well formed."""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterator

from urdftool.diagnostics import Diagnostic, Severity
from urdftool.model import JointType
from urdftool.rules.registry import CheckContext, Family, Rule, register
from urdftool.rules.suggest import did_you_mean


class _Syntax(Rule):
    family = Family.SYNTAX


@register
class InternalError(_Syntax):
    """urdftool failed while checking this model; the report may be incomplete.

    ## What it does
    Reports an unexpected failure inside urdftool itself instead of stopping
    with a traceback, so the other findings for this file and the other files
    are still reported.

    ## Why it matters
    A gate that crashes tells the user nothing about their robot. This is a
    bug in urdftool, not in the model.

    ## Example
    Any input that makes a rule raise an exception.

    ## Fix
    Report the file and the message to the urdftool maintainers; use
    `--ignore` with the failing rule's code to work around it meanwhile.
    """

    code = "S000"
    name = "internal-error"
    severity = Severity.ERROR


@register
class XmlSyntax(_Syntax):
    """The file is not well-formed XML, or is refused as unsafe.

    ## What it does
    Reports the first point where the XML parser gives up: unclosed or
    mismatched tags, bad characters, stray text after the root. Documents that
    declare entities, nest deeper than 256 levels or exceed 64 MiB are refused.

    ## Why it matters
    Nothing can be read from a file that does not parse. Entity declarations
    can expand without bound ("billion laughs") or read other files from disk,
    so urdftool never expands them.

    ## Example
    ```xml
    <robot name="arm">
      <link name="base">
    </robot>
    ```

    ## Fix
    Close every element; write values out instead of using XML entities
    (xacro properties do the same job safely).
    """

    code = "S001"
    name = "xml-syntax"
    severity = Severity.ERROR


@register
class NotARobot(_Syntax):
    """The root element is not `<robot>` (URDF) or `<sdf>` (SDF).

    ## What it does
    Reports a file whose root element is something other than a robot
    description, such as a launch file, a package manifest or an MJCF model.

    ## Why it matters
    URDF loaders (urdfdom, PyBullet, MuJoCo) reject such files, often with an
    unhelpful message, and a directory scan should say which file is not a robot.

    ## Example
    ```xml
    <mujoco model="arm"> ... </mujoco>
    ```

    ## Fix
    Point urdftool at the robot description, or give the file the right root.
    """

    code = "S002"
    name = "not-a-robot"
    severity = Severity.ERROR


@register
class RobotNameMissing(_Syntax):
    """The `<robot>` element has no `name` attribute, or an empty one.

    ## What it does
    Reports a robot without a name.

    ## Why it matters
    urdfdom refuses a nameless robot ("No name given for the robot"), so
    `robot_state_publisher` and MoveIt will not load it; SRDF files pair with
    their URDF by this name.

    ## Example
    ```xml
    <robot> <link name="base"/> </robot>
    ```

    ## Fix
    ```xml
    <robot name="arm"> <link name="base"/> </robot>
    ```
    """

    code = "S003"
    name = "robot-name-missing"
    severity = Severity.ERROR


@register
class EmptyRobot(_Syntax):
    """The robot has no links.

    ## What it does
    Reports a `<robot>` with no `<link>` element.

    ## Why it matters
    A robot needs at least one link to have a root; urdfdom refuses the file
    ("No link elements found in urdf file").

    ## Example
    ```xml
    <robot name="arm"/>
    ```

    ## Fix
    Add the links, or check that xacro conditions and includes produced them.
    """

    code = "S004"
    name = "empty-robot"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        from urdftool.rules.xacro import is_macro_library

        if is_macro_library(ctx.robot):
            return  # reported once as macros-only
        if ctx.robot.format == "sdf":
            return  # the SDF reader reports non-static models without links, at any depth
        if not ctx.robot.links and ctx.robot.name is not None:
            yield self.diagnostic(
                f"robot '{ctx.robot.name}' has no links", ctx.robot.span, element="robot"
            )
        elif not ctx.robot.links:
            yield self.diagnostic("robot has no links", ctx.robot.span, element="robot")


@register
class InvalidNumber(_Syntax):
    """A numeric attribute does not hold a finite decimal number.

    ## What it does
    Checks every number in the file (`xyz`, `rpy`, masses, inertias, limits,
    sizes, scales) and reports values that are not plain finite decimals:
    `0.07,` with a trailing comma, `-1.57.` with two dots, `NaN`, `inf`,
    `1_000`, or a leftover expression.

    ## Why it matters
    Parsers disagree on such values: urdfdom throws, PyBullet and some Python
    loaders read the leading digits and silently drop the rest, so the same
    file means different robots in different tools.

    ## Example
    ```xml
    <origin xyz="0 0.07, 0" rpy="0 -1.57. 0"/>
    ```

    ## Fix
    ```xml
    <origin xyz="0 0.07 0" rpy="0 -1.57 0"/>
    ```
    """

    code = "S005"
    name = "invalid-number"
    severity = Severity.ERROR


@register
class WrongVectorLength(_Syntax):
    """A vector attribute has the wrong number of components.

    ## What it does
    Reports `xyz`, `rpy`, `size`, `scale`, `rgba` and axis values with more or
    fewer numbers than their meaning allows (three for vectors, four for colours).

    ## Why it matters
    A 4-value `rpy` or `scale` is silently truncated by some loaders and
    rejected by others; the extra value usually means a typo that changed the
    robot.

    ## Example
    ```xml
    <mesh filename="chassis.stl" scale="1 1 1 1"/>
    ```

    ## Fix
    ```xml
    <mesh filename="chassis.stl" scale="1 1 1"/>
    ```
    """

    code = "S006"
    name = "wrong-vector-length"
    severity = Severity.ERROR


@register
class RepeatedElement(_Syntax):
    """An element that may appear once is written more than once.

    ## What it does
    Reports a second `<origin>`, `<axis>`, `<limit>`, `<inertial>`, `<mass>`,
    `<geometry>` and the like inside the same parent.

    ## Why it matters
    Loaders keep either the first or the last copy, and they do not agree:
    urdfdom reads the first `<axis>`, some Python loaders the last, so the
    joint turns about a different axis depending on the tool.

    ## Example
    ```xml
    <joint name="hip" type="revolute">
      <axis xyz="1 0 0"/>
      <axis xyz="0 1 0"/>
    </joint>
    ```

    ## Fix
    Keep the one you mean and delete the other.
    """

    code = "S007"
    name = "repeated-element"
    severity = Severity.ERROR


@register
class UnknownElement(_Syntax):
    """An element that the format does not define (with a did-you-mean suggestion).

    ## What it does
    Reports elements that URDF does not know in the place they are written,
    such as `<inertia>` directly in a link or `<orign>` for `<origin>`.

    ## Why it matters
    Loaders skip unknown elements without a word, so a misspelt `<origin>` or
    `<dynamics>` silently leaves its default value in place.

    ## Example
    ```xml
    <joint name="elbow" type="revolute"> <orign xyz="0 0 0.3"/> </joint>
    ```

    ## Fix
    ```xml
    <joint name="elbow" type="revolute"> <origin xyz="0 0 0.3"/> </joint>
    ```
    """

    code = "S008"
    name = "unknown-element"
    severity = Severity.WARNING


@register
class UnknownAttribute(_Syntax):
    """An attribute that the element does not define (with a did-you-mean suggestion).

    ## What it does
    Reports attributes URDF does not define on that element: `<limit
    lowwer="…">`, `<origin xzy="…">`, `<mass val="…">`.

    ## Why it matters
    Misspelt attributes are ignored by every loader: the value the author meant
    never reaches the simulator.

    ## Example
    ```xml
    <limit lowwer="-1.57" upper="1.57" effort="10" velocity="1"/>
    ```

    ## Fix
    ```xml
    <limit lower="-1.57" upper="1.57" effort="10" velocity="1"/>
    ```
    """

    code = "S009"
    name = "unknown-attribute"
    severity = Severity.WARNING


@register
class MissingAttribute(_Syntax):
    """A required attribute is missing.

    ## What it does
    Reports required attributes that are absent (`name` on links and joints,
    `type` on joints, `value` on `<mass>`, `filename` on `<mesh>`, the sizes
    of shapes, the six inertia components, `name` on a top-level material).
    Missing child elements are reported by `missing-element`.

    ## Why it matters
    urdfdom refuses the model; permissive loaders fill in zeros, which for a
    mass or an inertia makes the link physically impossible.

    ## Example
    ```xml
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0"/>
    ```

    ## Fix
    ```xml
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.002"/>
    ```
    """

    code = "S010"
    name = "missing-attribute"
    severity = Severity.ERROR


def _duplicates(names: list[str]) -> set[str]:
    return {name for name, count in Counter(names).items() if count > 1}


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
    The colour the author meant is lost: urdfdom logs an error and leaves the
    visual without material, RViz and simulators draw it in a default colour.
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
class JointMissingParentOrChild(_Syntax):
    """A joint has no `<parent link>` or no `<child link>`.

    ## What it does
    Reports joints without a `<parent>` or `<child>` element, or with an empty
    `link` attribute.

    ## Why it matters
    A joint that connects nothing cannot be placed in the tree; urdfdom refuses
    the model.

    ## Example
    ```xml
    <joint name="elbow" type="revolute"> <parent link="upper_arm"/> </joint>
    ```

    ## Fix
    ```xml
    <joint name="elbow" type="revolute"> <parent link="upper_arm"/> <child link="forearm"/> </joint>
    ```
    """

    code = "S015"
    name = "joint-missing-parent-or-child"
    severity = Severity.ERROR


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
class SelfLoopJoint(_Syntax):
    """A joint has the same link as parent and child.

    ## What it does
    Reports joints whose `<parent link>` equals their `<child link>`.

    ## Why it matters
    Such a joint means nothing physically, and some loaders hang on it
    (urdfdom's tree builder loops forever).

    ## Example
    ```xml
    <joint name="j" type="fixed"><parent link="base"/><child link="base"/></joint>
    ```

    ## Fix
    Point the child at the link the joint is meant to move.
    """

    code = "S019"
    name = "self-loop-joint"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for joint in ctx.robot.joints:
            if joint.parent and joint.parent == joint.child:
                yield self.diagnostic(
                    f"joint '{joint.name}' has link '{joint.parent}' as both parent and child",
                    joint.span,
                    element=f"joint[{joint.name}]",
                )


@register
class UnknownJointType(_Syntax):
    """A joint's `type` is not one of URDF's six.

    ## What it does
    Reports joint types other than `revolute`, `continuous`, `prismatic`,
    `fixed`, `floating` and `planar` (error; the joint is read as fixed).
    PyBullet's `spherical` extension is read as a ball joint and reported as a
    warning, because no other URDF loader accepts it.

    ## Why it matters
    urdfdom, ROS and MuJoCo refuse the model; a typo such as `revolut` makes the
    whole robot unloadable.

    ## Example
    ```xml
    <joint name="neck" type="spherical">…</joint>
    ```

    ## Fix
    Use a URDF type; for a ball joint, use SDF (`ball`) or three revolute joints
    through massless links.
    """

    code = "S020"
    name = "unknown-joint-type"
    severity = Severity.ERROR


@register
class UnexpandedSubstitution(_Syntax):
    """A value still contains a xacro or roslaunch substitution.

    ## What it does
    Reports attribute values containing `${…}` or `$(…)`, such as
    `$(optenv ROBOT_MODEL)` or `${wheel_radius}`, in a file that was not
    expanded by xacro.

    ## Why it matters
    The value is meaningless to a URDF loader: a number becomes garbage and a
    mesh path points nowhere. The file was probably generated without running
    xacro, or shipped with the `.urdf` suffix by mistake.

    ## Example
    ```xml
    <mesh filename="$(optenv MESH_DIR)/base.stl"/>
    ```

    ## Fix
    Expand the file with xacro (`urdftool` does this for `.xacro` files), or
    write the value out.
    """

    code = "S021"
    name = "unexpanded-substitution"
    severity = Severity.ERROR


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


@register
class MissingElement(_Syntax):
    """A required child element is missing.

    ## What it does
    Reports a `<visual>` or `<collision>` without `<geometry>`, a `<geometry>`
    with no shape, an `<inertial>` without `<mass>` or `<inertia>`.

    ## Why it matters
    urdfdom refuses the model; other loaders invent a value (PyBullet gives an
    inertial with no mass 0 kg and continues), so the robot differs per tool.

    ## Example
    ```xml
    <collision><origin xyz="0 0 0.1"/></collision>
    ```

    ## Fix
    Add the missing element, or delete the empty parent.
    """

    code = "S023"
    name = "missing-element"
    severity = Severity.ERROR
