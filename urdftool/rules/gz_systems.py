"""gz-sim systems (G3xx): the class a library registers, links, topics, parameter values,
the Sensors system's render engine, and gz_ros2_control's pairing with the ros2_control blocks.

Joint names of gz-sim systems (``joint_name``, ``left_joint``, …) are checked with every
other plugin's by ``plugin-joint-missing`` (G003). The systems are found in a URDF's
``<gazebo><plugin>`` and an SDF model's ``<plugin>``; an SDF world's own ``<plugin>``s
are read with its first model (``Robot.world_plugins``). What is known about each system is in
:mod:`urdftool.rules.gz_systems_known`; decisions are in ``docs/gazebo.md``.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.catalogue.suggest import closest, did_you_mean
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts import gazebo
from urdftool.facts import ros2_control as rc
from urdftool.facts.context import CheckContext
from urdftool.model import JointType, Robot
from urdftool.parse.locate import span_of
from urdftool.rules import gazebo_plugins as gz
from urdftool.rules import gz_systems_known as known

_TRUE_FALSE = frozenset({"true", "false", "1", "0"})


class _GzSim(Rule):
    family = Family.GAZEBO


def systems(ctx: CheckContext) -> list[known.System]:
    """Every gz-sim system of the model (and of its world), read once."""
    key = ("gz-systems",)
    if key not in ctx.cache:
        elements = [*gazebo.plugins(ctx), *ctx.robot.world_plugins]
        ctx.cache[key] = [s for e in elements if (s := known.read_system(e)) is not None]
    return ctx.cache[key]  # type: ignore[no-any-return]


def _children(system: known.System, tags: frozenset[str]) -> Iterator[tuple[Any, str]]:
    """(element, text) of the system's own children whose tag is in *tags*, text expanded."""
    for child in system.element:
        if isinstance(child.tag, str) and child.tag in tags and not len(child):
            text = gz.text_of(child)
            if text and "$" not in text:
                yield child, text


def _label(system: known.System) -> str:
    return gz.plugin_label(system.element)


@register
class SystemUnknown(_GzSim):
    """A gz-sim plugin's `name` is not a class its library registers.

    ## What it does
    For a `<plugin>` whose `filename` is one of gz-sim's system libraries
    (`gz-sim-diff-drive-system`, `ignition-gazebo-imu-system`,
    `libignition-gazebo-sensors-system.so`, …), checks that its `name` is the
    class that library registers (`gz::sim::systems::DiffDrive`, or the
    Ignition spelling `ignition::gazebo::systems::DiffDrive`), and suggests the
    right one. Libraries gz-sim does not ship (your own systems) are not checked.

    ## Why it matters
    gz-sim loads the library, then instantiates the class the `name` gives; a
    name no loaded library registers fails with "could not instantiate from
    library" and the system is skipped: the robot does not drive, publish or
    sense. A class of another gz-sim library works only if that library
    happens to be loaded first (a warning).

    ## Example
    ```xml
    <plugin filename="gz-sim-joint-state-publisher-system"
            name="gz::sim::systems::JointStatePublish"/>
    ```

    ## Fix
    Write the class the library registers: `name="gz::sim::systems::JointStatePublisher"`.
    """

    code = "G301"
    name = "gz-system-unknown"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for system in systems(ctx):
            if system.stem is None or system.stem not in known.LIBRARIES or "$" in system.name:
                continue
            classes = known.LIBRARIES[system.stem]
            if system.cls in classes:
                continue
            namespace = "ignition::gazebo" if system.name.startswith("ignition") else "gz::sim"
            wanted = [f"{namespace}::systems::{cls}" for cls in classes]
            where = f"plugin[{system.name}]"
            data = {"filename": system.filename, "name": system.name, "classes": wanted}
            if system.cls in known.CLASSES:
                yield self.diagnostic(
                    f"{_label(system)}: '{system.name}' is a class of the "
                    f"'{known.CLASSES[system.cls]}' system library, not of '{system.filename}'; it loads "
                    "only if that library was loaded before",
                    span_of(system.element),
                    severity=Severity.WARNING,
                    element=where,
                    help=f"write name=\"{wanted[0]}\", or the filename of the '{system.cls}' library",
                    data=data,
                )
                continue
            guess = closest(system.name, wanted) or wanted[0]
            yield self.diagnostic(
                f"{_label(system)}: the library registers no class '{system.name}'; did you mean '{guess}'?",
                span_of(system.element),
                element=where,
                help=f'write name="{guess}"',
                data=data,
            )


