"""What urdftool knows about gz-sim (Ignition Gazebo) systems named by ``<plugin>`` elements.

A gz-sim system is loaded from a shared library (``filename``) and instantiated
by class name (``name``): ``gz::sim::SystemLoader`` loads the library, then asks
gz-plugin for the class the ``name`` gives, and fails ("could not instantiate
from library") when no loaded library registers it. Each system of gz-sim is
built as ``gz-sim<N>-<stem>-system`` (with an unversioned link
``gz-sim-<stem>-system``) and registers ``gz::sim::systems::<Class>``;
Ignition Gazebo (Fortress) wrote ``ignition-gazebo-<stem>-system`` and
``ignition::gazebo::systems::<Class>``, and gz-sim still maps the old library
prefix to the new one. The table below is read from gz-sim's
``src/systems/*/CMakeLists.txt`` (``gz_add_system``) and each system's
``GZ_ADD_PLUGIN_ALIAS``; the parameters from each system's header
documentation.
"""

from __future__ import annotations

import re
from typing import Any

from urdftool.facts import ros2_control as rc
from urdftool.records import record

#: Library stem -> the classes that library registers.
LIBRARIES: dict[str, tuple[str, ...]] = {
    "ackermann-steering": ("AckermannSteering",),
    "acoustic-comms": ("AcousticComms",),
    "advanced-lift-drag": ("AdvancedLiftDrag",),
    "air-pressure": ("AirPressure",),
    "air-speed": ("AirSpeed",),
    "altimeter": ("Altimeter",),
    "apply-joint-force": ("ApplyJointForce",),
    "apply-link-wrench": ("ApplyLinkWrench",),
    "linearbatteryplugin": ("LinearBatteryPlugin",),
    "breadcrumbs": ("Breadcrumbs",),
    "buoyancy": ("Buoyancy",),
    "buoyancy-engine": ("BuoyancyEngine",),
    "camera-video-recorder": ("CameraVideoRecorder",),
    "collada-world-exporter": ("ColladaWorldExporter",),
    "comms-endpoint": ("CommsEndpoint",),
    "contact": ("Contact",),
    "cpu-lidar": ("CpuLidar",),
    "detachable-joint": ("DetachableJoint",),
    "diff-drive": ("DiffDrive",),
    "drive-to-pose-controller": ("DriveToPoseController",),
    "dvl": ("DopplerVelocityLogSystem",),
    "elevator": ("Elevator",),
    "entity-semantics": ("EntitySemantics",),
    "environment-preload": ("EnvironmentPreload",),
    "environmental-sensor": ("EnvironmentalSystem",),
    "follow-actor": ("FollowActor",),
    "forcetorque": ("ForceTorque",),
    "free-space-explorer": ("FreeSpaceExplorer",),
    "hydrodynamics": ("Hydrodynamics",),
    "imu": ("Imu",),
    "joint-controller": ("JointController",),
    "joint-position-controller": ("JointPositionController",),
    "joint-state-publisher": ("JointStatePublisher",),
    "joint-trajectory-controller": ("JointTrajectoryController",),
    "kinetic-energy-monitor": ("KineticEnergyMonitor",),
    "label": ("Label",),
    "led-plugin": ("LedPlugin",),
    "lens-flare": ("LensFlare",),
    "lift-drag": ("LiftDrag",),
    "lighter_than_air_dynamics": ("LighterThanAirDynamics",),
    "log": ("LogPlayback", "LogRecord"),
    "log-video-recorder": ("LogVideoRecorder",),
    "logicalaudiosensorplugin": ("LogicalAudioSensorPlugin",),
    "logical-camera": ("LogicalCamera",),
    "lookup-wheel-slip": ("LookupWheelSlip",),
    "magnetometer": ("Magnetometer",),
    "mecanum-drive": ("MecanumDrive",),
    "model-photo-shoot": ("ModelPhotoShoot",),
    "multicopter-control": ("MulticopterVelocityControl",),
    "multicopter-motor-model": ("MulticopterMotorModel",),
    "navsat": ("NavSat",),
    "odometry-publisher": ("OdometryPublisher",),
    "opticaltactileplugin": ("OpticalTactilePlugin",),
    "particle-emitter": ("ParticleEmitter",),
    "perfect-comms": ("PerfectComms",),
    "performer-detector": ("PerformerDetector",),
    "physics": ("Physics",),
    "pose-publisher": ("PosePublisher",),
    "python-system-loader": ("PythonSystemLoader",),
    "rf-comms": ("RFComms",),
    "scene-broadcaster": ("SceneBroadcaster",),
    "sensors": ("Sensors",),
    "shader-param": ("ShaderParam",),
    "spacecraft-thruster-model": ("SpacecraftThrusterModel",),
    "thermal": ("Thermal",),
    "thermal-sensor": ("ThermalSensor",),
    "thruster": ("Thruster",),
    "touchplugin": ("TouchPlugin",),
    "track-controller": ("TrackController",),
    "tracked-vehicle": ("TrackedVehicle",),
    "trajectory-follower": ("TrajectoryFollower",),
    "triggered-publisher": ("TriggeredPublisher",),
    "user-commands": ("UserCommands",),
    "velocity-control": ("VelocityControl",),
    "websocket-server": ("WebsocketServer",),
    "wheel-slip": ("WheelSlip",),
    "wind-effects": ("WindEffects",),
}
#: Class -> its library stem.
CLASSES: dict[str, str] = {cls: stem for stem, classes in LIBRARIES.items() for cls in classes}

