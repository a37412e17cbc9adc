"""ROS frame conventions (N1xx): REP 103, REP 105, REP 120 and REP 145.

Rules for conventions every ROS consumer relies on run by default; rules for
conventions a robot may legitimately not follow (a wheel that steers, an IMU
mounted at an angle) set ``default_enabled = False`` and run only when named
(``--select wheel-axis-not-lateral`` or ``extend-select``).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
else:
    from urdftool.lazy import numpy as np

from urdftool.catalogue.registry import register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts.context import CheckContext
from urdftool.model import JointType
from urdftool.model.pose import matrix_to_rpy, rpy_to_matrix
from urdftool.physics.describe import fmt
from urdftool.rules.intent_common import (
    IntentRule,
    angle_between,
    home_poses,
    option,
    rotation_angle,
    where_joint,
)

#: The optical frame in its camera body frame (REP 103: z forward, x right, y down).
OPTICAL_RPY = (-math.pi / 2, 0.0, -math.pi / 2)
_OPTICAL = re.compile(r"_optical(_frame)?$")
_WHEEL = re.compile(r"wheel", re.IGNORECASE)
_NOT_DRIVE = re.compile(r"caster|steer|swivel|castor|omni|mecanum|roller", re.IGNORECASE)
_IMU = re.compile(r"(^|[_-])imu($|[_-])", re.IGNORECASE)


def _rpy_text(rpy: tuple[float, float, float]) -> str:
    return " ".join(fmt(v) for v in rpy)


@register
class OpticalFrameRotation(IntentRule):
    """An `*_optical_frame` is not rotated by the optical transform from its camera frame.

    ## What it does
    For each link whose name ends in `_optical_frame` (or `_optical`), takes
    the fixed joint from its parent. Unless the parent is itself an optical
    frame, the joint's rotation must be the standard optical transform
    `rpy="-1.5708 0 -1.5708"` (within 2°, option `angle_tolerance_deg`).

    ## Why it matters
    REP 103, *Suffix Frames*: "`_optical`: z forward, x right, y down", while
    the camera's body frame is x forward, y left, z up. Image pipelines
    (`image_geometry`, `depth_image_proc`, every point cloud) project pixels
    through the optical frame; an unrotated optical frame puts the point
    cloud on the floor or the ceiling.

    ## Example
    ```xml
    <joint name="camera_optical_joint" type="fixed">
      <parent link="camera_link"/><child link="camera_optical_frame"/>
      <origin xyz="0 0 0" rpy="0 0 0"/>
    </joint>
    ```

    ## Fix
    `<origin xyz="0 0 0" rpy="${-pi/2} 0 ${-pi/2}"/>`. If the parent is a
    mount, not the camera body, add the camera frame between them. Silence
    with `<!-- urdftool: ignore[optical-frame-rotation] -->`.
    """

    code = "N101"
    name = "optical-frame-rotation"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        tolerance = math.radians(option(ctx, "angle_tolerance_deg"))
        expected = rpy_to_matrix(OPTICAL_RPY)
        for joint in ctx.robot.joints:
            if not _OPTICAL.search(joint.child) or _OPTICAL.search(joint.parent):
                continue
            if joint.type is not JointType.FIXED:
                continue
            error = rotation_angle(joint.origin.rotation.T @ expected)
            if error <= tolerance:
                continue
            yield self.diagnostic(
                f"joint '{joint.name}': optical frame '{joint.child}' is rotated "
                f"rpy=\"{_rpy_text(joint.origin.rpy)}\" from '{joint.parent}', "
                f"{fmt(math.degrees(error))}° from the optical transform "
                "(REP 103: z forward, x right, y down)",
                joint.span,
                element=where_joint(joint, "origin"),
                help='the optical frame of a camera body frame is rpy="-1.5708 0 -1.5708"',
                data={
                    "rpy": list(joint.origin.rpy),
                    "expected_rpy": list(OPTICAL_RPY),
                    "error_deg": math.degrees(error),
                },
            )


@register
class BaseFootprintOffGround(IntentRule):
    """`base_footprint` is not the projection of `base_link` on the ground.

    ## What it does
    Takes the fixed joint between `base_footprint` and `base_link` (either
    way round) and reports when `base_link` is not straight above the
    footprint: a horizontal offset over 5 mm (option `offset_tolerance`), a
    rotation over 2° (option `angle_tolerance_deg`), or `base_link` below
    the ground.

    ## Why it matters
    REP 120 (and the navigation stack after it): "`base_footprint` is the
    representation of the robot position on the floor", with z = 0 on the
    ground and x, y those of `base_link`. Costmaps, localisation and
    odometry publish the footprint; an offset or tilted footprint moves the
    whole robot in the map.

    ## Example
    ```xml
    <joint name="base_footprint_joint" type="fixed">
      <parent link="base_footprint"/><child link="base_link"/>
      <origin xyz="0.1 0 0.05" rpy="0 0 0"/>
    </joint>
    ```

    ## Fix
    `<origin xyz="0 0 0.05" rpy="0 0 0"/>`: only a height. Silence with
    `<!-- urdftool: ignore[base-footprint-off-ground] -->`.
    """

    code = "N102"
    name = "base-footprint-off-ground"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        offset_tol = option(ctx, "offset_tolerance")
        angle_tol = math.radians(option(ctx, "angle_tolerance_deg"))
        for joint in ctx.robot.joints:
            pair = {joint.parent, joint.child}
            if pair != {"base_footprint", "base_link"} or joint.type is not JointType.FIXED:
                continue
            pose = joint.origin if joint.parent == "base_footprint" else joint.origin.inverse()
            x, y, z = pose.xyz
            tilt = rotation_angle(pose.rotation)
            problems = []
            if math.hypot(x, y) > offset_tol:
                problems.append(f"offset {fmt(x)} {fmt(y)} m horizontally")
            if tilt > angle_tol:
                problems.append(f"rotated {fmt(math.degrees(tilt))}°")
            if z < -offset_tol:
                problems.append(f"{fmt(-z)} m below the ground")
            if not problems:
                continue
            yield self.diagnostic(
                f"joint '{joint.name}': base_link is " + ", ".join(problems) + " from base_footprint "
                "(REP 120: the footprint is base_link's projection on the floor)",
                joint.span,
                element=where_joint(joint, "origin"),
                help=f'base_footprint → base_link should be xyz="0 0 {fmt(max(z, 0.0))}" rpy="0 0 0"',
                data={"xyz": list(pose.xyz), "rpy": list(pose.rpy), "tilt_deg": math.degrees(tilt)},
            )


@register
class WheelAxisNotLateral(IntentRule):
    """A drive wheel turns about an axis other than the base's ±y.

    ## What it does
    Off by default (`--select wheel-axis-not-lateral`). For each continuous
    or revolute joint whose child link's name contains `wheel` (and not
    `caster`, `steer`, `omni`, `mecanum`, `roller`), expresses the joint axis
    in the root link's frame at home and reports it when it is more than 2°
    (option `angle_tolerance_deg`) from ±y.

    ## Why it matters
    REP 103: the base's x is forward, y left, z up. A forward-driving base's
    wheels turn about y; a diff-drive controller or Gazebo plugin that
    spins a wheel about x or z drives sideways, or spins the wheel like a
    top. The usual cause is a cylinder rotated for display and the joint
    axis copied with it, or a base frame whose x is not forward.

    ## Example
    ```xml
    <joint name="left_wheel_joint" type="continuous">
      <parent link="base_link"/><child link="left_wheel"/><axis xyz="1 0 0"/>
    </joint>
    ```

    ## Fix
    `<axis xyz="0 1 0"/>` (or `0 0 1` under an `rpy="-1.5708 0 0"` origin).
    Not for steered, omni or mecanum bases: leave the rule off there.
    """

    code = "N103"
    name = "wheel-axis-not-lateral"
    severity = Severity.WARNING
    default_enabled = False

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        tolerance = math.radians(option(ctx, "angle_tolerance_deg"))
        poses = home_poses(ctx)
        for joint in ctx.robot.joints:
            if joint.type not in (JointType.CONTINUOUS, JointType.REVOLUTE):
                continue
            if not _WHEEL.search(joint.child) or _NOT_DRIVE.search(joint.child + joint.name):
                continue
            parent = poses.get(joint.parent)
            if parent is None:
                continue
            axis = parent[:3, :3] @ joint.origin.rotation @ np.asarray(joint.axis, dtype=float)
            error = angle_between(axis, np.array([0.0, 1.0, 0.0]))
            if error <= tolerance:
                continue
            yield self.diagnostic(
                f"joint '{joint.name}': wheel '{joint.child}' turns about "
                f"({', '.join(fmt(float(v)) for v in axis / np.linalg.norm(axis))}) in the base frame, "
                f"{fmt(math.degrees(error))}° from ±y (REP 103: x forward, y left, z up)",
                joint.span,
                element=where_joint(joint, "axis"),
                help="a forward-driving wheel turns about the base's y axis",
                data={"axis_in_base": [float(v) for v in axis], "error_deg": math.degrees(error)},
            )


@register
class ImuFrameNotAligned(IntentRule):
    """An IMU frame is not aligned with the base's axes.

    ## What it does
    Off by default (`--select imu-frame-not-aligned`). For each link whose
    name has an `imu` token (`imu_link`, `base_imu`) on a fixed joint,
    reports when one of its axes is more than 2° (option
    `angle_tolerance_deg`) from every axis of the link it is mounted on: a
    frame tilted by a rotation that is not a multiple of 90°.

    ## Why it matters
    REP 145: IMU data is reported in the sensor's frame, and the frame in
    the URDF must be the one the sensor measures in; REP 103 puts the base
    at x forward, y left, z up. IMUs are mounted square to the body almost
    always, so a tilted frame usually means an rpy written in degrees, or
    in the wrong order, and a state estimator that sees gravity on the
    wrong axis.

    ## Example
    ```xml
    <joint name="imu_joint" type="fixed">
      <parent link="base_link"/><child link="imu_link"/>
      <origin xyz="0 0 0.1" rpy="0 0.3 0"/>
    </joint>
    ```

    ## Fix
    Write the mount's real rotation, a multiple of 90° (`rpy="0 0 0"`,
    `rpy="3.14159 0 0"` for upside down). Leave the rule off for an IMU
    that is really mounted at an angle.
    """

    code = "N104"
    name = "imu-frame-not-aligned"
    severity = Severity.WARNING
    default_enabled = False

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        tolerance = math.radians(option(ctx, "angle_tolerance_deg"))
        for joint in ctx.robot.joints:
            if not _IMU.search(joint.child) or joint.type is not JointType.FIXED:
                continue
            relative = joint.origin.rotation
            worst = max(
                min(angle_between(relative[:, i], np.eye(3)[:, k]) for k in range(3)) for i in range(3)
            )
            if worst <= tolerance:
                continue
            rpy = matrix_to_rpy(relative)
            yield self.diagnostic(
                f"IMU frame '{joint.child}' is rotated rpy=\"{_rpy_text(rpy)}\" from '{joint.parent}': an "
                f"axis is {fmt(math.degrees(worst))}° from every axis of the body it is mounted on (REP 145)",
                joint.span,
                element=where_joint(joint, "origin"),
                help="IMU frames are square to the body: rotations by multiples of 90°",
                data={"rpy": list(rpy), "error_deg": math.degrees(worst)},
            )
