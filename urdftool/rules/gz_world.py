"""What the world runs (G307-G309): sensors whose gz-sim system the world does not load, plugins
of one Gazebo in a file that the other Gazebo runs, and static models that a plugin should move.

gz-sim loads the systems a world lists in its own ``<plugin>`` elements; when the world lists
none it loads a server configuration instead (``GZ_SIM_SERVER_CONFIG_PATH``, else the installed
``server.config``: Physics, UserCommands and SceneBroadcaster only; gz-sim's "Server
Configuration" tutorial). So a world that lists its systems must list the system of every kind
of sensor it holds; for a world that lists none, what runs depends on the machine, and the
finding is an info. A model checked alone has no world and is left alone. Each model of a world
carries the ``<world>`` element as ``Robot.world``; decisions are in ``docs/gazebo.md``.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from typing import Any

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts import gazebo
from urdftool.facts.context import CheckContext
from urdftool.model import JointType, Robot
from urdftool.parse.locate import span_of
from urdftool.rules import gazebo_plugins as gz
from urdftool.rules import gz_systems_known as known

#: SDF sensor type -> the gz-sim system class that creates and updates that sensor
#: (gz-sim's ``src/systems/*``: rendering sensors are the Sensors system's; each other kind has
#: its own system). CPU ``ray``/``lidar`` sensors are left out: gz-sim has no system for them.
SENSOR_SYSTEMS: dict[str, str] = {
    **dict.fromkeys(
        ("camera", "depth_camera", "depth", "rgbd_camera", "rgbd", "gpu_lidar", "gpu_ray", "thermal_camera",
         "thermal", "segmentation_camera", "segmentation", "boundingbox_camera", "boundingbox",
         "wideanglecamera", "wide_angle_camera"),
        "Sensors",
    ),
    "imu": "Imu",
    "magnetometer": "Magnetometer",
    "air_pressure": "AirPressure",
    "air_speed": "AirSpeed",
    "altimeter": "Altimeter",
    "navsat": "NavSat",
    "gps": "NavSat",
    "contact": "Contact",
    "force_torque": "ForceTorque",
    "logical_camera": "LogicalCamera",
}

#: A Gazebo Classic plugin library: ``libgazebo_ros_diff_drive.so``, ``libgazebo_ros2_control.so``,
#: PX4's ``libgazebo_mavlink_interface.so``: Classic's plugins are ``lib…so`` files named for Gazebo.
_CLASSIC = re.compile(r"^lib(?:gazebo|Gazebo)\w*\.so$")


class _GzWorld(Rule):
    family = Family.GAZEBO


def classic_plugin(plugin: Any) -> bool:
    """Whether *plugin*'s library is a Gazebo Classic plugin (by its file name)."""
    filename = (plugin.get("filename") or "").strip().rsplit("/", 1)[-1]
    return bool(_CLASSIC.match(filename))


def model_plugins(robot: Robot) -> Iterator[Any]:
    """Every ``<plugin>`` of the model: its own, those in ``<gazebo>`` blocks, and those of its links'
    and joints' sensors (a camera's ROS plugin sits in its ``<sensor>``)."""
    yield from gz.plugins(robot)
    extensions = [e for link in robot.links for e in link.extensions]
    extensions += [e for joint in robot.joints for e in joint.extensions]
    for extension in extensions:
        if extension.tag in ("sensor", "plugin") and extension.element is not None:
            yield from extension.element.iter("plugin")


def _sensors(robot: Robot) -> Iterator[tuple[str, Any]]:
    """(owner, ``<sensor>`` element) of each sensor on the model's links and joints."""
    for link in robot.links:
        for extension in link.extensions:
            if extension.tag == "sensor" and extension.element is not None:
                yield f"link[{link.name}]", extension.element
    for joint in robot.joints:
        for extension in joint.extensions:
            if extension.tag == "sensor" and extension.element is not None:
                yield f"joint[{joint.name}]", extension.element


