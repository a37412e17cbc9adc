"""Links and frames named by Gazebo classic ROS plugins (G007).

``gazebo_ros`` plugins (ROS 1 camelCase, ROS 2 snake_case) name links of the
robot in two ways: a *body* the plugin acts on or measures (``bodyName``,
``body_name``: the plugin looks the link up and does not load without it),
and the *frame* it publishes in (``robotBaseFrame``, ``frameName``,
``robot_base_frame``, ``frame_name``: the TF frame of odometry, IMU, camera
and ground-truth messages, which must be a link of the robot for the TF tree
to connect). Frames outside the robot (``world``, ``map``, ``odom``) and
namespaced names (``robot1/base_link``, set by ``tf_prefix``) are left alone.
gz-sim systems publish in frames of their own naming (``model/base_link``) and
are not checked here.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.catalogue.suggest import did_you_mean
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts import gazebo
from urdftool.facts.context import CheckContext
from urdftool.parse.locate import span_of
from urdftool.rules import gazebo_plugins as gz

#: Plugin children whose text names a link the plugin acts on (it fails to load without it).
BODY_TAGS = frozenset({"bodyName", "body_name"})
#: Plugin children whose text names the TF frame the plugin publishes in.
FRAME_TAGS = frozenset({"robotBaseFrame", "robot_base_frame", "frameName", "frame_name"})
_NAMING_TAGS = BODY_TAGS | FRAME_TAGS
#: Frames that are not links of a robot by convention (REP 105) or by Gazebo's naming.
EXTERNAL_FRAMES = frozenset({"world", "map", "odom", "earth", "/world", "/map", "/odom"})


def _is_gazebo_ros(plugin: Any) -> bool:
    filename = plugin.get("filename") or ""
    return "gazebo_ros" in filename


@register
class PluginFrameMissing(Rule):
    """A Gazebo ROS plugin names a body or frame that is not a link of the robot.

    ## What it does
    Checks the link names that `gazebo_ros` plugins (ROS 1 and ROS 2) read
    from `bodyName`/`body_name` (the link the plugin acts on or measures:
    P3D ground truth, IMU, force) and from `robotBaseFrame`/`robot_base_frame`
    and `frameName`/`frame_name` (the TF frame of the messages it publishes:
    diff drive odometry, IMU, cameras), against the robot's links, with the
    closest name. `world`, `map`, `odom`, namespaced names and unexpanded
    substitutions are left alone.

    ## Why it matters
    A missing body makes the plugin refuse to load ("body not found"). A
    missing frame is worse because nothing fails: the diff drive publishes
    `odom → base_footprint` while robot_state_publisher's tree starts at
    `base_link`, so the TF tree is split, navigation cannot localise the
    robot and RViz shows it at the origin.

    ## Example
    ```xml
    <plugin name="diff_drive" filename="libgazebo_ros_diff_drive.so">
      <robotBaseFrame>base_footprint</robotBaseFrame>   <!-- the robot starts at base_link -->
    </plugin>
    ```

    ## Fix
    Name an existing link (usually the root, `base_footprint` or
    `base_link`), or add the frame as a link with a fixed joint.
    """

    code = "G007"
    name = "plugin-frame-missing"
    severity = Severity.WARNING
    family = Family.GAZEBO

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        links = {link.name for link in ctx.robot.links}
        for plugin in gazebo.plugins(ctx):
            if not _is_gazebo_ros(plugin):
                continue
            label = gz.plugin_label(plugin)
            for child in plugin:
                if not isinstance(child.tag, str) or child.tag not in _NAMING_TAGS:
                    continue
                name = gz.text_of(child)
                if (
                    not name
                    or len(child)
                    or "$" in name
                    or "/" in name.strip("/")
                    or name in EXTERNAL_FRAMES
                    or name.lstrip("/") in links
                ):
                    continue
                body = child.tag in BODY_TAGS
                yield self.diagnostic(
                    f"{label}: <{child.tag}> '{name}' is not a link of the robot"
                    + did_you_mean(name, links),
                    span_of(child),
                    element=f"plugin[{plugin.get('name') or 'unnamed'}]/{child.tag}",
                    help="the plugin does not load without its body"
                    if body
                    else "its messages are stamped with a frame the robot's TF tree does not have, "
                    "so the tree is split; name an existing link",
                    data={"tag": child.tag, "name": name},
                    severity=Severity.ERROR if body else None,
                )
