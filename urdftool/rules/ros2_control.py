"""ros2_control blocks (G1xx): hardware, interfaces, limits, duplicates, mimic joints, parameter files.

Joint names of ``<ros2_control>`` blocks (missing, or fixed) are checked by
``transmission-joint-missing`` (G002) in :mod:`urdftool.rules.gazebo`; the rules
here check the rest of each block, read by :mod:`urdftool.facts.ros2_control`.
Decisions are in ``docs/ros2_control.md``.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.catalogue.suggest import closest
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts import gazebo
from urdftool.facts import ros2_control as rc
from urdftool.facts.context import CheckContext
from urdftool.model import JointType
from urdftool.parse.locate import span_of

#: Hardware component types the resource manager accepts.
BLOCK_TYPES = frozenset({"system", "actuator", "sensor"})
#: Relative slack when comparing a parameter with a URDF limit (values are often rounded).
SLACK = 1e-6


class _Ros2Control(Rule):
    family = Family.GAZEBO


def _fmt(value: float) -> str:
    return f"{value:.6g}"


@register
class HardwareMissing(_Ros2Control):
    """A `<ros2_control>` block has no hardware plugin, a wrong type, or sits where nobody reads it.

    ## What it does
    Checks that every `<ros2_control>` block has `type` `system`, `actuator`
    or `sensor` and a `<hardware><plugin>` naming the hardware class, and
    reports `<ros2_control>` blocks nested inside `<gazebo>`, where the
    controller manager does not look.

    ## Why it matters
    The controller manager parses every block at start-up and stops on a
    block without a plugin or with an unknown type; a block inside
    `<gazebo>` is never seen ("ros2_control tag not recognized"), so no
    interface is exported and every controller fails to activate.

    ## Example
    ```xml
    <ros2_control name="Arm" type="system">
      <joint name="joint1"> <command_interface name="position"/> </joint>
    </ros2_control>
    ```

    ## Fix
    Add the hardware: `<hardware><plugin>mock_components/GenericSystem</plugin></hardware>`
    (or the robot's driver, or `gz_ros2_control/GazeboSimSystem`), and move
    the block to the top level of `<robot>`.
    """

    code = "G101"
    name = "ros2-control-hardware-missing"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for block in rc.blocks(ctx):
            where = f"ros2_control[{block.name}]"
            if block.type is not None and block.type.lower() not in BLOCK_TYPES:
                yield self.diagnostic(
                    f"ros2_control '{block.name}' has type '{block.type}'; the resource manager knows "
                    "system, actuator and sensor",
                    span_of(block.element),
                    element=where,
                    help='write type="system" (or actuator, sensor)',
                    data={"type": block.type},
                )
            if block.plugin is None:
                yield self.diagnostic(
                    f"ros2_control '{block.name}' names no hardware plugin",
                    span_of(block.element),
                    element=where,
                    help="add <hardware><plugin>…</plugin></hardware>: the driver's class, "
                    "mock_components/GenericSystem, or gz_ros2_control/GazeboSimSystem",
                    data={"block": block.name},
                )
        for gazebo_block in gazebo.gazebo_blocks(ctx):
            for nested in gazebo_block.iter("ros2_control"):
                yield self.diagnostic(
                    f"ros2_control '{nested.get('name') or 'unnamed'}' is inside <gazebo>; the "
                    "controller manager reads only top-level <ros2_control> blocks",
                    span_of(nested),
                    element="gazebo/ros2_control",
                    help="move the block to the top level of <robot>",
                )


@register
class InterfaceUnknown(_Ros2Control):
    """A ros2_control interface name looks like a misspelt standard one, or a simulator cannot bind it.

    ## What it does
    Checks the `name` of every `<command_interface>` and `<state_interface>`
    of a joint against the standard interfaces (`position`, `velocity`,
    `effort`, `acceleration`) and the names ros2_control's sensors and
    broadcasters use (`force.x`, `orientation.w`, …). A name close to one of
    them (`postion`, `Velocity`) is reported with the likely one. In a block
    whose hardware is Gazebo's or gz-sim's, a joint command interface other
    than position, velocity or effort is reported too: the simulator binds
    nothing to it.

    ## Why it matters
    Custom interface names are allowed, so nothing refuses a typo: the
    hardware exports `postion`, the controller asks for `position`, and the
    controller fails to activate with a missing-interface error at launch.

    ## Example
    ```xml
    <joint name="joint1"> <command_interface name="postion"/> </joint>
    ```

    ## Fix
    Use the standard name: `<command_interface name="position"/>`.
    """

    code = "G102"
    name = "ros2-control-interface-unknown"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for block in rc.blocks(ctx):
            for component in block.joints():
                for kind, interfaces in (("command", component.command), ("state", component.state)):
                    for interface in interfaces:
                        yield from self._one(block, component.name, kind, interface)

    def _one(self, block: rc.Block, joint: str, kind: str, interface: rc.Interface) -> Iterator[Diagnostic]:
        name = interface.name
        if not name or "$" in name or name in rc.KNOWN_INTERFACES:
            return
        where = f"ros2_control[{block.name}]/joint[{joint}]/{kind}_interface[{name}]"
        match = closest(name.lower(), rc.STANDARD_INTERFACES) if name.lower() != name else None
        match = match or closest(name, rc.STANDARD_INTERFACES)
        if match is not None:
            yield self.diagnostic(
                f"joint '{joint}' in ros2_control '{block.name}': {kind} interface '{name}' is not a "
                f"standard interface; did you mean '{match}'?",
                span_of(interface.element),
                element=where,
                help=f'write <{kind}_interface name="{match}"/>',
                data={"interface": name, "suggestion": match},
            )
        elif block.simulated and kind == "command":
            yield self.diagnostic(
                f"joint '{joint}' in ros2_control '{block.name}': the simulator's hardware "
                f"({block.plugin}) binds only position, velocity and effort commands; '{name}' does "
                "nothing",
                span_of(interface.element),
                element=where,
                help="command position, velocity or effort in simulation",
                data={"interface": name},
            )


@register
class LimitsMismatch(_Ros2Control):
    """A ros2_control `min`, `max` or `initial_value` lies outside the joint's URDF `<limit>`.

    ## What it does
    For each joint of a `<ros2_control>` block, compares the `min` and `max`
    parameters of its position, velocity and effort command interfaces with
    the joint's `<limit>` (`lower`/`upper`, `velocity`, `effort`), and the
    `initial_value` of its interfaces with the position limits. A `min` or
    `max` that is the URDF limit rounded to the decimals it is written with
    (two or more: `-2.793` for `-2.7925268`) agrees with it. Also reports
    `min` above `max` and values that are not numbers.

    ## Why it matters
    The two files disagree about what the joint may do: commands the URDF
    calls impossible pass the hardware's clamp (or the hardware clamps inside
    the range a planner uses), and a joint that starts outside its limits
    makes limit enforcement and trajectory controllers refuse or jump at
    start-up.

    ## Example
    ```xml
    <joint name="joint1" type="revolute"> <limit lower="-1.57" upper="1.57" .../> </joint>
    <command_interface name="position">
      <param name="min">-3.14</param> <param name="max">3.14</param>
    </command_interface>
    ```

    ## Fix
    Write the URDF's limits in the ros2_control block (xacro properties
    shared by both keep them together).
    """

    code = "G103"
    name = "ros2-control-limits-mismatch"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for block in rc.blocks(ctx):
            for component in block.joints():
                joint = ctx.robot.joint(component.name)
                if joint is None or joint.limit is None:
                    continue
                for interface in (*component.command, *component.state):
                    yield from self._interface(block, component.name, joint.type, joint.limit, interface)

    def _number(
        self, interface: rc.Interface, param: str, joint: str
    ) -> tuple[float | None, Diagnostic | None]:
        text = interface.param_text(param)
        if text is None or not text or "$" in text:
            return None, None
        try:
            return float(text), None
        except ValueError:
            return None, self.diagnostic(
                f"joint '{joint}': {interface.name} {param} '{text}' is not a number",
                span_of(interface.params[param]),
                element=f"joint[{joint}]/{interface.name}/{param}",
                help="write a number",
            )

    def _interface(
        self, block: rc.Block, joint: str, jtype: JointType, limit: object, interface: rc.Interface
    ) -> Iterator[Diagnostic]:
        values: dict[str, float] = {}
        for param in ("min", "max", "initial_value"):
            value, problem = self._number(interface, param, joint)
            if problem is not None:
                yield problem
            if value is not None:
                values[param] = value
        bounds = _bounds(interface.name, jtype, limit)
        if "min" in values and "max" in values and values["min"] > values["max"]:
            yield self._finding(
                joint,
                interface,
                "min",
                f"min {_fmt(values['min'])} is above max {_fmt(values['max'])}",
                "swap them",
            )
        if bounds is not None:
            low, high, what = bounds
            for param in ("min", "max"):
                value = values.get(param)
                if value is not None and _outside(value, low, high) and not _rounded(
                    interface.param_text(param) or "", low if param == "min" else high
                ):
                    yield self._finding(
                        joint,
                        interface,
                        param,
                        f"{interface.name} {param} {_fmt(value)} is outside the URDF {what} "
                        f"[{_fmt(low)}, {_fmt(high)}]",
                        f"write the URDF limit ({_fmt(low if param == 'min' else high)}), or change the "
                        "<limit>",
                    )
        position = _bounds("position", jtype, limit)
        value = values.get("initial_value")
        if interface.name == "position" and position is not None and value is not None:
            low, high, what = position
            if _outside(value, low, high):
                yield self._finding(
                    joint,
                    interface,
                    "initial_value",
                    f"initial position {_fmt(value)} is outside the URDF {what} [{_fmt(low)}, {_fmt(high)}]",
                    "start the joint inside its limits",
                )

    def _finding(self, joint: str, interface: rc.Interface, param: str, what: str, fix: str) -> Diagnostic:
        return self.diagnostic(
            f"joint '{joint}': {what}",
            span_of(interface.params[param]),
            element=f"joint[{joint}]/{interface.name}/{param}",
            help=fix,
            data={"joint": joint, "interface": interface.name, "param": param},
        )


def _bounds(interface: str, jtype: JointType, limit: object) -> tuple[float, float, str] | None:
    lower, upper = getattr(limit, "lower", None), getattr(limit, "upper", None)
    if interface == "position":
        if jtype not in (JointType.REVOLUTE, JointType.PRISMATIC) or lower is None or upper is None:
            return None
        return (lower, upper, "position limits") if lower < upper else None
    for name in ("velocity", "effort"):
        value = getattr(limit, name, None)
        if interface == name and value is not None and value > 0:
            return (-value, value, f"{name} limit")
    return None


def _rounded(text: str, bound: float) -> bool:
    """Whether *text* is *bound* rounded to the decimals *text* writes (two or more): Spot's
    ros2_control block writes the URDF's -2.79252680 rad as -2.793."""
    mantissa, _, rest = text.strip().partition(".")
    if not rest.isdigit() or len(rest) < 2 or not mantissa.lstrip("+-").isdigit():
        return False
    return abs(float(text) - bound) <= 0.5 * 10.0 ** -len(rest) * (1 + 1e-9)