_LIBRARY = re.compile(
    r"^(?:lib)?(?P<prefix>gz-sim|ignition-gazebo)\d*-(?P<stem>.+)-system(?:\.(?:so|dylib|dll))?$"
)
_CLASS = re.compile(r"^(?P<ns>gz::sim|ignition::gazebo)(?:::v\d+)?::systems::(?P<cls>\w+)$")

#: gz_ros2_control's system plugin (and its Humble name, ign_ros2_control); classic Gazebo's.
GZ_ROS2_CONTROL_FILES = frozenset({"gz_ros2_control-system", "ign_ros2_control-system"})
CLASSIC_ROS2_CONTROL_FILES = frozenset({"gazebo_ros2_control"})
#: ros2_control hardware classes of each simulator's ros2_control plugin.
GZ_HARDWARE = frozenset({"gz_ros2_control/GazeboSimSystem", "ign_ros2_control/IgnitionSystem"})
CLASSIC_HARDWARE = frozenset({"gazebo_ros2_control/GazeboSystem"})

#: Render engines gz-rendering loads by name (``RenderEngineManager``); anything else is
#: looked up as a render-engine plugin library.
RENDER_ENGINES = frozenset({"ogre", "ogre2", "optix"})

#: The state interfaces gz_ros2_control binds for each gz sensor type
#: (``GazeboSimSystem::registerSensors``); any other name makes it throw.
IMU_INTERFACES = rc.IMU_INTERFACES
FORCE_TORQUE_INTERFACES = rc.FORCE_TORQUE_INTERFACES
SENSOR_INTERFACES = {"imu": frozenset(IMU_INTERFACES), "force_torque": frozenset(FORCE_TORQUE_INTERFACES)}


@record
class Params:
    """Which of a system's parameters name links, and which must read as numbers or flags."""

    links: frozenset[str] = frozenset()
    #: (child tag, attribute) pairs whose attribute names a link (WheelSlip's ``<wheel link_name>``)
    link_attributes: frozenset[tuple[str, str]] = frozenset()
    numbers: frozenset[str] = frozenset()
    integers: frozenset[str] = frozenset()
    flags: frozenset[str] = frozenset()
    positive: frozenset[str] = frozenset()


_PID = frozenset({"p_gain", "i_gain", "d_gain", "i_max", "i_min", "cmd_max", "cmd_min", "cmd_offset"})
_LIMITS = frozenset(
    f"{bound}_{kind}{what}"
    for bound in ("min", "max")
    for kind in ("", "linear_", "angular_")
    for what in ("velocity", "acceleration", "jerk")
)