@register
class SystemLinkMissing(_GzSim):
    """A gz-sim system names a link the model does not have, or one Gazebo merges away.

    ## What it does
    Checks the link parameters of gz-sim systems (`link_name` of LiftDrag,
    AdvancedLiftDrag, BuoyancyEngine, Hydrodynamics, KineticEnergyMonitor,
    TrajectoryFollower and VelocityControl; `link` of TrackController;
    `body_link` of TrackedVehicle; `parent_link` of DetachableJoint; the
    `<wheel link_name>` of WheelSlip) against the model's
    links, with the closest name as a suggestion. In a URDF, a link attached
    by a fixed joint is merged into its parent by sdformat's converter
    unless the joint is preserved: reported as a warning.

    ## Why it matters
    The system looks the link up by name when it is configured and, not
    finding it, logs an error and does nothing: the wing has no lift, the
    hull no drag, the track no motion.

    ## Example
    ```xml
    <plugin filename="gz-sim-lift-drag-system" name="gz::sim::systems::LiftDrag">
      <link_name>wing</link_name>   <!-- the link is "wing_link" -->
    </plugin>
    ```

    ## Fix
    Name the link exactly; for a link behind a fixed joint add
    `<gazebo reference="JOINT"><preserveFixedJoint>true</preserveFixedJoint></gazebo>`.
    """

    code = "G302"
    name = "gz-system-link-missing"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        if not systems(ctx):
            return  # most models: no gz-sim system, so no link named by one
        names = {link.name for link in ctx.robot.links} | _gazebo_links(ctx.robot)
        parents = {joint.child: joint for joint in ctx.robot.joints}
        kept = gazebo.preserved_fixed_joints(ctx)
        urdf = ctx.robot.format in ("urdf", "xacro")
        world = {id(e) for e in ctx.robot.world_plugins}
        for system in systems(ctx):
            if id(system.element) in world:
                continue  # a world's system names links of whichever model it means, not this one's
            for element, text in _link_refs(system):
                where = f"plugin[{system.name}]/{element.tag}[{text}]"
                if text not in names and not any(n.endswith("::" + text) for n in names):
                    yield self.diagnostic(
                        f"{_label(system)} names link '{text}', which the model does not have"
                        + did_you_mean(text, names),
                        span_of(element),
                        element=where,
                        help="use the exact name of one of the model's links",
                        data={"link": text, "plugin": system.name},
                    )
                    continue
                joint = parents.get(text)
                if urdf and joint is not None and joint.type is JointType.FIXED and joint.name not in kept:
                    yield self.diagnostic(
                        f"{_label(system)} names link '{text}', attached by fixed joint '{joint.name}'; "
                        "the URDF converter merges it into its parent, so the system will not find it",
                        span_of(element),
                        severity=Severity.WARNING,
                        element=where,
                        help=f"name the parent link '{joint.parent}', or keep the link with "
                        f'<gazebo reference="{joint.name}"><preserveFixedJoint>true'
                        "</preserveFixedJoint></gazebo>",
                        data={"link": text, "plugin": system.name, "fixed_joint": joint.name},
                    )


def _link_refs(system: known.System) -> Iterator[tuple[Any, str]]:
    """(element, link name) for each link a system's parameters name, in text or attribute."""
    yield from _children(system, system.params.links)
    for tag, attribute in system.params.link_attributes:
        for child in system.element:
            name = (child.get(attribute) or "").strip() if child.tag == tag else ""
            if name and "$" not in name:
                yield child, name


def _gazebo_links(robot: Robot) -> set[str]:
    """Links declared in raw SDF inside reference-less ``<gazebo>`` blocks."""
    return {
        name
        for block in gz.gazebo_blocks(robot)
        if block.get("reference") is None
        for child in block
        if child.tag == "link" and (name := child.get("name"))
    }