def _outside(value: float, low: float, high: float) -> bool:
    slack = SLACK * max(1.0, abs(low), abs(high))
    return math.isfinite(value) and (value < low - slack or value > high + slack)


@register
class JointDuplicated(_Ros2Control):
    """The same joint interface is exported twice by ros2_control blocks.

    ## What it does
    Reports a joint declared by two `<joint>` elements, in one `<ros2_control>`
    block or in two hardware blocks, that export the same command or state
    interface. A joint split between blocks (an actuator block commanding it,
    a sensor block reading its position, as in modular hardware) is not
    reported.

    ## Why it matters
    Each block exports `JOINT/INTERFACE` names into one resource manager; the
    second export of the same name makes the controller manager fail at
    start-up ("already exists"), and two hardware components would fight
    over the joint anyway.

    ## Example
    ```xml
    <ros2_control name="Arm" type="system"> <joint name="joint1">…</joint> </ros2_control>
    <ros2_control name="Gripper" type="system"> <joint name="joint1">…</joint> </ros2_control>
    ```

    ## Fix
    Export each interface of a joint from one block only.
    """

    code = "G104"
    name = "ros2-control-joint-duplicated"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        # (joint, "command"|"state", interface) -> the block and component that export it first
        first: dict[tuple[str, str, str], tuple[rc.Block, rc.Component]] = {}
        for block in rc.blocks(ctx):
            for component in block.joints():
                if not component.name or "$" in component.name:
                    continue
                clash: tuple[rc.Block, list[str]] | None = None
                for kind, interfaces in (("command", component.command), ("state", component.state)):
                    for interface in interfaces:
                        key = (component.name, kind, interface.name)
                        earlier, original = first.setdefault(key, (block, component))
                        if original is not component:
                            clash = clash or (earlier, [])
                            clash[1].append(f"{kind} '{interface.name}'")
                if clash is None:
                    continue
                earlier = clash[0]
                where = (
                    "again in the same block"
                    if earlier is block
                    else f"also in ros2_control '{earlier.name}'"
                )
                yield self.diagnostic(
                    f"joint '{component.name}' in ros2_control '{block.name}' is declared {where}, "
                    f"with the same interfaces ({', '.join(clash[1])})",
                    span_of(component.element),
                    element=f"ros2_control[{block.name}]/joint[{component.name}]",
                    help="export each interface of a joint from one hardware block only",
                    data={
                        "joint": component.name,
                        "blocks": [earlier.name, block.name],
                        "interfaces": clash[1],
                    },
                )