PARAMS: dict[str, Params] = {
    "DiffDrive": Params(
        numbers=_LIMITS | {"wheel_separation", "wheel_radius", "odom_publish_frequency"},
        positive=frozenset({"wheel_separation", "wheel_radius"}),
    ),
    "JointPositionController": Params(
        numbers=_PID | {"initial_position"},
        integers=frozenset({"joint_index", "actuator_number"}),
        flags=frozenset({"use_velocity_commands", "use_actuator_msg"}),
    ),
    "JointController": Params(
        numbers=_PID | {"initial_velocity"},
        integers=frozenset({"joint_index", "actuator_number"}),
        flags=frozenset({"use_force_commands", "use_actuator_msg"}),
    ),
    "JointStatePublisher": Params(numbers=frozenset({"update_rate"})),
    "ApplyJointForce": Params(),
    "Sensors": Params(flags=frozenset({"disable_on_drained_battery"})),
    "LiftDrag": Params(links=frozenset({"link_name"})),
    "AdvancedLiftDrag": Params(links=frozenset({"link_name"})),
    "BuoyancyEngine": Params(links=frozenset({"link_name"})),
    "Hydrodynamics": Params(links=frozenset({"link_name"})),
    "KineticEnergyMonitor": Params(links=frozenset({"link_name"})),
    "TrajectoryFollower": Params(links=frozenset({"link_name"})),
    "TrackController": Params(links=frozenset({"link"})),
    "TrackedVehicle": Params(links=frozenset({"body_link"})),
    "DetachableJoint": Params(links=frozenset({"parent_link"})),
    "VelocityControl": Params(links=frozenset({"link_name"})),
    "WheelSlip": Params(link_attributes=frozenset({("wheel", "link_name")})),
}


@record
class System:
    """A ``<plugin>`` read as a gz-sim system: library stem and class (either may be unknown)."""

    element: Any
    filename: str
    name: str
    stem: str | None
    cls: str | None

    @property
    def kind(self) -> str | None:
        """The system's class: the one named, else the one its library registers first."""
        if self.cls in CLASSES:
            return self.cls
        return LIBRARIES[self.stem][0] if self.stem in LIBRARIES else self.cls

    @property
    def params(self) -> Params:
        return PARAMS.get(self.kind or "", Params())


def read_system(plugin: Any) -> System | None:
    """*plugin* as a gz-sim system, or ``None`` when neither its file nor its name is gz-sim's."""
    filename = (plugin.get("filename") or "").strip()
    name = (plugin.get("name") or "").strip()
    library = _LIBRARY.match(filename.rsplit("/", 1)[-1])
    cls = _CLASS.match(name)
    if library is None and cls is None:
        return None
    return System(
        plugin, filename, name, library.group("stem") if library else None, cls.group("cls") if cls else None
    )


def ros2_control_flavour(plugin: Any) -> str | None:
    """``gz`` or ``classic`` for a simulator's ros2_control plugin, else ``None``."""
    filename = (plugin.get("filename") or "").strip().rsplit("/", 1)[-1]
    stem = re.sub(r"^lib|\.(so|dylib|dll)$", "", filename)
    if stem in GZ_ROS2_CONTROL_FILES:
        return "gz"
    if stem in CLASSIC_ROS2_CONTROL_FILES:
        return "classic"
    return None


def valid_topic(topic: str) -> str:
    """The topic gz-transport uses for *topic* (``TopicUtils::AsValidTopic``): spaces become
    ``_``, ``@``, ``~``, ``//`` and ``:=`` are dropped; ``""`` when nothing valid remains."""
    fixed = re.sub("@|~|//|:=", "", topic.replace(" ", "_"))
    if not fixed or fixed == "/" or any(bad in fixed for bad in ("~", " ", "//", "@", ":=")):
        return ""
    return fixed


def is_topic_tag(tag: str) -> bool:
    return tag == "topic" or tag.endswith("_topic")