@register
class SensorSystemMissing(_GzWorld):
    """A gz-sim world lists its systems but not the one that runs a sensor it holds.

    ## What it does
    In an SDF world whose own `<plugin>`s include gz-sim systems, reports each
    kind of sensor on its models whose system is in neither the world's nor
    the model's plugins: cameras, depth and RGBD cameras, GPU lidars, thermal,
    segmentation and bounding-box cameras need the Sensors system
    (`gz-sim-sensors-system`); `imu`, `magnetometer`, `air_pressure`,
    `air_speed`, `altimeter`, `navsat`, `contact`, `force_torque` and
    `logical_camera` sensors need their own system (`gz-sim-imu-system`, …).
    It is reported once per model and kind, at the first such sensor. A world
    that lists no plugin at all gets an info instead when it is written for
    gz-sim (gz-gui plugins in its `<gui>`, or gz-sim systems on the model):
    gz-sim then loads a server configuration, whose installed default runs
    no sensor, but `GZ_SIM_SERVER_CONFIG_PATH` may name one that does. A
    model checked without its world is not judged.

    ## Why it matters
    gz-sim loads the systems the world lists and, only when it lists none, its
    default set. A sensor whose system is not loaded is never created: its
    topic is never published, and nothing is printed (husarion/rosbot_ros#109:
    no IMU data; gazebosim/ros_gz#362). It is the usual slip when a Gazebo
    Classic world is ported, or when a world's plugin list is trimmed.

    ## Example
    ```xml
    <world name="demo">
      <plugin filename="gz-sim-physics-system" name="gz::sim::systems::Physics"/>
      <plugin filename="gz-sim-scene-broadcaster-system" name="gz::sim::systems::SceneBroadcaster"/>
      <model name="robot"> … <sensor name="front" type="camera"> … </sensor> … </model>
    </world>
    ```

    ## Fix
    Add the system to the world:
    ```xml
    <plugin filename="gz-sim-sensors-system" name="gz::sim::systems::Sensors">
      <render_engine>ogre2</render_engine>
    </plugin>
    ```
    """

    code = "G307"
    name = "gz-sensor-system-missing"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        world = world_plugins(ctx.robot)
        listed = [s for p in world if (s := known.read_system(p)) is not None]
        if not listed and (world or ctx.robot.world is None):
            return  # no world, or a world of another simulator
        own = [s for p in gazebo.plugins(ctx) if (s := known.read_system(p)) is not None]
        if listed:
            severity = None
        elif own or _gz_gui(ctx.robot.world):
            # No world plugin: gz-sim loads a server configuration, whose installed default
            # (Physics, UserCommands, SceneBroadcaster) runs no sensor; GZ_SIM_SERVER_CONFIG_PATH
            # may name one that does (PX4's worlds rely on it), so this is only an info.
            severity = Severity.INFO
        else:
            return  # no world, or a world of another simulator
        loaded = {s.kind for s in (*listed, *own)}
        found: dict[str, list[tuple[str, Any]]] = {}
        for owner, sensor in _sensors(ctx.robot):
            system = SENSOR_SYSTEMS.get((sensor.get("type") or "").strip())
            if system is not None and system not in loaded:
                found.setdefault(system, []).append((owner, sensor))
        for system, sensors in found.items():
            owner, sensor = sensors[0]
            stem = next(stem for stem, classes in known.LIBRARIES.items() if system in classes)
            others = f" (and {len(sensors) - 1} more)" if len(sensors) > 1 else ""
            why = (
                "which the world does not load: it lists its own systems, so the sensor publishes nothing"
                if severity is None
                else "and the world lists no system: gz-sim's default server configuration does not load "
                "it, so the sensor publishes nothing unless GZ_SIM_SERVER_CONFIG_PATH names one that does"
            )
            yield self.diagnostic(
                f"{owner}: sensor '{sensor.get('name')}' ({sensor.get('type')}){others} needs gz-sim's "
                f"{system} system, {why}",
                span_of(sensor),
                severity=severity,
                element=f"{owner}/sensor[{sensor.get('name')}]",
                help=f'add <plugin filename="gz-sim-{stem}-system" name="gz::sim::systems::{system}"/> '
                "to the world",
                data={"system": system, "sensors": [s.get("name") for _, s in sensors]},
            )


