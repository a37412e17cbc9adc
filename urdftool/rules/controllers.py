"""Controllers YAML (G2xx): joints, interfaces and types checked against the ros2_control blocks.

The YAML is read by :mod:`urdftool.parse.controllers` (every value keeps its
line and column), found by :mod:`urdftool.pipeline.controllers` and read here
through :func:`urdftool.facts.ros2_control.controllers`; every finding is
located in the YAML. The wheel geometry of ``diff_drive_controller`` is
checked by ``drive-geometry-mismatch`` (G004). Decisions are in
``docs/ros2_control.md``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.catalogue.suggest import closest, did_you_mean
from urdftool.diagnostics import Diagnostic, Related, Severity
from urdftool.facts import ros2_control as rc
from urdftool.facts.context import CheckContext
from urdftool.parse.controllers import Controller, Value

#: Controller types of ros2_controllers (and ros2_control's broadcasters), by plugin name.
KNOWN_TYPES = frozenset(
    {
        "joint_trajectory_controller/JointTrajectoryController",
        "diff_drive_controller/DiffDriveController",
        "forward_command_controller/ForwardCommandController",
        "forward_command_controller/MultiInterfaceForwardCommandController",
        "joint_state_broadcaster/JointStateBroadcaster",
        "position_controllers/JointGroupPositionController",
        "velocity_controllers/JointGroupVelocityController",
        "effort_controllers/JointGroupEffortController",
        "imu_sensor_broadcaster/IMUSensorBroadcaster",
        "force_torque_sensor_broadcaster/ForceTorqueSensorBroadcaster",
        "range_sensor_broadcaster/RangeSensorBroadcaster",
        "pose_broadcaster/PoseBroadcaster",
        "gps_sensor_broadcaster/GPSSensorBroadcaster",
        "gripper_controllers/GripperActionController",
        "position_controllers/GripperActionController",
        "effort_controllers/GripperActionController",
        "parallel_gripper_action_controller/GripperActionController",
        "admittance_controller/AdmittanceController",
        "tricycle_controller/TricycleController",
        "tricycle_steering_controller/TricycleSteeringController",
        "bicycle_steering_controller/BicycleSteeringController",
        "ackermann_steering_controller/AckermannSteeringController",
        "mecanum_drive_controller/MecanumDriveController",
        "omni_wheel_drive_controller/OmniWheelDriveController",
        "pid_controller/PidController",
        "gpio_controllers/GpioCommandController",
        "steering_controllers_library/SteeringControllersLibrary",
    }
)
#: Parameters that list joints, per convention of ros2_controllers.
JOINT_LIST_PARAMS = (
    "joints",
    "left_wheel_names",
    "right_wheel_names",
    "rear_wheels_names",
    "front_wheels_names",
    "traction_joints_names",
    "steering_joints_names",
)
#: Parameters naming one joint.
JOINT_PARAMS = ("joint",)
#: Command interface a controller type implies for its joints (``None``: read from the parameters).
IMPLIED_COMMAND = {
    "position_controllers/JointGroupPositionController": "position",
    "velocity_controllers/JointGroupVelocityController": "velocity",
    "effort_controllers/JointGroupEffortController": "effort",
    "position_controllers/GripperActionController": "position",
    "effort_controllers/GripperActionController": "effort",
    "gripper_controllers/GripperActionController": "position",
    "diff_drive_controller/DiffDriveController": "velocity",
}


class _Controllers(Rule):
    family = Family.GAZEBO


def _all(ctx: CheckContext) -> Iterator[Controller]:
    yield from rc.controller_list(ctx)


def _type(controller: Controller) -> str:
    return (controller.type.text() or "") if controller.type else ""


def joint_values(controller: Controller) -> Iterator[Value]:
    """Every value naming a joint in *controller*'s parameters."""
    for key in JOINT_LIST_PARAMS:
        value = controller.param(key)
        if value is not None:
            yield from (item for item in value.items() if item.text())
    for key in JOINT_PARAMS:
        value = controller.param(key)
        if value is not None and value.text():
            yield value


def _vendor_prefix(controller: Controller, name: str, urdf: set[str], known: set[str]) -> bool:
    """Whether *name* may be an interface prefix a vendor's hardware exports on its own.

    A controller type outside ros2_controllers gives its parameters its own meaning: Kinova's
    MoveIt configurations give PickNik's twist controller ``joint: tcp``, and the Kortex hardware
    interface exports ``tcp/twist.linear.x``… from code, with no URDF joint ``tcp``. Such a name
    is left alone unless it is close to a joint name of the robot (then it is likely a typo).
    """
    if _type(controller) in KNOWN_TYPES or name in urdf:
        return False
    return closest(name, known) is None


