"""What urdftool knows about Gazebo and ros_control extension blocks inside a URDF.

Readers keep ``<gazebo>``, ``<transmission>`` and ``<ros2_control>`` as
:class:`~urdftool.model.Extension` elements; this module finds in them the
names of joints and links they refer to, and the parameters of drive plugins.
Element tags are those of the plugins' own documentation:

* ROS 1 ``gazebo_ros`` (camelCase: ``leftJoint``, ``wheelSeparation``),
* ROS 2 ``gazebo_ros`` (snake_case, repeatable for several wheel pairs),
* gz-sim / Ignition systems (``left_joint``, ``wheel_radius``),
* plugins seen in the corpora (roboticsgroup's mimic joint plugin, the
  underactuated finger plugin, the force/torque sensor plugin).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator
from dataclasses import field
from typing import Any

from urdftool.facts import gazebo as facts
from urdftool.model import Robot
from urdftool.records import record

#: Plugin child elements whose text names one joint (or, for ``jointName``, a
#: comma-separated list of joints).
JOINT_TAGS = frozenset(
    {
        "leftJoint",
        "rightJoint",
        "left_joint",
        "right_joint",
        "leftFrontJoint",
        "leftRearJoint",
        "rightFrontJoint",
        "rightRearJoint",
        "front_left_joint",
        "back_left_joint",
        "back_right_joint",
        "control_joint_name",
        "cabin_joint",
        "front_right_joint",
        "rear_left_joint",
        "rear_right_joint",
        "left_steering_joint",
        "right_steering_joint",
        "steering_wheel_joint",
        "steeringJoint",
        "actuatedWheelJoint",
        "jointName",
        "joint_name",
        "joint",
        "mimicJoint",
        "actuatedJoint",
        "virtualJoint",
    }
)

#: ``<transmission>`` children that name a joint in a ``name`` attribute (ROS 1
#: transmissions, including PR2's wrist and gripper transmissions).
TRANSMISSION_JOINT_TAGS = frozenset(
    {"joint", "flexJoint", "rollJoint", "gap_joint", "passive_joint"}
)

_SPLIT = re.compile(r"[,\s]+")


@record
class JointRef:
    """A joint named by an extension: the name, the element naming it, and who names it."""

    name: str
    element: Any
    owner: str


#: Every top-level ``<gazebo>`` element, as lxml elements. A rule asks
#: :func:`urdftool.facts.gazebo.gazebo_blocks` instead, which finds them once per model.
gazebo_blocks = facts.blocks_of
#: Every ``<plugin>`` in ``<gazebo>`` blocks (at any depth: sensors carry plugins too) and at the
#: top level of the robot; once per model: :func:`urdftool.facts.gazebo.plugins`.
plugins = facts.plugins_of


def plugin_label(plugin: Any) -> str:
    """``plugin 'name' (libfile.so)`` in the user's words."""
    name = plugin.get("name") or "unnamed"
    filename = plugin.get("filename")
    return f"plugin '{name}'" + (f" ({filename})" if filename else "")


def text_of(element: Any) -> str:
    return (element.text or "").strip()


def plugin_joint_refs(plugin: Any) -> Iterator[JointRef]:
    """Joints named by a plugin's own child elements (not those of nested plugins)."""
    label = plugin_label(plugin)
    for child in plugin:
        if not isinstance(child.tag, str) or child.tag not in JOINT_TAGS:
            continue
        if len(child) or not text_of(child) or "$" in text_of(child):
            continue  # structured element, empty, or an unexpanded substitution
        for name in _SPLIT.split(text_of(child)):
            if name:
                yield JointRef(name, child, label)


def transmission_joint_refs(robot: Robot) -> Iterator[JointRef]:
    """Joints named by ROS 1 ``<transmission>`` and ros2_control ``<ros2_control>`` blocks."""
    for extension in robot.extensions:
        element = extension.element
        if element is None:
            continue
        if extension.tag == "transmission":
            owner = f"transmission '{element.get('name') or 'unnamed'}'"
            for child in element:
                if isinstance(child.tag, str) and child.tag in TRANSMISSION_JOINT_TAGS:
                    yield from _named(child, owner)
        elif extension.tag == "ros2_control":
            owner = f"ros2_control '{element.get('name') or 'unnamed'}'"
            for child in element:
                if child.tag == "joint":
                    yield from _named(child, owner)
                elif child.tag == "transmission":
                    for grandchild in child:
                        if grandchild.tag == "joint":
                            yield from _named(grandchild, owner)


