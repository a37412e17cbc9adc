"""ROS 1 ros_control transmissions (G006): the hardware interface each joint exports.

``gazebo_ros_control`` and ros_control's ``TransmissionParser`` read a
``<transmission>`` of the ros_control format (a ``<type>`` child element,
``transmission_interface/…``) joint by joint: a joint without its own
``<hardwareInterface>`` is skipped, and ``DefaultRobotHWSim`` refuses an
interface name it does not know. PR2-style transmissions (a ``type``
attribute) are read by pr2_mechanism instead and are not checked here; a
robot with ``<ros2_control>`` blocks is driven by ros2_control, which ignores
top-level transmissions, so they are not checked either. Evidence and
decisions: ``docs/gazebo.md``.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.catalogue.suggest import closest
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts.context import CheckContext
from urdftool.parse.locate import span_of

PREFIX = "hardware_interface/"

#: ros_control's interface classes a ``<hardwareInterface>`` may name (ROS 1
#: hardware_interface and the joint-mode and sensor interfaces of ros_control).
KNOWN_INTERFACES = frozenset(
    {
        "EffortJointInterface",
        "VelocityJointInterface",
        "PositionJointInterface",
        "PosVelJointInterface",
        "PosVelAccJointInterface",
        "JointStateInterface",
        "JointModeInterface",
        "EffortActuatorInterface",
        "VelocityActuatorInterface",
        "PositionActuatorInterface",
        "ActuatorStateInterface",
        "ImuSensorInterface",
        "ForceTorqueSensorInterface",
    }
)

#: How alike (difflib ratio) a name must be to a known interface to be called a misspelling of
#: it: one or two letters in a 20-letter name. Vendors' interfaces share words with ros_control's
#: ("JointCommandInterface" and "JointModeInterface" are 0.82 alike) and must stay quiet.
TYPO_SIMILARITY = 0.85


def _text(element: Any) -> str:
    return (element.text or "").strip()


def ros_control_transmissions(ctx: CheckContext) -> Iterator[Any]:
    """Top-level ``<transmission>`` elements of the ros_control format that ROS 1 reads."""
    extensions = ctx.robot.extensions
    if any(e.tag == "ros2_control" for e in extensions):
        return
    for extension in extensions:
        element = extension.element
        if extension.tag != "transmission" or element is None:
            continue
        kind = next(element.iterchildren("type"), None)  # find("type") without ElementPath's setup
        if kind is None or not _text(kind).startswith("transmission_interface/"):
            continue
        yield element


@register
class TransmissionHardwareInterface(Rule):
    """A ros_control `<transmission>` joint has no `<hardwareInterface>`, or a misspelt one.

    ## What it does
    For every top-level `<transmission>` of the ros_control format (`<type>
    transmission_interface/…</type>`) in a robot without `<ros2_control>`
    blocks, checks that each `<joint>` has its own `<hardwareInterface>`, and
    that every `<hardwareInterface>` names one of ros_control's interfaces
    (`hardware_interface/EffortJointInterface`, `…/PositionJointInterface`,
    `…/VelocityJointInterface`, …). A name close to a known one is reported
    with the name it looks like; a name far from all of them may be a
    vendor's own interface and is left alone. A bare name without the
    `hardware_interface/` prefix is an info: ROS 1 Kinetic and later accept
    it with a deprecation warning, Indigo accepted only the bare name.

    ## Why it matters
    ros_control's transmission parser reads the interface from the
    `<joint>`, not from the `<actuator>`: a joint that has it only under
    `<actuator>` is skipped ("No valid hardware interface element found in
    joint"), so `gazebo_ros_control` never exports it and its controller
    waits forever. A misspelt name makes `DefaultRobotHWSim` stop loading the
    whole robot ("No matching hardware interface found").

    ## Example
    ```xml
    <transmission name="shoulder_trans">
      <type>transmission_interface/SimpleTransmission</type>
      <joint name="shoulder"/>                          <!-- no hardwareInterface -->
      <actuator name="shoulder_motor">
        <hardwareInterface>hardware_interface/EffortJointInterface</hardwareInterface>
      </actuator>
    </transmission>
    ```

    ## Fix
    Put `<hardwareInterface>hardware_interface/EffortJointInterface</hardwareInterface>`
    (or the position or velocity interface your controllers claim) inside
    the `<joint>`; spell the interface as ros_control does.
    """

    code = "G006"
    name = "transmission-hardware-interface"
    severity = Severity.WARNING
    family = Family.GAZEBO

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for transmission in ros_control_transmissions(ctx):
            label = transmission.get("name") or "unnamed"
            # lxml's tag filter, as findall() of a bare tag, without ElementPath's setup per call
            for joint in transmission.iterchildren("joint"):
                interface = next(joint.iterchildren("hardwareInterface"), None)
                if interface is None and joint.get("name"):
                    yield self._missing(transmission, label, joint)
            for element in transmission.iter("hardwareInterface"):
                yield from self._named(label, element)

    def _missing(self, transmission: Any, label: str, joint: Any) -> Diagnostic:
        name = joint.get("name")
        from_actuator = [
            _text(e) for e in transmission.findall("actuator/hardwareInterface") if _text(e)
        ]
        suggestion = from_actuator[0] if from_actuator else PREFIX + "EffortJointInterface"
        return self.diagnostic(
            f"transmission '{label}': joint '{name}' has no <hardwareInterface>"
            + (" (the <actuator> has one; ros_control reads the joint's)" if from_actuator else ""),
            span_of(joint),
            element=f"transmission[{label}]/joint[{name}]",
            help=f"ros_control skips the joint; add <hardwareInterface>{suggestion}"
            "</hardwareInterface> inside <joint>",
            data={"joint": name, "suggested": suggestion},
        )

    def _named(self, label: str, element: Any) -> Iterator[Diagnostic]:
        value = _text(element)
        if not value or "$" in value:
            return
        bare = value[len(PREFIX) :] if value.startswith(PREFIX) else value
        if bare in KNOWN_INTERFACES:
            if bare == value:
                yield self.diagnostic(
                    f"transmission '{label}': hardware interface '{value}' has no "
                    f"'{PREFIX}' prefix",
                    span_of(element),
                    element=f"transmission[{label}]/hardwareInterface",
                    help=f"ROS 1 Kinetic and later read it with a deprecation warning; write "
                    f"{PREFIX}{value}",
                    data={"interface": value, "suggested": PREFIX + value},
                    severity=Severity.INFO,
                )
            return
        # difflib's closest match, each misspelling looked up once (a transmission per joint)
        match = closest(bare, KNOWN_INTERFACES, TYPO_SIMILARITY)
        if match is None:
            return  # far from every ros_control name: a vendor's own interface
        meant = PREFIX + match if value.startswith(PREFIX) else match
        yield self.diagnostic(
            f"transmission '{label}': '{value}' is not a ros_control hardware interface; "
            f"did you mean '{meant}'?",
            span_of(element),
            element=f"transmission[{label}]/hardwareInterface",
            help="gazebo_ros_control stops loading the robot on an interface it does not know; "
            f"use one of {PREFIX}EffortJointInterface, PositionJointInterface, "
            "VelocityJointInterface",
            data={"interface": value, "suggested": meant},
        )
