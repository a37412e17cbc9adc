"""The robot's ``<ros2_control>`` blocks, read once, and the controllers YAML beside them.

The URDF reader keeps every top-level ``<ros2_control>`` as an lxml element;
:func:`blocks` reads them into :class:`Block` values (hardware plugin, joints,
sensors and GPIOs with their command and state interfaces and parameters),
each keeping its element so a finding is located where the block was written
(in the ``.xacro`` when it came from one). The controllers YAML is read by the
pipeline (``check --controllers FILE``, or the file a Gazebo ros2_control
plugin's ``<parameters>`` names; see :mod:`urdftool.pipeline.controllers`) and
handed to the rules through the run's options under :data:`OPTION`.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import field
from typing import Any

from urdftool.facts.context import CONTROLLERS_OPTION, CheckContext
from urdftool.parse.controllers import Controller, Controllers, Value
from urdftool.records import record

#: Key of the run's options that holds the :class:`Controllers`.
OPTION = CONTROLLERS_OPTION

#: The interface names hardware_interface defines
#: (``hardware_interface/types/hardware_interface_type_values.hpp``).
STANDARD_INTERFACES = frozenset({"position", "velocity", "effort", "acceleration"})
#: Further interface names that ros2_control's own components and broadcasters export
#: (IMU and force/torque semantic components, GPIO and mock hardware conventions).
#: The state interfaces of ros2_control's IMU and force/torque semantic components, which
#: gz_ros2_control binds for its gz sensors (``GazeboSimSystem::registerSensors``).
IMU_INTERFACES = (
    "orientation.x",
    "orientation.y",
    "orientation.z",
    "orientation.w",
    "angular_velocity.x",
    "angular_velocity.y",
    "angular_velocity.z",
    "linear_acceleration.x",
    "linear_acceleration.y",
    "linear_acceleration.z",
)
FORCE_TORQUE_INTERFACES = ("force.x", "force.y", "force.z", "torque.x", "torque.y", "torque.z")
KNOWN_INTERFACES = (
    STANDARD_INTERFACES
    | frozenset(IMU_INTERFACES)
    | frozenset(FORCE_TORQUE_INTERFACES)
    | frozenset({"jerk", "current", "temperature", "voltage", "mechanical_power", "torque_current"})
)
#: Interfaces the Gazebo ros2_control systems (gazebo_ros2_control's GazeboSystem,
#: gz_ros2_control's GazeboSimSystem / IgnitionSystem) bind to a simulated joint;
#: any other joint command interface is ignored by them.
SIM_JOINT_INTERFACES = frozenset({"position", "velocity", "effort"})


@record
class Interface:
    """A ``<command_interface>`` or ``<state_interface>`` with its ``<param>``s."""

    name: str
    element: Any
    params: dict[str, Any] = field(default_factory=dict)

    def param_text(self, name: str) -> str | None:
        element = self.params.get(name)
        return (element.text or "").strip() if element is not None else None


@record
class Component:
    """A ``<joint>``, ``<sensor>`` or ``<gpio>`` of a hardware block."""

    kind: str
    name: str
    element: Any
    command: tuple[Interface, ...] = ()
    state: tuple[Interface, ...] = ()
    params: dict[str, Any] = field(default_factory=dict)


@record
class Block:
    """One ``<ros2_control name type>`` block."""

    name: str
    type: str | None
    element: Any
    plugin: str | None
    components: tuple[Component, ...] = ()
    #: ``<param>``s of ``<hardware>``
    hardware_params: dict[str, Any] = field(default_factory=dict)

    def joints(self) -> Iterator[Component]:
        return (c for c in self.components if c.kind == "joint")

    @property
    def simulated(self) -> bool:
        """A Gazebo classic or gz-sim hardware plugin, which binds interfaces to simulated joints."""
        plugin = (self.plugin or "").lower()
        return any(key in plugin for key in ("gazebo", "gz_ros2_control", "ign_ros2_control", "ignition"))


def controllers(ctx: CheckContext) -> Controllers | None:
    value = ctx.options.get(OPTION)
    return value if isinstance(value, Controllers) else None


def controller_list(ctx: CheckContext) -> list[Controller]:
    """The controllers of the model's controllers YAML files that can run on this robot.

    One file may hold the controllers of several robots, each in its controller manager's
    namespace (ros2_control_demos example 15: `/rrbot_1/forward_position_controller` and
    `/rrbot_2/forward_position_controller`, whose joints carry each robot's prefix). Which
    namespace the model is started in is the launch file's choice, so when a file places
    controllers in two or more namespaces only those of the namespaces whose parameters name the
    most joints of this robot are kept (all of them when none names any); controllers under a
    wildcard namespace run in any namespace and are always kept.
    """
    key = ("ros2_control-controllers",)
    if key not in ctx.cache:
        found = controllers(ctx)
        joints = {joint.name for joint in ctx.robot.joints}
        ctx.cache[key] = [
            controller
            for config in (found.configs if found else [])
            for controller in _for_robot(config.controllers, joints)
        ]
    return ctx.cache[key]  # type: ignore[no-any-return]


def _names(value: Value) -> Iterator[str]:
    """Every string a parameter value holds (a scalar, or the items of a list)."""
    if isinstance(value.value, list):
        for item in value.value:
            yield from _names(item)
    elif isinstance(value.value, str):
        yield value.value


def _for_robot(found: list[Controller], joints: set[str]) -> list[Controller]:
    spaces = {c.namespace for c in found if "*" not in c.namespace}
    if len(spaces) < 2:
        return found
    fit = dict.fromkeys(spaces, 0)
    for controller in found:
        if controller.namespace in fit:
            fit[controller.namespace] += sum(
                name in joints for value in controller.params.values() for name in _names(value)
            )
    best = max(fit.values())
    return [c for c in found if best == 0 or fit.get(c.namespace, best) == best]


def _text(element: Any) -> str:
    return (element.text or "").strip()


def _params(element: Any) -> dict[str, Any]:
    return {p.get("name"): p for p in element if p.tag == "param" and p.get("name")}


def _interfaces(element: Any, tag: str) -> tuple[Interface, ...]:
    return tuple(
        Interface(child.get("name") or "", child, _params(child)) for child in element if child.tag == tag
    )


def read_block(element: Any) -> Block:
    hardware = next((c for c in element if c.tag == "hardware"), None)
    plugin = None
    hardware_params: dict[str, Any] = {}
    if hardware is not None:
        found = next((c for c in hardware if c.tag in ("plugin", "classType")), None)
        plugin = _text(found) if found is not None and _text(found) else None
        hardware_params = _params(hardware)
    components = tuple(
        Component(
            child.tag,
            child.get("name") or "",
            child,
            _interfaces(child, "command_interface"),
            _interfaces(child, "state_interface"),
            _params(child),
        )
        for child in element
        if child.tag in ("joint", "sensor", "gpio")
    )
    return Block(
        element.get("name") or "unnamed", element.get("type"), element, plugin, components, hardware_params
    )


def blocks(ctx: CheckContext) -> list[Block]:
    """The robot's top-level ``<ros2_control>`` blocks, read once per model."""
    key = ("ros2_control-blocks",)
    if key not in ctx.cache:
        ctx.cache[key] = [
            read_block(e.element)
            for e in ctx.robot.extensions
            if e.tag == "ros2_control" and e.element is not None
        ]
    return ctx.cache[key]  # type: ignore[no-any-return]


def exported(ctx: CheckContext) -> dict[str, tuple[set[str], set[str]]]:
    """Joint name -> (command interface names, state interface names), over every block."""
    out: dict[str, tuple[set[str], set[str]]] = {}
    for block in blocks(ctx):
        for component in block.components:
            command, state = out.setdefault(component.name, (set(), set()))
            command.update(i.name for i in component.command)
            state.update(i.name for i in component.state)
    return out