@register
class ControllerJointUnknown(_Controllers):
    """A controller in the controllers YAML names a joint that no ros2_control block declares.

    ## What it does
    Checks the joints each controller lists (`joints`, `joint`,
    `left_wheel_names`, `right_wheel_names`, …) against the joints of the
    robot's `<ros2_control>` blocks (or, for a robot without one, its URDF
    joints), with the closest name. The finding is located in the YAML. A
    controller is any node whose `type` names a plugin, listed under
    `controller_manager` or typed in its own `ros__parameters`
    (docs/ros2_control.md).

    ## Why it matters
    The controller manager loads the controller, then fails to configure or
    activate it ("joint not found", "missing interfaces"); a spawner waits
    and times out, and the robot never moves. Renaming a joint in the URDF
    without the YAML is the usual cause.

    ## Example
    ```yaml
    arm_controller:
      ros__parameters:
        joints: [joint1, joint_2]   # the URDF says joint2
    ```

    ## Fix
    Use the joint names of the `<ros2_control>` block, or declare the joint there.
    (Chained controllers' reference interfaces, `pid_controller/left_wheel_joint`,
    name another controller of the file and are not reported; nor is a name
    far from every joint in a controller type outside ros2_controllers, which
    may be an interface prefix its vendor's hardware exports, such as Kortex's
    `tcp/twist.linear.x`.)
    """

    code = "G201"
    name = "controller-joint-unknown"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        declared = set(rc.exported(ctx))
        urdf = {joint.name for joint in ctx.robot.joints}
        known = declared or urdf
        names = {controller.name for controller in _all(ctx)}
        for controller in _all(ctx):
            for value in joint_values(controller):
                name = value.text() or ""
                if name in known or "$" in name or name.split("/")[0] in names:
                    continue  # a chained controller's reference interface: CONTROLLER/NAME
                if _vendor_prefix(controller, name, urdf, known):
                    continue
                if name in urdf:
                    message = (
                        f"controller '{controller.name}' names joint '{name}', which no "
                        "ros2_control block declares"
                    )
                    fix = f'add <joint name="{name}"> with its interfaces to the ros2_control block'
                else:
                    message = (
                        f"controller '{controller.name}' names joint '{name}', which the robot "
                        "does not have" + did_you_mean(name, known)
                    )
                    fix = "use the joint's exact name"
                yield self.diagnostic(
                    message,
                    value.span,
                    element=f"{controller.name}/joints[{name}]",
                    help=fix,
                    data={"controller": controller.name, "joint": name},
                )


@register
class ControllerInterfaceUnknown(_Controllers):
    """A controller claims a command or state interface its joints do not export.

    ## What it does
    For each controller, takes the interfaces it claims on its joints
    (`command_interfaces`, `state_interfaces`, `interface_name`, or the one
    its type implies: position for `JointGroupPositionController`, velocity
    for `DiffDriveController`'s wheels, …) and checks that the joint's
    `<ros2_control>` declaration exports each of them. Located in the YAML.

    ## Why it matters
    The controller manager refuses to activate a controller whose interfaces
    are missing: `arm_controller` stays inactive and the only trace is a log
    line at launch.

    ## Example
    ```yaml
    arm_controller:
      ros__parameters:
        joints: [joint1]
        command_interfaces: [velocity]   # joint1 exports only position
    ```

    ## Fix
    Claim the interfaces the hardware exports, or add them to the `<ros2_control>` joint.
    """

    code = "G202"
    name = "controller-interface-unknown"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        exported = rc.exported(ctx)
        if not exported:
            return
        for controller in _all(ctx):
            claims = list(self._claims(controller))
            if not claims:
                continue
            for value in joint_values(controller):
                joint = value.text() or ""
                if joint not in exported:
                    continue  # controller-joint-unknown reports it
                for kind, interface, where in claims:
                    available = exported[joint][0 if kind == "command" else 1]
                    if interface in available or "$" in interface:
                        continue
                    suggestion = closest(interface, available)
                    offered = ", ".join(sorted(available)) or "none"
                    yield self.diagnostic(
                        f"controller '{controller.name}' claims {kind} interface '{joint}/{interface}', but "
                        f"joint '{joint}' exports {kind} interfaces: {offered}"
                        + (f"; did you mean '{suggestion}'?" if suggestion else ""),
                        where.span,
                        element=f"{controller.name}/{kind}_interfaces[{interface}]",
                        help=f'claim one of {offered}, or add <{kind}_interface name="{interface}"/> '
                        f"to joint '{joint}' in the ros2_control block",
                        data={
                            "controller": controller.name,
                            "joint": joint,
                            "interface": interface,
                            "kind": kind,
                        },
                    )

    @staticmethod
    def _claims(controller: Controller) -> Iterator[tuple[str, str, Value]]:
        for kind in ("command", "state"):
            value = controller.param(f"{kind}_interfaces")
            if value is not None:
                for item in value.items():
                    if item.text():
                        yield kind, item.text() or "", item
        single = controller.param("interface_name")
        if single is not None and single.text():
            yield "command", single.text() or "", single
        implied = IMPLIED_COMMAND.get(_type(controller))
        if implied and controller.type is not None and controller.param("command_interfaces") is None:
            yield "command", implied, controller.type