@register
class SystemTopicInvalid(_GzSim):
    """A gz-sim system's topic is not a valid gz-transport topic name.

    ## What it does
    Checks the `topic` and `*_topic` parameters of gz-sim's own systems against
    gz-transport's rules: no spaces, no `~`, `@`, `:=` or `//`, and not just
    `/`. ROS habits (`~/cmd_vel`, a topic with a space) are the usual cause.

    ## Why it matters
    gz-sim passes each topic through `TopicUtils::AsValidTopic`, which
    silently rewrites it (spaces to `_`, the forbidden characters dropped; a
    debug-level message is the only trace) or, when nothing valid remains,
    ignores it: the system uses its default topic, or does not start. Either
    way it listens or publishes on a topic other than the one written, and
    nothing sent to the written name (gz-transport cannot even publish to
    it) reaches it.

    ## Example
    ```xml
    <plugin filename="gz-sim-diff-drive-system" name="gz::sim::systems::DiffDrive">
      <topic>~/cmd_vel</topic>   <!-- gz-sim listens on "/cmd_vel" -->
    </plugin>
    ```

    ## Fix
    Write a gz-transport topic: `<topic>/model/robot/cmd_vel</topic>` (or `cmd_vel`).
    """

    code = "G303"
    name = "gz-system-topic-invalid"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for system in systems(ctx):
            if system.kind not in known.CLASSES:
                continue  # a system of the user's own may read its topics another way (ROS names)
            for child in system.element:
                if not isinstance(child.tag, str) or not known.is_topic_tag(child.tag) or len(child):
                    continue
                topic = child.text or ""
                if "$" in topic or not topic.strip():
                    continue  # an unexpanded substitution, or empty (the default topic)
                topic = topic.strip()
                fixed = known.valid_topic(topic)
                if fixed == topic:
                    continue
                becomes = (
                    f"gz-sim uses '{fixed}' instead"
                    if fixed
                    else "gz-sim ignores it (the system uses its default topic, or does not start)"
                )
                yield self.diagnostic(
                    f"{_label(system)}: <{child.tag}> '{topic}' is not a valid gz-transport topic; {becomes}",
                    span_of(child),
                    element=f"plugin[{system.name}]/{child.tag}",
                    help="write a topic without spaces, '~', '@', ':=' or '//'"
                    + (f" (e.g. '{fixed}')" if fixed else ""),
                    data={"topic": topic, "used": fixed or None, "plugin": system.name},
                )


@register
class SystemParameterInvalid(_GzSim):
    """A gz-sim system parameter that must be a number or a flag is not one.

    ## What it does
    Reads the numeric parameters of DiffDrive (`wheel_separation`,
    `wheel_radius`, `odom_publish_frequency`, velocity, acceleration and jerk
    limits), JointPositionController and JointController (the PID gains and
    limits `p_gain`, `i_gain`, `d_gain`, `i_max`, `i_min`, `cmd_max`,
    `cmd_min`, `cmd_offset`, `initial_position`, `joint_index`), and
    JointStatePublisher (`update_rate`), and their true/false flags
    (`use_velocity_commands`, `use_force_commands`, `use_actuator_msg`), and
    reports values that do not read as such, and a wheel separation or
    radius that is not positive.

    ## Why it matters
    sdformat either cannot convert the text (it logs an error and the system
    runs with the parameter's default) or reads only its leading digits
    (`0,01` as 0): a position controller with the wrong gains (a limp or
    oscillating joint), a drive whose odometry uses the wrong wheel size.

    ## Example
    ```xml
    <plugin filename="gz-sim-joint-position-controller-system"
            name="gz::sim::systems::JointPositionController">
      <joint_name>j1</joint_name> <p_gain>1O0</p_gain>   <!-- letter O -->
    </plugin>
    ```

    ## Fix
    Write the number (`<p_gain>100</p_gain>`), or `true`/`false` for a flag.
    """

    code = "G304"
    name = "gz-system-parameter-invalid"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for system in systems(ctx):
            params = system.params
            kinds = (
                ("a number", params.numbers),
                ("an integer", params.integers),
                ("true or false", params.flags),
            )
            for what, tags in kinds:
                for element, text in _children(system, tags):
                    problem = _problem(text, what, element.tag in params.positive)
                    if problem is None:
                        continue
                    yield self.diagnostic(
                        f"{_label(system)}: <{element.tag}> '{text}' {problem}",
                        span_of(element),
                        element=f"plugin[{system.name}]/{element.tag}",
                        help=f"write {what}" + (" above zero" if element.tag in params.positive else ""),
                        data={"parameter": element.tag, "value": text, "plugin": system.name},
                    )


def _problem(text: str, what: str, positive: bool) -> str | None:
    if what == "true or false":
        return None if text.lower() in _TRUE_FALSE else "is not true or false"
    try:
        value = int(text) if what == "an integer" else float(text)
    except ValueError:
        return f"is not {what}"
    if positive and not value > 0:
        return "must be above zero"
    return None


