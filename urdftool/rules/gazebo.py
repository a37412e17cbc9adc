"""Gazebo and ROS extensions (G): plugins, transmissions and SDF-isms inside URDF.

The extension blocks are kept by the reader as lxml elements; what they mean
(which tags name joints, what drive plugins declare) is in
:mod:`urdftool.rules.gazebo_plugins`, and the wheel geometry a drive plugin
should declare is measured in :mod:`urdftool.rules.gazebo_drive`. Decisions
and their evidence are in ``docs/gazebo.md``.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import Any

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.catalogue.suggest import suggester
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts import gazebo
from urdftool.facts import ros2_control as rc
from urdftool.facts.context import CheckContext
from urdftool.model import Extension, JointType, Link
from urdftool.parse.controllers import Value
from urdftool.parse.locate import span_of
from urdftool.rules import gazebo_drive as drive
from urdftool.rules import gazebo_plugins as gz
from urdftool.source import Span

#: Keys of ``<gazebo>`` blocks that sdformat's URDF converter reads (from text
#: or from a ``value`` attribute); anything else is copied into the SDF as is.
CONVERTER_KEYS = frozenset(
    {
        "material",
        "static",
        "turnGravityOff",
        "dampingFactor",
        "maxVel",
        "minDepth",
        "mu1",
        "mu2",
        "fdir1",
        "kp",
        "kd",
        "selfCollide",
        "maxContacts",
        "laserRetro",
        "springReference",
        "springStiffness",
        "stopCfm",
        "stopErp",
        "fudgeFactor",
        "provideFeedback",
        "canonicalBody",
        "cfmDamping",
        "implicitSpringDamper",
        "disableFixedJointLumping",
        "preserveFixedJoint",
    }
)

#: Where each SDF-only element of a URDF link or joint belongs instead.
SDF_ISM_FIX = {
    "pose": "URDF places a link only through its parent joint's <origin>",
    "sensor": 'Gazebo reads sensors from <gazebo reference="…"><sensor>',
    "self_collide": 'write it as <gazebo reference="…"><selfCollide>',
    "gravity": 'write <gazebo reference="…"><turnGravityOff>true</turnGravityOff>',
    "kinematic": 'write it inside <gazebo reference="…">',
    "velocity_decay": 'write it inside <gazebo reference="…">',
    "must_be_base_link": 'write it inside <gazebo reference="…">',
}


class _Gazebo(Rule):
    family = Family.GAZEBO


def _fmt(value: float) -> str:
    return f"{value:.3g}"


def _is_urdf(ctx: CheckContext) -> bool:
    return ctx.robot.format in ("urdf", "xacro")


@register
class GazeboReferenceMissing(_Gazebo):
    """A `<gazebo reference="…">` names no link or joint of the robot.

    ## What it does
    Checks the `reference` of every top-level `<gazebo>` block against the
    robot's link and joint names, and suggests the closest name. Links and
    joints that a reference-less `<gazebo>` block declares in raw SDF (Gazebo
    merges them into the model) count as names too.

    ## Why it matters
    Gazebo silently ignores a block whose reference matches nothing: the
    sensor it declares never exists, the friction or colour never applies.
    Renaming a link without renaming its `<gazebo>` block is the usual cause.
    A block that sets only a `<material>` (and Gazebo's defaults, such as
    `<gravity>true</gravity>` or `<self_collide>false</self_collide>`) is a
    warning: the robot behaves the same, only its colour is lost.

    ## Example
    ```xml
    <link name="camera_link"/>
    <gazebo reference="camera"> <sensor type="camera" name="cam"/> </gazebo>
    ```

    ## Fix
    Use the link's (or joint's) exact name: `<gazebo reference="camera_link">`.
    """

    code = "G001"
    name = "gazebo-reference-missing"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        names = {link.name for link in ctx.robot.links} | {joint.name for joint in ctx.robot.joints}
        blocks = gazebo.gazebo_blocks(ctx)
        # A reference-less block may hold raw SDF <link>/<joint> elements that Gazebo merges into
        # the model (PR2's gripper parallel links); they are as real as the URDF's own.
        names |= {
            name
            for block in blocks
            if block.get("reference") is None
            for child in block.iterchildren("link", "joint")  # lxml's tag filter: no other child is built
            if (name := child.get("name"))
        }
        suggest = suggester(names)
        for block in blocks:
            reference = block.get("reference")
            if reference is None or reference in names or "$" in reference:
                continue
            looks = _only_looks(block)
            yield self.diagnostic(
                f'<gazebo reference="{reference}"> names no link or joint'
                + suggest(reference),
                span_of(block),
                element=f"gazebo[{reference}]",
                help="Gazebo ignores the whole block; use the exact name of a link or joint"
                + ("; the block sets only a colour and Gazebo's defaults, so nothing but the colour "
                   "is lost" if looks else ""),
                data={"reference": reference},
                severity=Severity.WARNING if looks else None,
            )


#: what a ``<gazebo reference>`` block may set, besides its ``<material>``, and still change nothing
#: but the link's looks: Gazebo's own defaults written out (values as Classic's URDF reader takes them)
_DEFAULTS = {"gravity": ("true", "1"), "self_collide": ("false", "0"), "turnGravityOff": ("false", "0")}


def _only_looks(block: Any) -> bool:
    """Whether a ``<gazebo>`` block sets only a colour and Gazebo's defaults: ignored, it leaves
    the robot behaving as written, only coloured otherwise."""
    children = [child for child in block if isinstance(child.tag, str)]
    return bool(children) and all(
        child.tag == "material"
        or (child.tag in _DEFAULTS and (child.text or "").strip().lower() in _DEFAULTS[child.tag])
        for child in children
    )


@register
class TransmissionJointMissing(_Gazebo):
    """A `<transmission>` or `<ros2_control>` block names a joint the robot does not have.

    ## What it does
    Checks every joint named by ROS 1 `<transmission>` blocks (`<joint
    name>`, and PR2's `flexJoint`, `rollJoint`, `gap_joint`, `passive_joint`)
    and by ros2_control `<ros2_control>` blocks (`<joint name>`, also inside
    their `<transmission>`). Also reports joints that exist but are fixed,
    since Gazebo merges fixed joints away and controllers cannot command them.

    ## Why it matters
    `gazebo_ros_control` and `gz_ros2_control` stop loading the robot's
    hardware interface ("joint not found"), so no controller starts and the
    robot lies limp in simulation. A fixed joint is reported as a warning:
    its name is right, but Gazebo merges it away.

    ## Example
    ```xml
    <transmission name="shoulder_trans">
      <type>transmission_interface/SimpleTransmission</type>
      <joint name="shoulder_joint"> ... </joint>   <!-- the joint is called "shoulder" -->
    </transmission>
    ```

    ## Fix
    Name the joint exactly as in its `<joint name="…">`, or remove the
    transmission of a joint that no longer exists.
    """

    code = "G002"
    name = "transmission-joint-missing"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        yield from _joint_refs(self, ctx, gz.transmission_joint_refs(ctx.robot), "transmission")


@register
class PluginJointMissing(_Gazebo):
    """A Gazebo plugin names a joint the robot does not have, or a fixed joint Gazebo removes.

    ## What it does
    Checks the joint names that drive plugins (diff drive, skid steer,
    tricycle, Ackermann), joint-state publishers, mimic-joint and
    force/torque plugins read from their parameters (`leftJoint`,
    `left_joint`, `jointName`, `joint_name`, `mimicJoint`, …), for ROS 1,
    ROS 2 and gz-sim plugins alike.

    ## Why it matters
    The plugin fails to load (or, for a joint-state publisher, silently
    publishes nothing for that joint): the robot does not drive, and TF
    trees in RViz are missing wheels. A fixed joint is merged away by Gazebo
    unless `<preserveFixedJoint>` keeps it, so a plugin cannot find it either.

    ## Example
    ```xml
    <plugin name="diff_drive" filename="libgazebo_ros_diff_drive.so">
      <leftJoint>left_wheel_hinge</leftJoint>  <!-- the joint is "left_wheel_joint" -->
    </plugin>
    ```

    ## Fix
    Use the joint's exact name; for a fixed joint a plugin must see, add
    `<gazebo reference="JOINT"><preserveFixedJoint>true</preserveFixedJoint></gazebo>`.
    """

    code = "G003"
    name = "plugin-joint-missing"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        refs = (ref for plugin in gazebo.plugins(ctx) for ref in gz.plugin_joint_refs(plugin))
        yield from _joint_refs(self, ctx, refs, "plugin")


def _joint_refs(
    rule: Rule, ctx: CheckContext, refs: Iterable[gz.JointRef], what: str
) -> Iterator[Diagnostic]:
    joints = {joint.name: joint for joint in ctx.robot.joints}
    extra = gazebo.defined_joints(ctx)
    kept = gazebo.preserved_fixed_joints(ctx)
    suggest = suggester(joints)
    for ref in refs:
        joint = joints.get(ref.name)
        if joint is None and ref.name not in extra:
            yield rule.diagnostic(
                f"{ref.owner} names joint '{ref.name}', which the robot does not have"
                + suggest(ref.name),
                span_of(ref.element),
                element=f"{what}/{ref.element.tag}[{ref.name}]",
                help="use the exact name of one of the robot's joints",
                data={"joint": ref.name, "owner": ref.owner},
            )
        elif joint is not None and joint.type is JointType.FIXED and ref.name not in kept:
            yield rule.diagnostic(
                f"{ref.owner} names joint '{ref.name}', which is fixed; Gazebo merges fixed joints "
                "away, so it will not find it",
                span_of(ref.element),
                severity=Severity.WARNING,  # the name is right; only Gazebo's lumping loses it
                element=f"{what}/{ref.element.tag}[{ref.name}]",
                help=f"make '{ref.name}' a moving joint, or keep it with <gazebo reference="
                f'"{ref.name}"><preserveFixedJoint>true</preserveFixedJoint></gazebo>',
                data={"joint": ref.name, "owner": ref.owner, "fixed": True},
            )


@register
class DriveGeometryMismatch(_Gazebo):
    """A drive plugin's wheel separation or diameter disagrees with the robot's wheels.

    ## What it does
    For differential-drive and skid-steer plugins (ROS 1, ROS 2 and gz-sim),
    measures the distance between the left and right wheel centres along the
    axle, and the wheels' diameter from their collision shapes, and compares
    them with `wheelSeparation`/`wheel_separation` and
    `wheelDiameter`/`wheel_diameter`/`wheel_radius`. Differences above 5%
    are reported with the measured value.

    ## Why it matters
    The plugin converts velocity commands to wheel speeds, and wheel speeds
    to odometry, with the declared values. A wrong separation makes the
    robot turn at the wrong rate and its odometry drift on every turn; a
    wrong diameter scales every speed and distance. Navigation tuned in
    simulation then fails on the real robot.

    ## Example
    ```xml
    <joint name="left_wheel_hinge" type="continuous"> <origin xyz="0 0.15 0"/> ...
    <joint name="right_wheel_hinge" type="continuous"> <origin xyz="0 -0.15 0"/> ...
    <wheelSeparation>0.4</wheelSeparation>   <!-- the wheels are 0.3 m apart -->
    ```

    ## Fix
    Declare the measured values, `<wheelSeparation>0.3</wheelSeparation>`, or
    move the wheel joints if the plugin is right. (Skid-steer robots are
    sometimes given a wider separation on purpose, to mimic wheel slip: then
    ignore this rule for that file.)
    """

    code = "G004"
    name = "drive-geometry-mismatch"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        yield from self._controllers(ctx)
        plugins = list(gz.drive_plugins(gazebo.plugins(ctx)))
        if not plugins:
            return
        poses = ctx.tree.forward_kinematics()
        for plugin in plugins:
            pairs = [
                (drive.measure_wheel(ctx, left, poses), drive.measure_wheel(ctx, right, poses))
                for left, right in plugin.pairs
            ]
            measured = [(a, b) for a, b in pairs if a is not None and b is not None]
            if not measured:
                continue
            yield from self._separation(plugin, measured)
            yield from self._diameter(plugin, [w for pair in measured for w in pair])

    def _controllers(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        """``diff_drive_controller`` entries of the controllers YAML, located in the YAML."""
        drives = [c for c in rc.controller_list(ctx)
                  if c.type is not None and c.type.text() == "diff_drive_controller/DiffDriveController"]
        if not drives:
            return
        poses = ctx.tree.forward_kinematics()
        for controller in drives:
            names = [[v.text() or "" for v in (controller.param(key) or _EMPTY).items()]
                     for key in ("left_wheel_names", "right_wheel_names")]
            pairs = [(drive.measure_wheel(ctx, a, poses), drive.measure_wheel(ctx, b, poses))
                     for a, b in zip(names[0], names[1], strict=False)]
            wheels = [(a, b) for a, b in pairs if a is not None and b is not None]
            if not wheels:
                continue
            label = f"diff_drive_controller '{controller.name}'"
            checks = (("wheel_separation", sum(drive.separation(a, b) for a, b in wheels) / len(wheels)),
                      ("wheel_radius", _mean([w.diameter / 2 for p in wheels for w in p if w.diameter])))
            for key, measured in checks:
                value = controller.param(key)
                declared = value.number() if value is not None else None
                if declared is None or measured is None or not drive.differs(declared, measured):
                    continue
                assert value is not None  # a number was read from it
                yield self.diagnostic(
                    f"{label} declares {key} {_fmt(declared)} m, but the wheels measure {_fmt(measured)} m",
                    value.span, element=f"{controller.name}/{key}", help=f"write {key}: {measured:.4g}",
                    data={"declared_m": declared, "measured_m": measured,
                          "joints": [w.joint.name for p in wheels for w in p]})

    def _separation(
        self, plugin: gz.DrivePlugin, pairs: list[tuple[drive.Wheel, drive.Wheel]]
    ) -> Iterator[Diagnostic]:
        for index, (declared, element) in enumerate(plugin.separations):
            left, right = pairs[min(index, len(pairs) - 1)]
            # A single declared value serves every pair (skid steer): compare with their mean.
            group = pairs if len(plugin.separations) == 1 else [(left, right)]
            measured = sum(drive.separation(a, b) for a, b in group) / len(group)
            if not drive.differs(declared, measured):
                continue
            joints = " and ".join(f"'{w.joint.name}'" for pair in group for w in pair)
            yield self.diagnostic(
                f"{plugin.kind} {gz.plugin_label(plugin.element)} declares wheel separation "
                f"{_fmt(declared)} m, but wheel joints {joints} are {_fmt(measured)} m apart",
                span_of(element),
                element=f"plugin[{plugin.element.get('name')}]/{element.tag}",
                help=f"write <{element.tag}>{measured:.4g}</{element.tag}> (the distance between "
                "the "
                "wheel centres along the axle), or move the wheel joints",
                data={
                    "declared_m": declared,
                    "measured_m": measured,
                    "joints": [w.joint.name for pair in group for w in pair],
                },
            )

    def _diameter(self, plugin: gz.DrivePlugin, wheels: list[drive.Wheel]) -> Iterator[Diagnostic]:
        sizes = [w.diameter for w in wheels if w.diameter is not None]
        if plugin.diameter is None or not sizes:
            return
        declared, element = plugin.diameter
        measured = sum(sizes) / len(sizes)
        factor = 0.5 if element.tag == "wheel_radius" else 1.0
        if not drive.differs(declared, measured):
            return
        yield self.diagnostic(
            f"{plugin.kind} {gz.plugin_label(plugin.element)} declares wheel "
            f"{'radius' if factor < 1 else 'diameter'} {_fmt(declared * factor)} m, "
            "but the wheels' "
            f"collision shapes measure {_fmt(measured * factor)} m",
            span_of(element),
            element=f"plugin[{plugin.element.get('name')}]/{element.tag}",
            help=f"write <{element.tag}>{measured * factor:.4g}</{element.tag}>",
            data={
                "declared_m": declared * factor,
                "measured_m": measured * factor,
                "joints": [w.joint.name for w in wheels],
            },
        )


@register
class SdfElementInUrdf(_Gazebo):
    """An SDF element inside a URDF link or joint, or an old-style Gazebo key, that loaders skip.

    ## What it does
    Reports SDF-only elements written directly inside a URDF `<link>` or
    `<joint>` (`<pose>`, `<sensor>`, `<self_collide>`, `<gravity>`,
    `<kinematic>`, `<velocity_decay>`, `<must_be_base_link>`), which every URDF loader
    ignores, and keys of `<gazebo>` blocks written `<key value="…"/>`: sdformat
    still reads that old form for the keys it knows (as info), while keys it
    does not know (such as `stopKp`) are copied into the SDF where nothing
    reads them (as a warning).

    ## Why it matters
    The author meant something by them: a `<pose>` in a link is meant to
    move it, but URDF places links only by joint origins, so the model in
    RViz, MoveIt, MuJoCo and PyBullet differs from what its author sees in
    the file.

    ## Example
    ```xml
    <link name="chassis">
      <pose>0 0 0.1 0 0 0</pose>
    </link>
    ```

    ## Fix
    Move the offset into the parent joint's `<origin xyz="0 0 0.1"/>`;
    put Gazebo settings in `<gazebo reference="chassis">`; write Gazebo
    keys with their value as text: `<mu1>0.8</mu1>`.
    """

    code = "G005"
    name = "sdf-element-in-urdf"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        if not _is_urdf(ctx):
            return
        for link in ctx.robot.links:
            for extension in link.extensions:
                if extension.tag in SDF_ISM_FIX:
                    yield self._in_link(ctx, link, extension)
        for joint in ctx.robot.joints:
            for extension in joint.extensions:
                if extension.tag in SDF_ISM_FIX:
                    values = gz.text_of(extension.element).split()
                    fix = (
                        f"write it as <origin {_origin_text(values)}/>"
                        if extension.tag == "pose" and len(values) == 6
                        else SDF_ISM_FIX[extension.tag].replace("…", joint.name)
                    )
                    yield self.diagnostic(
                        f"joint '{joint.name}': <{extension.tag}> is SDF; URDF loaders ignore it",
                        extension.span,
                        element=f"joint[{joint.name}]/{extension.tag}",
                        help=fix,
                        data={"element": extension.tag},
                    )
        yield from self._legacy_keys(ctx)

    def _in_link(self, ctx: CheckContext, link: Link, extension: Extension) -> Diagnostic:
        what = f"link '{link.name}': <{extension.tag}> is SDF; URDF loaders ignore it"
        fix = SDF_ISM_FIX[extension.tag].replace("…", link.name)
        data: dict[str, Any] = {"element": extension.tag}
        if extension.tag == "pose":
            values = gz.text_of(extension.element).split()
            data["pose"] = values
            joint = ctx.tree.parent_joint.get(link.name)
            what += (
                f", so the link is not moved by {' '.join(values)}"
                if any(_nonzero(v) for v in values)
                else " (its value is zero, so nothing is lost)"
            )
            now = (
                (
                    f'xyz="{" ".join(f"{v:g}" for v in joint.origin.xyz)}" '
                    f'rpy="{" ".join(f"{v:g}" for v in joint.origin.rpy)}"'
                )
                if joint
                else ""
            )
            target = _origin_text(values) if len(values) == 6 else "…"
            fix = (
                f"move it into joint '{joint.name}': <origin {target}/> relative to the model "
                f"(the joint's origin is now {now})"
                if joint
                else "set the robot's spawn pose instead (the link is the root)"
            )
        return self.diagnostic(
            what, extension.span, element=f"link[{link.name}]/{extension.tag}", help=fix, data=data
        )

    def _legacy_keys(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for block, child in gz.legacy_value_keys(gazebo.gazebo_blocks(ctx)):
            value = child.get("value")
            where = (
                f'<gazebo reference="{block.get("reference")}">'
                if block.get("reference")
                else "<gazebo>"
            )
            known = child.tag in CONVERTER_KEYS
            yield self.diagnostic(
                f'{where}: <{child.tag} value="{value}"/> is the old Gazebo form; '
                + (
                    "sdformat still reads it, newer tools may not"
                    if known
                    else f"Gazebo no longer knows <{child.tag}> and ignores it"
                ),
                span_of(child),
                severity=Severity.INFO if known else Severity.WARNING,
                element=f"gazebo/{child.tag}",
                help=f"write <{child.tag}>{value}</{child.tag}>"
                if known
                else f"remove it, or use the SDF element that replaced <{child.tag}>",
                data={"key": child.tag, "value": value, "read_by_sdformat": known},
            )


_EMPTY = Value([], Span(""))


def _mean(values: list[float]) -> float | None:
    return sum(values) / len(values) if values else None


def _origin_text(values: list[str]) -> str:
    """``xyz="x y z" rpy="r p y"`` from an SDF pose's six numbers."""
    return f'xyz="{" ".join(values[:3])}" rpy="{" ".join(values[3:6])}"'


def _nonzero(text: str) -> bool:
    try:
        return float(text) != 0.0
    except ValueError:
        return True
