"""Syntax and structure (S) reported while a file is read: XML, numbers, elements, attributes.

The readers in :mod:`urdftool.parse` create these findings with
:meth:`~urdftool.catalogue.registry.Rule.diagnostic`. Two structural rules
that the SDF reader also reports (``empty-robot``, ``self-loop-joint``) keep
their model check here, written against :class:`ModelView` (the robot and its
tree, nothing else); the other structural rules are in :mod:`urdftool.rules.syntax`.
"""

from __future__ import annotations

from collections.abc import Iterator

from urdftool.catalogue.registry import Family, ModelView, Rule, register
from urdftool.catalogue.xacro import is_macro_library
from urdftool.diagnostics import Diagnostic, Severity


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
    `<geometry>` and the like inside the same parent. A repeated `<material>`
    in a `<visual>` (CAD exporters write one per colour) is a warning: every
    loader shows the first, and only the robot's look depends on it. So is an
    exact copy of the first (the same attributes and children, such as a
    joint's `<child link>` written twice): whichever copy a loader keeps, the
    robot is the same.

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
    such as `<inertia>` directly in a link or `<orign>` for `<origin>`. In SDF
    files, elements the declared SDFormat version does not define there, also
    inside a saved world's `<state>` block, which is checked against the state
    descriptions (a link state holds `<velocity>`, `<acceleration>` and
    `<wrench>`; a link does not).

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
    lowwer="…">`, `<origin xzy="…">`, `<mass val="…">`. In SDF files of
    version 1.7 and later it reports `<pose frame="…">`, the attribute 1.7
    replaced by `relative_to`: an error when it names a frame, a warning when
    it is empty (`frame=""`, as `gz sdf -p` writes for 1.5 and 1.6 files, where
    it is valid).

    ## Why it matters
    Misspelt attributes are ignored by every loader: the value the author meant
    never reaches the simulator. libsdformat drops a 1.7 file's `pose@frame`
    with only a console warning ("XML Attribute[frame] in element[pose] not
    defined in SDF, ignoring", sdformat#178), so the element is placed in the
    default frame (the model's, for a link), not in the frame named.

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
    In SDF: `filename` on every `<plugin>` (its `name` is optional in
    libsdformat's spec), `name` and `type` on every `<sensor>`; a plugin's own
    content is not checked. Missing child elements are reported by
    `missing-element`.

    ## Why it matters
    urdfdom refuses the model; permissive loaders fill in zeros, which for a
    mass or an inertia makes the link physically impossible. libsdformat
    refuses an SDF file with a missing required attribute ("Required
    attribute[filename] in element[plugin] is not specified in SDF"), so
    gz-sim does not load it.

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
    expanded by xacro, and the same in the `<parameters>` of a ros2_control
    simulation plugin (gz_ros2_control passes that path on as written).

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

    def check(self, ctx: ModelView) -> Iterator[Diagnostic]:
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

    def check(self, ctx: ModelView) -> Iterator[Diagnostic]:
        for joint in ctx.robot.joints:
            if joint.parent and joint.parent == joint.child:
                yield self.diagnostic(
                    f"joint '{joint.name}' has link '{joint.parent}' as both parent and child",
                    joint.span,
                    element=f"joint[{joint.name}]",
                )


@register
class UnusedSuppression(_Syntax):
    """An `urdftool: ignore[…]` comment silences nothing.

    ## What it does
    Reports each code or name in an `<!-- urdftool: ignore[…] -->` (or
    `ignore-file[…]`) comment that silenced no finding in this run, and each
    one that is not a rule at all. A suppression of a rule that is switched off
    (`--ignore`, `--select`) is not reported: it may be needed in other runs.

    ## Why it matters
    Suppressions outlive the findings they were written for: after the file is
    fixed, a stale comment would silently hide the next, real finding on that
    line. Reporting them keeps every suppression deliberate, as ruff does for
    an unused `# noqa`.

    ## Example
    ```xml
    <!-- urdftool: ignore[zero-mass] -->
    <link name="sensor"><inertial><mass value="0.1"/>…</inertial></link>
    ```

    ## Fix
    Remove the code from the comment, or the comment when nothing is left.
    `--no-suppressions` shows every finding with all comments ignored.
    """

    code = "S024"
    name = "unused-suppression"
    severity = Severity.WARNING


@register
class VendorExtension(_Syntax):
    """An attribute or element a vendor adds to URDF: recognised, and what reads it.

    ## What it does
    Reports once per kind, at its first use, the attributes and elements that
    real robot vendors add to URDF and that some tool reads (Franka's joint
    friction model `<dynamics D K mu_coulomb mu_viscous>`, Gazebo's
    `<joint dont_collapse>`, ROS-Industrial's `<collision><material>`, …), with
    the tool that reads them and how often they occur. The table is in
    `docs/extensions.md`. Anything not in it stays `unknown-attribute` or
    `unknown-element`.

    ## Why it matters
    urdfdom, yourdfpy and Pinocchio ignore them, so they are not mistakes; but
    a consumer that does not know them loses what they say (friction, a kept
    fixed joint). A note per kind keeps that visible without repeating a
    warning on every joint.

    ## Example
    ```xml
    <dynamics D="1" K="7000" damping="0.003" friction="0.0" mu_coulomb="0" mu_viscous="16"/>
    ```

    ## Fix
    Nothing to fix. Silence it with `--ignore vendor-extension`.
    """

    code = "S025"
    name = "vendor-extension"
    severity = Severity.INFO