def world_plugins(robot: Robot) -> list[Any]:
    """The ``<plugin>`` children of the world the model is in (none for a model read alone)."""
    world = robot.world
    return [] if world is None else [c for c in world if c.tag == "plugin"]


def _gz_gui(world: Any) -> bool:
    """Whether the world's ``<gui>`` lists gz-gui plugins (``MinimalScene``: a name, where Gazebo
    Classic's GUI plugins are ``lib….so`` files): the world is written for gz-sim."""
    gui = world.find("gui")
    if gui is None:
        return False
    names = [(p.get("filename") or "").strip() for p in gui.iter("plugin")]
    return any(n and not n.endswith((".so", ".dylib", ".dll")) for n in names)


@register
class ClassicPluginInGzSim(_GzWorld):
    """A Gazebo Classic plugin in a gz-sim world, or a gz-sim system in a Classic world.

    ## What it does
    Tells a file's simulator by its plugins: gz-sim systems
    (`gz-sim-*-system`, `ignition-gazebo-*-system`, `gz::sim::systems::*`) or
    Gazebo Classic plugins (`libgazebo_ros_*.so`, `libgazebo_*.so`). When the
    world's own plugins are gz-sim systems, a Classic plugin anywhere in it (a
    model's, a sensor's) is an error. When they are Classic plugins only, a
    gz-sim system is a warning. A model (URDF or SDF) checked without a world,
    or in a world whose own plugins do not tell, is not judged: a model may
    carry both kinds on purpose, to run in either simulator (iCub's URDFs load
    `gz-sim-yarp-*` systems and `libgazebo_yarp_*.so` plugins side by side).

    ## Why it matters
    gz-sim cannot load a Classic plugin ("does not export any plugins. The
    symbol [GzPluginHook] is missing", gazebo_ros_pkgs#1536) and goes on
    without it: the drive does not move the robot, the camera publishes no ROS
    topic. Gazebo Classic cannot load a gz-sim system either.

    ## Example
    ```xml
    <world name="demo">
      <plugin filename="gz-sim-physics-system" name="gz::sim::systems::Physics"/>
      <model name="robot"> …
        <plugin filename="libgazebo_ros_diff_drive.so" name="diff_drive"> … </plugin>
      </model>
    </world>
    ```

    ## Fix
    Use the gz-sim system that does the job (`gz-sim-diff-drive-system`,
    `gz::sim::systems::DiffDrive`) and bridge its topics with `ros_gz_bridge`.
    """

    code = "G308"
    name = "gz-classic-plugin-mixed"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        world = world_plugins(ctx.robot)
        if not world:
            return  # a model read alone, or a world without plugins: neither kind of runner is known
        world_gz = any(known.read_system(p) is not None for p in world)
        world_classic = any(classic_plugin(p) for p in world)
        first = bool(ctx.robot.world_plugins)  # the world's own plugins are reported with its first model
        plugins = [*model_plugins(ctx.robot), *(world if first else ())]
        gz_plugins = [p for p in plugins if known.read_system(p) is not None]
        classic = [p for p in plugins if classic_plugin(p)]
        if world_gz and not world_classic:
            for plugin in classic:
                yield self._report(plugin, "gz-sim", "the world loads gz-sim systems", None)
        elif world_classic and not world_gz:
            for plugin in gz_plugins:
                yield self._report(plugin, "Gazebo Classic", "the world loads Gazebo Classic plugins",
                                   Severity.WARNING)

    def _report(self, plugin: Any, runner: str, why: str, severity: Severity | None) -> Diagnostic:
        label = gz.plugin_label(plugin)
        kind = "a gz-sim system" if runner == "Gazebo Classic" else "a Gazebo Classic plugin"
        return self.diagnostic(
            f"{label} is {kind}, but {why}: {runner} cannot load it and runs without it",
            span_of(plugin),
            severity=severity,
            element=f"plugin[{plugin.get('name') or ''}]",
            help="use the gz-sim system that does the same job (e.g. gz-sim-diff-drive-system for "
            "libgazebo_ros_diff_drive.so) and bridge its topics with ros_gz_bridge"
            if runner == "gz-sim"
            else "use the Gazebo Classic plugin, or run the world in gz-sim",
            data={"filename": plugin.get("filename"), "simulator": runner},
        )


