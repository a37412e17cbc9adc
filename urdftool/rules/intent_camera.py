"""Camera frames (N105): images stamped with a frame in the body convention (REP 103).

Gazebo's ROS camera plugins (``gazebo_ros_camera``, ``gazebo_ros_depth_camera``,
``gazebo_ros_openni_kinect`` and their ROS 2 ports) publish image and point-cloud data in
the optical convention (z forward, x right, y down) and stamp it with the frame the author
names in ``frameName``/``frame_name``. Naming the camera's body link (x forward, z up)
is the classic mistake: the data is then turned by 90° about two axes in RViz and in every
TF consumer. The evidence is geometric, not a name: the named frame has the same
orientation as the sensor itself.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator
from typing import Any

from urdftool.catalogue.registry import register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts.context import CheckContext
from urdftool.facts.home import Rotation, angle_between_frames, home_frames
from urdftool.parse.locate import span_of
from urdftool.physics import vec3
from urdftool.rules import gazebo_plugins as gz
from urdftool.rules.intent_common import IntentRule, option

#: Gazebo sensor types whose ROS plugins publish optical-convention data.
CAMERA_SENSORS = frozenset({"camera", "depth", "depth_camera", "rgbd", "rgbd_camera"})
FRAME_TAGS = ("frameName", "frame_name")


def _is_ros_camera_plugin(plugin: Any) -> bool:
    filename = (plugin.get("filename") or "").lower()
    return "gazebo_ros" in filename and any(k in filename for k in ("camera", "openni", "depth"))


def _pose_rotation(element: Any) -> Rotation:
    """The rotation of an element's ``<pose>`` child (identity when absent or unreadable)."""
    pose = element.find("pose") if element is not None else None
    values = (pose.text or "").split() if pose is not None else []
    rpy = (0.0, 0.0, 0.0)
    if len(values) == 6:
        with contextlib.suppress(ValueError):
            rpy = (float(values[3]), float(values[4]), float(values[5]))
    return vec3.rotation(rpy)  # non-finite angles count as 0


def _sensor_rotation(sensor: Any) -> Rotation:
    """The rotation of the camera that takes the images, in the reference link's frame: the
    ``<sensor><pose>``, then the ``<camera><pose>`` inside it (SDF: relative to the sensor;
    Baxter turns its head camera there)."""
    return vec3.product(_pose_rotation(sensor), _pose_rotation(sensor.find("camera")))


@register
class CameraFrameNotOptical(IntentRule):
    """A Gazebo camera plugin stamps its images with a frame in the body convention.

    ## What it does
    For every `<gazebo reference="LINK"><sensor type="camera|depth|rgbd">` whose
    `gazebo_ros` camera plugin names a frame (`frameName`, `frame_name`),
    compares the orientation of that frame with the camera's own (the
    reference link, turned by the sensor's `<pose>` and then by the
    `<camera><pose>` inside it). When they are the same
    (within the intent angle tolerance, 2° by default), the frame is in the
    body convention: x forward, z up.

    ## Why it matters
    The plugins publish image and point-cloud data in the optical convention
    of REP 103 (z forward, x right, y down). Stamped with a body frame, the
    point cloud stands on its side in RViz, and every consumer that
    transforms it through TF (navigation, perception, MoveIt's octomap)
    places obstacles in the wrong place.

    ## Convention
    REP 103, "Suffix Frames": a camera's data is expressed in a frame with the
    `_optical` suffix, rotated `rpy="-π/2 0 -π/2"` from the camera body frame.

    ## Example
    ```xml
    <gazebo reference="camera_link">
      <sensor type="camera" name="cam">
        <plugin name="cam" filename="libgazebo_ros_camera.so">
          <frameName>camera_link</frameName>
        </plugin>
      </sensor>
    </gazebo>
    ```

    ## Fix
    Add `camera_link_optical` on a fixed joint with `rpy="-1.5708 0 -1.5708"`
    below `camera_link`, and name it in `frameName`/`frame_name`. To silence:
    `<!-- urdftool: ignore[N105] -->` before the plugin.
    """

    code = "N105"
    name = "camera-frame-not-optical"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        tolerance = math.radians(option(ctx, "angle_tolerance_deg"))
        frames = None
        for block in gz.gazebo_blocks(ctx.robot):
            reference = block.get("reference")
            for sensor in block.iter("sensor"):
                if (sensor.get("type") or "") not in CAMERA_SENSORS or not reference:
                    continue
                for plugin in sensor.iter("plugin"):
                    if not _is_ros_camera_plugin(plugin):
                        continue
                    for child in plugin:
                        if not isinstance(child.tag, str) or child.tag not in FRAME_TAGS:
                            continue
                        frame = gz.text_of(child).lstrip("/")
                        if frames is None:
                            frames = home_frames(ctx)
                        if frame not in frames or reference not in frames:
                            continue  # not a link of the robot: plugin-frame-missing says so
                        sensor_rotation = vec3.product(frames[reference][0], _sensor_rotation(sensor))
                        if angle_between_frames(sensor_rotation, frames[frame][0]) > tolerance:
                            continue
                        yield self.diagnostic(
                            f"sensor '{sensor.get('name') or 'unnamed'}' ({sensor.get('type')}) "
                            f"publishes optical-convention data (z forward, x right, y down) "
                            f"stamped with '{frame}', which is oriented like the camera body "
                            "(x forward, z up)",
                            span_of(child),
                            element=f"gazebo[{reference}]/sensor/{child.tag}",
                            help=f"add a link '{frame}_optical' on a fixed joint with "
                            'rpy="-1.5708 0 -1.5708" below it and name that frame here (REP 103)',
                            data={"frame": frame, "reference": reference},
                        )