def _named(element: Any, owner: str) -> Iterator[JointRef]:
    name = element.get("name")
    if name is None and not len(element):
        name = text_of(element)  # the oldest style: <joint>name</joint>
    if name and "$" not in name:
        yield JointRef(name, element, owner)


# -- drive plugins -------------------------------------------------------------------------


@record(frozen=False)
class DrivePlugin:
    """A differential or skid-steer drive plugin's declared geometry.

    ``pairs`` are (left joint, right joint) in the order the plugin pairs
    them; ``separations`` the declared wheel separations (m), one per pair or
    one for all; ``diameter`` the declared wheel diameter (m), from
    ``wheel_radius`` for gz-sim. Each value keeps the element it came from.
    """

    element: Any
    kind: str
    pairs: list[tuple[str, str]] = field(default_factory=list)
    separations: list[tuple[float, Any]] = field(default_factory=list)
    diameter: tuple[float, Any] | None = None


def drive_kind(plugin: Any) -> str | None:
    """``diff-drive`` or ``skid-steer`` from the plugin's file and class name, else ``None``."""
    key = f"{plugin.get('filename', '')} {plugin.get('name', '')}".lower().replace("-", "_")
    if "skid_steer" in key:
        return "skid-steer"
    if "diff_drive" in key or "diffdrive" in key:
        return "diff-drive"
    return None


def drive_plugins(elements: Iterable[Any]) -> Iterator[DrivePlugin]:
    """The drive plugins among the ``<plugin>`` *elements* (:func:`urdftool.facts.gazebo.plugins`)."""
    for plugin in elements:
        kind = drive_kind(plugin)
        if kind is not None:
            yield _read_drive(plugin, kind)


def _read_drive(plugin: Any, kind: str) -> DrivePlugin:
    found = DrivePlugin(plugin, kind)
    values: dict[str, list[Any]] = {}
    for child in plugin:
        if isinstance(child.tag, str):
            values.setdefault(child.tag, []).append(child)
    if kind == "skid-steer":
        for front, rear in (
            ("leftFrontJoint", "rightFrontJoint"),
            ("leftRearJoint", "rightRearJoint"),
        ):
            if front in values and rear in values:
                found.pairs.append((text_of(values[front][0]), text_of(values[rear][0])))
    else:
        lefts = values.get("leftJoint", []) + values.get("left_joint", [])
        rights = values.get("rightJoint", []) + values.get("right_joint", [])
        found.pairs = [(text_of(a), text_of(b)) for a, b in zip(lefts, rights, strict=False)]
    for tag in ("wheelSeparation", "wheel_separation"):
        found.separations += [(v, e) for e in values.get(tag, []) if (v := _number(e)) is not None]
    for tag, factor in (("wheelDiameter", 1.0), ("wheel_diameter", 1.0), ("wheel_radius", 2.0)):
        for element in values.get(tag, [])[:1]:
            value = _number(element)
            if value is not None and found.diameter is None:
                found.diameter = (value * factor, element)
    return found


def _number(element: Any) -> float | None:
    try:
        return float(text_of(element))
    except ValueError:
        return None


def legacy_value_keys(blocks: Iterable[Any]) -> Iterator[tuple[Any, Any]]:
    """``(gazebo block, child)`` for each child of the ``<gazebo>`` *blocks*
    (:func:`urdftool.facts.gazebo.gazebo_blocks`) written ``<key value="…"/>`` with no text."""
    for block in blocks:
        for child in block:
            tag = child.tag
            if not isinstance(tag, str) or tag.startswith("{"):
                continue
            # a `value` attribute, even an empty one (`value=""`)
            if child.get("value") is not None and not text_of(child) and not len(child):
                yield block, child