@register
class RenderEngineUnknown(_GzSim):
    """The gz-sim Sensors system names a render engine gz-rendering does not know.

    ## What it does
    Checks the `render_engine` of the Sensors system (`gz::sim::systems::Sensors`,
    usually a world plugin) against the engines gz-rendering loads by name:
    `ogre2` (the default), `ogre` and `optix`. A name close to one of them
    (`orge2`, `Ogre2`) is an error; another name is a warning, since
    gz-rendering also loads a render-engine plugin library by its name.

    ## Why it matters
    The engine fails to load and no rendering sensor (camera, depth camera,
    GPU lidar, thermal camera) produces data; the rest of the simulation runs,
    so the missing images are noticed late.

    ## Example
    ```xml
    <plugin filename="gz-sim-sensors-system" name="gz::sim::systems::Sensors">
      <render_engine>orge2</render_engine>
    </plugin>
    ```

    ## Fix
    Write `ogre2` (or `ogre` on machines without OpenGL 3.3).
    """

    code = "G305"
    name = "gz-render-engine-unknown"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for system in systems(ctx):
            if system.kind != "Sensors":
                continue
            for element, text in _children(system, frozenset({"render_engine"})):
                if text in known.RENDER_ENGINES or "rendering" in text:
                    continue  # a name, or a render-engine library (gz-rendering-ogre2)
                guess = closest(text.lower(), known.RENDER_ENGINES)
                yield self.diagnostic(
                    f"{_label(system)}: render engine '{text}' is not one gz-rendering ships"
                    + (f"; did you mean '{guess}'?" if guess else ""),
                    span_of(element),
                    severity=None if guess else Severity.WARNING,
                    element=f"plugin[{system.name}]/render_engine",
                    help=f"write <render_engine>{guess or 'ogre2'}</render_engine>"
                    + ("" if guess else ", or make sure the engine's plugin is on GZ_RENDERING_PLUGIN_PATH"),
                    data={"render_engine": text, "suggestion": guess},
                )


@register
class Ros2ControlPluginMismatch(_GzSim):
    """A simulator's ros2_control plugin has no `<ros2_control>` block, or a block for the other simulator.

    ## What it does
    In a URDF with gz-sim's ros2_control system (`gz_ros2_control-system`,
    `ign_ros2_control-system`) or classic Gazebo's (`libgazebo_ros2_control.so`),
    reports a robot with no `<ros2_control>` block, and a block whose
    hardware is the other simulator's (`gazebo_ros2_control/GazeboSystem`
    under gz-sim, `gz_ros2_control/GazeboSimSystem` under classic Gazebo)
    when no plugin of that simulator is present. (That the plugin's
    `<parameters>` file exists is `ros2-control-parameters-missing`, G106.)

    ## Why it matters
    The plugin reads the robot description for `<ros2_control>` blocks and
    loads each block's hardware class through its own plugin loader: with no
    block it stops ("no ros2_control tag"); a class of the other simulator
    fails to load, and the joints of that block are never simulated or
    commanded.

    ## Example
    ```xml
    <ros2_control name="GazeboSystem" type="system">
      <hardware><plugin>gazebo_ros2_control/GazeboSystem</plugin></hardware> ...
    </ros2_control>
    <gazebo>
      <plugin filename="gz_ros2_control-system" name="gz_ros2_control::GazeboSimROS2ControlPlugin"/>
    </gazebo>
    ```

    ## Fix
    Use the hardware of the simulator the plugin belongs to
    (`gz_ros2_control/GazeboSimSystem` for gz-sim), and put the
    `<ros2_control>` block in the same robot description.
    """

    code = "G306"
    name = "gz-ros2-control-mismatch"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        if ctx.robot.format not in ("urdf", "xacro") or not ctx.robot.links:
            return
        found = [(p, f) for p in gazebo.plugins(ctx) if (f := known.ros2_control_flavour(p)) is not None]
        if not found:
            return
        blocks = rc.blocks(ctx)
        if not blocks:
            plugin = found[0][0]
            yield self.diagnostic(
                f"{gz.plugin_label(plugin)} loads ros2_control, but the robot has no <ros2_control> block",
                span_of(plugin),
                element=f"plugin[{plugin.get('name')}]",
                help="add a <ros2_control> block with the simulator's hardware "
                "(gz_ros2_control/GazeboSimSystem) and the joints it commands",
            )
            return
        flavours = {f for _, f in found}
        for block in blocks:
            other = _hardware_flavour(block.plugin)
            if other is None or other in flavours:
                continue
            plugin, flavour = found[0]
            right = (
                "gz_ros2_control/GazeboSimSystem" if flavour == "gz" else "gazebo_ros2_control/GazeboSystem"
            )
            element = next((c for c in block.element if c.tag == "hardware"), block.element)
            yield self.diagnostic(
                f"ros2_control '{block.name}' uses hardware '{block.plugin}' of "
                f"{'classic Gazebo' if other == 'classic' else 'gz-sim'}, but the robot loads ros2_control "
                f"with {gz.plugin_label(plugin)}, which cannot load that hardware",
                span_of(element),
                element=f"ros2_control[{block.name}]/hardware",
                help=f"write <plugin>{right}</plugin>",
                data={"hardware": block.plugin, "plugin": plugin.get("filename")},
            )


def _hardware_flavour(hardware: str | None) -> str | None:
    if hardware in known.GZ_HARDWARE:
        return "gz"
    if hardware in known.CLASSIC_HARDWARE:
        return "classic"
    return None