@register
class MimicInconsistent(_Ros2Control):
    """A ros2_control joint's mimic declaration disagrees with the URDF.

    ## What it does
    Reports a ros2_control `<joint mimic="true">` whose URDF joint has no
    `<mimic>`, a `<param name="mimic">` naming a joint the robot does not
    have, and a `<param name="mimic">` naming another joint than the URDF's
    `<mimic joint>`.

    ## Why it matters
    ros2_control (Jazzy and later) refuses a `mimic="true"` joint that is not
    a mimic joint in the URDF; mock hardware and the Gazebo systems copy the
    position from the joint the parameter names, so a wrong name leaves the
    joint still or makes it follow the wrong joint.

    ## Example
    ```xml
    <joint name="finger_right" type="prismatic"> <mimic joint="finger_left"/> ... </joint>
    <joint name="finger_right"> <param name="mimic">finger_lft</param> ... </joint>
    ```

    ## Fix
    Name the URDF's mimicked joint, or add the `<mimic>` to the URDF joint.
    """

    code = "G105"
    name = "ros2-control-mimic-inconsistent"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        blocks = rc.blocks(ctx)
        if not blocks:
            return  # most models: no <ros2_control>, and no joint to look up
        joints = {joint.name: joint for joint in ctx.robot.joints}
        for block in blocks:
            for component in block.joints():
                joint = joints.get(component.name)
                if joint is None:
                    continue  # transmission-joint-missing reports it
                where = f"ros2_control[{block.name}]/joint[{component.name}]"
                flag = (component.element.get("mimic") or "").strip().lower()
                if flag == "true" and joint.mimic is None:
                    yield self.diagnostic(
                        f"joint '{component.name}' is marked mimic=\"true\" in ros2_control '{block.name}', "
                        "but the URDF joint has no <mimic>",
                        span_of(component.element),
                        element=where,
                        help='add <mimic joint="…"/> to the URDF joint, or drop mimic="true"',
                    )
                param = component.params.get("mimic")
                target = (param.text or "").strip() if param is not None else ""
                if not target or "$" in target:
                    continue
                if target not in joints:
                    yield self.diagnostic(
                        f"joint '{component.name}': mimic parameter names joint '{target}', which the "
                        "robot does not have",
                        span_of(param),
                        element=f"{where}/param[mimic]",
                        help="name the joint it follows",
                        data={"joint": component.name, "mimic": target},
                    )
                elif joint.mimic is not None and joint.mimic.joint != target:
                    yield self.diagnostic(
                        f"joint '{component.name}': mimic parameter says '{target}', the URDF <mimic> says "
                        f"'{joint.mimic.joint}'",
                        span_of(param),
                        severity=Severity.WARNING,
                        element=f"{where}/param[mimic]",
                        help=f"write '{joint.mimic.joint}'",
                        data={"joint": component.name, "mimic": target, "urdf": joint.mimic.joint},
                    )