#: gz-sim systems that move a model's joints or the model itself.
ACTUATING_SYSTEMS = frozenset({
    "DiffDrive", "AckermannSteering", "MecanumDrive", "TrackedVehicle", "TrackController", "JointController",
    "JointPositionController", "JointTrajectoryController", "ApplyJointForce", "MulticopterMotorModel",
    "Thruster",
})
#: Gazebo Classic and ros2_control plugins (by library file) that do the same.
_ACTUATING_FILES = re.compile(
    r"diff_drive|skid_steer|ackermann|planar_move|ros2?_control|joint_pose_trajectory|joint_trajectory"
)


def actuating(plugin: Any) -> bool:
    """Whether *plugin* drives the model (a drive, a joint controller, ros2_control)."""
    system = known.read_system(plugin)
    if system is not None and system.kind in ACTUATING_SYSTEMS:
        return True
    filename = (plugin.get("filename") or "").strip().rsplit("/", 1)[-1]
    return bool(_ACTUATING_FILES.search(filename))


@register
class StaticModelActuated(_GzWorld):
    """A `<static>` model has moving joints and a plugin that drives them.

    ## What it does
    Reports an SDF model marked `<static>true</static>` (by itself or by the
    `<include>` that brings it in) that has a joint other than `fixed` and a
    plugin that actuates it: a drive (DiffDrive, AckermannSteering,
    MecanumDrive, `libgazebo_ros_diff_drive.so`, …), a joint controller
    (JointController, JointPositionController, JointTrajectoryController,
    ApplyJointForce) or ros2_control. Static props without joints, and static
    scenery whose joints nothing drives, are left alone.

    ## Why it matters
    The SDFormat spec makes a static model immovable: the physics engine does
    not simulate it, so its joints never move and the drive's or the
    controller's commands do nothing, without a message. It is usually a
    `<static>true</static>` left over from placing the model in a world.

    ## Example
    ```xml
    <model name="vehicle"><static>true</static> …
      <joint name="left_wheel_joint" type="revolute"> … </joint>
      <plugin filename="gz-sim-diff-drive-system" name="gz::sim::systems::DiffDrive"> … </plugin>
    </model>
    ```

    ## Fix
    Remove `<static>true</static>` (or write `false`); to hold the base in place, fix it to the
    world with a `fixed` joint to `world` instead.
    """

    code = "G309"
    name = "static-model-actuated"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        span = ctx.robot.static_span
        if span is None:
            return
        moving = [j for j in ctx.robot.joints if j.type is not JointType.FIXED]
        drivers = [p for p in model_plugins(ctx.robot) if actuating(p)]
        if not moving or not drivers:
            return
        plugin = drivers[0]
        yield self.diagnostic(
            f"model '{ctx.robot.name}' is static, so its {len(moving)} moving joint(s) "
            f"('{moving[0].name}'{', …' if len(moving) > 1 else ''}) never move, and "
            f"{gz.plugin_label(plugin)} drives nothing",
            span,
            element=f"model[{ctx.robot.name}]/static",
            help="remove <static>true</static>; to hold the base still, fix it to 'world' with a fixed joint",
            data={"joints": [j.name for j in moving], "plugin": plugin.get("filename")},
        )
