"""ros2_control sensors (G107, G108): what a `<sensor>` of a `<ros2_control>` block binds to.

ros2_control itself lets a sensor component take any name and export any state
interface; the names matter to whoever reads them. gz_ros2_control
(``GazeboSimSystem::registerSensors``) binds a ros2_control sensor to the gz-sim
IMU or force/torque sensor *of the same name* and looks each state interface up
in a fixed table (throwing on any other name). ``<gpio>`` names are free-form
and are not checked. Decisions are in ``docs/ros2_control.md``.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterator

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.catalogue.suggest import did_you_mean
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts import gazebo
from urdftool.facts import ros2_control as rc
from urdftool.facts.context import CheckContext
from urdftool.parse.locate import span_of
from urdftool.rules import gazebo_plugins as gz
from urdftool.rules import gz_systems_known as known

#: The state interfaces of ros2_control's IMU and force/torque semantic components.
SENSOR_STANDARD = frozenset(known.IMU_INTERFACES) | frozenset(known.FORCE_TORQUE_INTERFACES)


#: How alike a name must be to a standard one to be called a typo of it (difflib ratio): custom
#: names (`pos_x`, `force`) stay quiet, `force_x`, `orientaton.x`, `linear_accel.x` do not.
TYPO_CUTOFF = 0.8


def _typo_of(name: str) -> str | None:
    """The standard sensor interface *name* misspells, or ``None`` (every standard name ends in
    an axis, so a name that does not is a custom one)."""
    if name[-1:].lower() not in ("x", "y", "z", "w"):
        return None
    for candidate in (
        name.lower()
        .replace("_", ".")
        .replace("angular.velocity", "angular_velocity")
        .replace("linear.acceleration", "linear_acceleration"),
        name,
    ):
        found = difflib.get_close_matches(candidate, sorted(SENSOR_STANDARD), n=1, cutoff=TYPO_CUTOFF)
        if found:
            return found[0]
    return None


class _Sensors(Rule):
    family = Family.GAZEBO


def gazebo_sensors(ctx: CheckContext) -> dict[str, str]:
    """Sensor name -> SDF type, for every ``<sensor>`` inside the robot's ``<gazebo>`` blocks; read
    once per model (every ros2_control sensor asks)."""
    key = ("gazebo-sensors",)
    if key not in ctx.cache:
        out: dict[str, str] = {}
        for block in gazebo.gazebo_blocks(ctx):
            for sensor in block.iter("sensor"):
                name = (sensor.get("name") or "").strip()
                if name:
                    out.setdefault(name, (sensor.get("type") or "").strip().replace("-", "_"))
        ctx.cache[key] = out
    return ctx.cache[key]  # type: ignore[no-any-return]


def bound_type(ctx: CheckContext, block: rc.Block, sensor: rc.Component) -> str | None:
    """``imu`` or ``force_torque`` when gz_ros2_control binds *sensor* to a gz sensor, else ``None``."""
    if block.plugin not in known.GZ_HARDWARE:
        return None
    kind = gazebo_sensors(ctx).get(sensor.name)
    return kind if kind in known.SENSOR_INTERFACES else None


def _sensors(block: rc.Block) -> Iterator[rc.Component]:
    return (c for c in block.components if c.kind == "sensor" and c.name and "$" not in c.name)


@register
class SensorUnknown(_Sensors):
    """A ros2_control `<sensor>` names no sensor the simulator has, or a `frame_id` that is not a link.

    ## What it does
    In a `<ros2_control>` block whose hardware is gz-sim's
    (`gz_ros2_control/GazeboSimSystem`, `ign_ros2_control/IgnitionSystem`),
    checks that each `<sensor name>` is the name of an `imu` or
    `force_torque` `<sensor>` in the robot's `<gazebo>` blocks, with the
    closest name as a suggestion. For any hardware, checks that a sensor's
    `frame_id` parameter names a link. Sensor names of real hardware are
    free-form and not checked.

    ## Why it matters
    gz_ros2_control binds a ros2_control sensor to the gz-sim sensor of the
    same name, and only IMUs and force/torque sensors: under any other name
    the sensor exports nothing in simulation, and the IMU or force/torque
    broadcaster that reads it fails to activate. A shared description may
    declare a sensor that is simply not simulated, so this is a warning. A
    `frame_id` that is no link puts the readings in a frame TF does not know.

    ## Example
    ```xml
    <gazebo reference="imu_link"> <sensor name="imu_sensor" type="imu">…</sensor> </gazebo>
    <ros2_control name="GazeboSimSystem" type="system">
      <hardware><plugin>gz_ros2_control/GazeboSimSystem</plugin></hardware>
      <sensor name="imu"> <state_interface name="orientation.x"/> … </sensor>
    </ros2_control>
    ```

    ## Fix
    Give the ros2_control sensor the gz sensor's name (`<sensor name="imu_sensor">`),
    and its `frame_id` the link it is mounted on.
    """

    code = "G107"
    name = "ros2-control-sensor-unknown"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        blocks = rc.blocks(ctx)
        if not blocks:
            return
        simulated = gazebo_sensors(ctx)
        links = {link.name for link in ctx.robot.links}
        for block in blocks:
            for sensor in _sensors(block):
                where = f"ros2_control[{block.name}]/sensor[{sensor.name}]"
                if block.plugin in known.GZ_HARDWARE and bound_type(ctx, block, sensor) is None:
                    yield self._unbound(block, sensor, simulated, where)
                frame = sensor.params.get("frame_id")
                text = gz.text_of(frame) if frame is not None else ""
                if text and "$" not in text and text not in links:
                    yield self.diagnostic(
                        f"sensor '{sensor.name}' in ros2_control '{block.name}': frame_id '{text}' is not a "
                        "link of the robot" + did_you_mean(text, links),
                        span_of(frame),
                        element=f"{where}/param[frame_id]",
                        help="name the link the sensor is mounted on",
                        data={"sensor": sensor.name, "frame_id": text},
                    )

    def _unbound(
        self, block: rc.Block, sensor: rc.Component, simulated: dict[str, str], where: str
    ) -> Diagnostic:
        kind = simulated.get(sensor.name)
        if kind is None:
            what = "no <gazebo> block declares a sensor of that name" + did_you_mean(sensor.name, simulated)
        else:
            what = f"it is a gz '{kind or 'untyped'}' sensor, and only imu and force_torque are read"
        return self.diagnostic(
            f"sensor '{sensor.name}' in ros2_control '{block.name}': gz_ros2_control binds it to the gz "
            f"imu or force_torque sensor of the same name, but {what}; it reads nothing in simulation",
            span_of(sensor.element),
            element=where,
            help="give the ros2_control sensor the name of the imu or force_torque <sensor> in <gazebo>",
            data={"sensor": sensor.name, "gazebo_sensors": sorted(simulated), "type": kind},
        )


@register
class SensorInterfaceUnknown(_Sensors):
    """A ros2_control sensor's state interface is one gz_ros2_control cannot bind, or a misspelt standard one.

    ## What it does
    For a sensor that gz_ros2_control binds to a gz-sim IMU or force/torque
    sensor, checks each `<state_interface>` against the names it reads from
    that sensor (`orientation.x`…`orientation.w`, `angular_velocity.x`…,
    `linear_acceleration.x`…; `force.x`…, `torque.x`…). For any other
    sensor, reports (as a warning) a name close to one of those of
    ros2_control's IMU and force/torque semantic components (`orientation.X`,
    `force_x`); other names are custom interfaces, which ros2_control
    allows, and are not reported.

    ## Why it matters
    gz_ros2_control looks each interface of a bound sensor up in a fixed
    table and throws on any other name, which stops Gazebo while the robot
    is loaded. On real hardware a misspelt name is exported as written, and
    the IMU or force/torque broadcaster, which asks for `SENSOR/force.x`,
    fails to activate.

    ## Example
    ```xml
    <sensor name="tcp_fts_sensor"> <state_interface name="force_x"/> </sensor>
    ```

    ## Fix
    Use the standard name: `<state_interface name="force.x"/>`.
    """

    code = "G108"
    name = "ros2-control-sensor-interface-unknown"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for block in rc.blocks(ctx):
            for sensor in _sensors(block):
                kind = bound_type(ctx, block, sensor)
                for interface in sensor.state:
                    if interface.name and "$" not in interface.name:
                        yield from self._one(block, sensor, interface, kind)

    def _one(
        self, block: rc.Block, sensor: rc.Component, interface: rc.Interface, kind: str | None
    ) -> Iterator[Diagnostic]:
        name = interface.name
        where = f"ros2_control[{block.name}]/sensor[{sensor.name}]/state_interface[{name}]"
        data = {"sensor": sensor.name, "interface": name}
        if kind is not None:
            table = known.SENSOR_INTERFACES[kind]
            if name not in table:
                yield self.diagnostic(
                    f"sensor '{sensor.name}' in ros2_control '{block.name}': gz_ros2_control has no "
                    f"'{name}' for its gz {kind} sensor and throws while loading the robot"
                    + did_you_mean(name, table),
                    span_of(interface.element),
                    element=where,
                    help=f"use one of: {', '.join(sorted(table))}",
                    data={**data, "type": kind},
                )
            return
        match = None if name in rc.KNOWN_INTERFACES else _typo_of(name)
        if match is not None:
            yield self.diagnostic(
                f"sensor '{sensor.name}' in ros2_control '{block.name}': state interface '{name}' is not a "
                f"standard one; did you mean '{match}'?",
                span_of(interface.element),
                severity=Severity.WARNING,
                element=where,
                help=f'write <state_interface name="{match}"/>',
                data={**data, "suggestion": match},
            )