@register
class ParametersMissing(_Ros2Control):
    """A Gazebo ros2_control plugin's `<parameters>` names a file that does not exist.

    ## What it does
    Resolves the `<parameters>` of `gazebo_ros2_control`, `gz_ros2_control`
    and `ign_ros2_control` plugins (`package://` URIs and absolute paths,
    which is what `$(find pkg)` becomes) and reports those that name no file.
    A `$(find pkg)/…` path that does not exist in a source tree is looked for
    where the package's ament install rule takes it from (`bringup/config`
    installed as `config`). Relative paths are read by Gazebo from its working directory, which a
    static check cannot know, so they are not reported.

    ## Why it matters
    The plugin starts the controller manager without the file: no
    controller is configured and spawning them fails at launch.

    ## Example
    ```xml
    <plugin filename="gz_ros2_control-system" name="gz_ros2_control::GazeboSimROS2ControlPlugin">
      <parameters>package://my_robot/config/controler.yaml</parameters>
    </plugin>
    ```

    ## Fix
    Name the controllers file that exists (the package's `config/` folder usually holds it).
    """

    code = "G106"
    name = "ros2-control-parameters-missing"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        found = rc.controllers(ctx)
        if found is None:
            return
        for text, span, tried in found.missing:
            yield self.diagnostic(
                f"ros2_control plugin parameters '{text}' name no file",
                span,
                element="plugin/parameters",
                help="name an existing controllers YAML; looked in: " + ", ".join(tried[:3]),
                data={"parameters": text, "tried": list(tried)},
            )