#: The packages of :data:`KNOWN_TYPES`.
KNOWN_PACKAGES = frozenset(t.split("/")[0] for t in KNOWN_TYPES)
#: How alike a package name must be to one of ros2_controllers' to be a misspelling of it: every
#: package there ends in ``_controller(s)``, so a whole-string match tied UR's
#: ``ur_controllers/ForceModeController`` to ``pid_controller/PidController`` (0.8: ``ur_controllers``
#: and ``gpio_controllers``; 0.97: ``position_controller`` and ``position_controllers``).
PACKAGE_CUTOFF = 0.85


def _likely_meant(declared: str) -> str | None:
    """The ros2_controllers type *declared* misspells, or ``None`` for a vendor's own package."""
    package = declared.split("/")[0]
    meant = package if package in KNOWN_PACKAGES else closest(package, KNOWN_PACKAGES, PACKAGE_CUTOFF)
    if meant is None:
        return None
    return closest(declared, [t for t in KNOWN_TYPES if t.startswith(meant + "/")])


@register
class ControllerTypeUnknown(_Controllers):
    """A controller's `type` is not one of ros2_controllers' (a misspelling, or a vendor's controller).

    ## What it does
    Compares each controller's `type` in the controller manager's parameters
    with the controllers ros2_controllers and ros2_control ship
    (`joint_trajectory_controller/JointTrajectoryController`,
    `diff_drive_controller/DiffDriveController`, …). A type whose package is
    one of ros2_controllers' (or a near miss of one) and whose name is close
    to one of its types is a warning with the likely name; any other type is
    a note, since vendors ship their own controllers
    (`ur_controllers/ForceModeController`).

    ## Why it matters
    pluginlib finds no class for a misspelt type: the controller manager
    refuses to load the controller and the spawner exits with an error.

    ## Example
    ```yaml
    arm_controller:
      type: joint_trajectory_controller/JointTrajectoryControler
    ```

    ## Fix
    Write the exact plugin name: `joint_trajectory_controller/JointTrajectoryController`.
    """

    code = "G203"
    name = "controller-type-unknown"
    severity = Severity.INFO

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for controller in _all(ctx):
            # both types when the two layouts disagree (type-conflict reports that): each is
            # loaded by one way of starting the controller
            types = [controller.type, controller.listed_type]
            for value in types[: 1 if _same(controller.type, controller.listed_type) else 2]:
                yield from self._type(controller, value)

    def _type(self, controller: Controller, value: Value | None) -> Iterator[Diagnostic]:
        declared = (value.text() or "") if value is not None else ""
        if not declared or declared in KNOWN_TYPES or value is None:
            return
        suggestion = _likely_meant(declared)
        if suggestion is not None:
            yield self.diagnostic(
                f"controller '{controller.name}' has type '{declared}'; did you mean '{suggestion}'?",
                value.span,
                severity=Severity.WARNING,
                element=f"{controller.name}/type",
                help=f"write type: {suggestion}",
                data={"type": declared, "suggestion": suggestion},
            )
        else:
            yield self.diagnostic(
                f"controller '{controller.name}' has type '{declared}', which is not one of "
                "ros2_controllers'; its package must be installed",
                value.span,
                element=f"{controller.name}/type",
                help="nothing to do if the package provides it",
                data={"type": declared},
            )


def _same(a: Value | None, b: Value | None) -> bool:
    return a is None or b is None or a.text() == b.text()


@register
class ControllerTypeConflict(_Controllers):
    """A controller's own parameters and the controller manager's give it different types.

    ## What it does
    Compares a controller's `type` written in its own `ros__parameters` (the
    layout ros2_control_demos and gz_ros2_control's demos use since
    ros2_control PR 1502) with the `type` the `controller_manager`'s
    parameters list it with, when the file holds both. Located at the
    controller's own `type`, with the manager's as a related location.

    ## Why it matters
    Which one is loaded depends on how the controller is started. The
    spawner given the file with `--param-file` reads the type from the
    controller's own parameters and sets it on the controller manager,
    replacing the listed one; a controller loaded without it (the spawner
    without `--param-file`, `ros2 control load_controller`, the manager's
    own start-up list) gets the manager's type. The same file then runs a
    different controller, with other interfaces, in simulation and on the
    robot, or after a launch file is edited.

    ## Example
    ```yaml
    controller_manager:
      ros__parameters:
        arm_controller:
          type: position_controllers/JointGroupPositionController
    arm_controller:
      ros__parameters:
        type: joint_trajectory_controller/JointTrajectoryController
        joints: [joint1, joint2]
    ```

    ## Fix
    Declare the type once, in the controller's own parameters, and delete
    the other.
    """

    code = "G204"
    name = "controller-type-conflict"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for controller in _all(ctx):
            own, listed = controller.type, controller.listed_type
            if own is None or listed is None or own is listed or _same(own, listed):
                continue
            yield dataclasses.replace(
                self.diagnostic(
                    f"controller '{controller.name}' has type '{own.text()}' in its own parameters, "
                    f"but the controller manager's parameters list it as '{listed.text()}'",
                    own.span,
                    element=f"{controller.name}/type",
                    help="declare the type once, in the controller's own parameters: the spawner "
                    "with --param-file loads this one, any other way of loading it the manager's",
                    data={"type": own.text(), "listed_type": listed.text()},
                ),
                related=(Related(listed.span, "the type under controller_manager"),),
            )
