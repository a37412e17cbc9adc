"""MJCF actuators (``--actuators none|position|velocity|motor|auto``) and joint armature.

Every 1-DOF joint with a positive, finite effort that is not a mimic follower
gets one actuator named after the joint. ``auto`` picks the kind per joint from
the source: the command interface of its ``<transmission>``
(``PositionJointInterface`` → position, ``VelocityJointInterface`` →
velocity, ``EffortJointInterface`` → motor) or ``<ros2_control>`` joint
(``<command_interface name="position|velocity|effort">``); wheels (a
continuous joint of a robot that moves on wheels) get velocity; every other
joint a position servo, so that an ``auto`` export holds its home pose.

Gains come from the joint's reflected inertia and a target bandwidth:

    I  = inertia about the axis (kg·m²) or mass along it (kg) of everything the
         joint moves, at the home configuration, plus the joint's armature
    ω  = 2π · f,  f = :data:`BANDWIDTH_HZ` (10 Hz)
    G  = g Σ mᵢ rᵢ, the largest gravity torque the joint can meet (rᵢ: distance of
         each moved link's centre of mass from the axis; for a slide G = g Σ mᵢ)
         (a free robot adds its whole mass at the farthest point the joint moves
         when the joint moves a link it stands on: a link whose collision geometry
         reaches within :data:`STANCE_BAND` of the lowest point at home)
    position: kp = max(I ω², G / e) with e = :data:`HOLD_ERROR` (5 mrad, 1 mm);
              kv = max(2 ζ √(kp I), kp · dt) with ζ = 1 (critically damped) and
              dt = :data:`TIMESTEP`: with the damping integrated implicitly
              (``implicitfast``), symplectic Euler is stable when kp dt² < 4 I + 2 kv dt,
              which kv ≥ kp dt guarantees for any I (a stiff servo on a light
              link becomes overdamped, time constant kv / kp ≥ dt, instead of exploding)
    velocity: kv = I ω    (first order, time constant 1/ω)
    motor:    gear 1, ctrlrange = ±effort

``forcerange`` (position, velocity) is ±effort. A joint's armature is the
rotor inertia reflected through its reduction, ``rotor · reduction²``, when a
``<transmission>`` gives ``<mechanicalReduction>`` and a rotor inertia
(``<motorInertia>`` or ``<rotorInertia>`` in its ``<actuator>``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
from lxml import etree

from urdftool.export.mjcf_bodies import MjJoint, unit_axis
from urdftool.export.mjcf_extras import actuated_joints, moved_inertia
from urdftool.export.numbers import num, vec
from urdftool.export.placement import bounding_radius, lowest_point
from urdftool.model import Inertial, Joint, JointType, KinematicTree, Robot
from urdftool.physics.mobility import mobility
from urdftool.records import record

#: Target closed-loop bandwidth (Hz) of position and velocity actuators.
BANDWIDTH_HZ = 10.0
#: Largest static error (rad, m) a position actuator may leave under gravity.
HOLD_ERROR = {"hinge": 0.005, "slide": 0.001}
#: MuJoCo's default time step (s), which the exported models keep: kv ≥ kp · TIMESTEP keeps a
#: servo stable under the implicit integrator however small the inertia it moves.
TIMESTEP = 0.002
GRAVITY = 9.81
#: Links whose collision geometry reaches this close (m) to the robot's lowest point carry it.
STANCE_BAND = 0.02
#: Damping ratio of position actuators.
DAMPING_RATIO = 1.0
#: Floor (kg·m² or kg) under the reflected inertia, so a joint moving nothing still gets kp > 0.
MIN_INERTIA = 1e-6
MODES = ("none", "position", "velocity", "motor", "auto")
_INTERFACES = {"position": "position", "velocity": "velocity", "effort": "motor"}


@record
class Drive:
    """What the source says about one joint's actuation."""

    interface: str | None = None  # "position" | "velocity" | "motor"
    reduction: float | None = None
    rotor_inertia: float | None = None

    @property
    def armature(self) -> float | None:
        if self.rotor_inertia is None or self.rotor_inertia <= 0:
            return None
        reduction = self.reduction if self.reduction is not None else 1.0
        return self.rotor_inertia * reduction * reduction


def _local(tag: object) -> str:
    return tag.split("}")[-1] if isinstance(tag, str) else ""


def _number(element: etree._Element, *names: str) -> float | None:
    for child in element.iter():
        if _local(child.tag) in names and child.text:
            try:
                value = float(child.text.strip())
            except ValueError:
                continue
            if math.isfinite(value):
                return value
    return None


def _interface(text: str) -> str | None:
    lower = text.lower()
    for word, kind in _INTERFACES.items():
        if word in lower:
            return kind
    return None


def drives(robot: Robot) -> dict[str, Drive]:
    """Per joint name: its command interface, reduction and rotor inertia from the source."""
    found: dict[str, Drive] = {}
    for ext in robot.extensions:
        if ext.element is None:
            continue
        if ext.tag == "transmission":
            actuator = next((c for c in ext.element.iter() if _local(c.tag) == "actuator"), None)
            reduction = _number(actuator, "mechanicalReduction") if actuator is not None else None
            rotor = _number(actuator, "motorInertia", "rotorInertia") if actuator is not None else None
            for joint in ext.element.iter():
                if _local(joint.tag) != "joint" or not joint.get("name"):
                    continue
                words = " ".join(c.text or "" for c in ext.element.iter()
                                 if _local(c.tag) == "hardwareInterface")
                found[joint.get("name", "")] = Drive(_interface(words), reduction, rotor)
        elif ext.tag == "ros2_control":
            for joint in ext.element.iter():
                if _local(joint.tag) != "joint" or not joint.get("name"):
                    continue
                commands = [c.get("name", "") for c in joint if _local(c.tag) == "command_interface"]
                kinds = [_INTERFACES[c] for c in commands if c in _INTERFACES]
                previous = found.get(joint.get("name", ""), Drive())
                found[joint.get("name", "")] = Drive(kinds[0] if kinds else previous.interface,
                                                     previous.reduction, previous.rotor_inertia)
    return found


def _is_wheel(robot: Robot, name: str, moves_on_wheels: bool) -> bool:
    joint = robot.joint(name)
    if joint is None or joint.type is not JointType.CONTINUOUS:
        return False
    return moves_on_wheels or "wheel" in f"{joint.name} {joint.child}".lower()


def gravity_moment(tree: KinematicTree, inertials: Mapping[str, Inertial | None], joint: Joint,
                   q: Mapping[str, float], carried: float = 0.0) -> float:
    """The largest gravity torque (N·m) or force (N) on *joint* from what it moves, over all
    orientations: g Σ mᵢ rᵢ for a hinge (rᵢ from the axis), g Σ mᵢ for a slide; plus a mass
    *carried* at the farthest point it moves (link origins, and collision shapes by their bounding
    spheres: a free robot standing on that limb)."""
    poses = tree.forward_kinematics(dict(q))
    frame = poses[joint.child]
    axis = frame[:3, :3] @ np.asarray(unit_axis(joint))
    anchor = frame[:3, 3]
    total = 0.0
    reach = 0.0
    for _, link, _ in tree.walk(joint.child):
        tip = poses[link.name][:3, 3] - anchor
        reach = max(reach, float(np.linalg.norm(tip - float(tip @ axis) * axis)))
        for collision in link.collisions:  # a foot stands on its collision shape, not its origin
            centre = (poses[link.name] @ collision.origin.matrix)[:3, 3] - anchor
            reach = max(reach, float(np.linalg.norm(centre - float(centre @ axis) * axis))
                        + bounding_radius(collision.geometry))
        inertial = inertials.get(link.name)
        if inertial is None:
            continue
        if joint.type is JointType.PRISMATIC:
            total += inertial.mass
            continue
        offset = (poses[link.name] @ inertial.origin.matrix)[:3, 3] - anchor
        total += inertial.mass * float(np.linalg.norm(offset - float(offset @ axis) * axis))
    if carried:
        total += carried * (1.0 if joint.type is JointType.PRISMATIC else reach)
    return GRAVITY * total


def stance_links(robot: Robot, tree: KinematicTree, q: Mapping[str, float]) -> set[str]:
    """The links a free robot stands on at *q*: those whose collision geometry reaches within
    :data:`STANCE_BAND` of the robot's lowest collision point, and the links a loop closure ties
    to them."""
    poses = tree.forward_kinematics(dict(q))
    lowest: dict[str, float] = {}
    for link in robot.links:
        frame = poses.get(link.name)
        if frame is None:
            continue
        for collision in link.collisions:
            z = lowest_point(collision.geometry, frame @ collision.origin.matrix)
            if z is not None:
                lowest[link.name] = min(z, lowest.get(link.name, z))
    if not lowest:
        return set()
    floor = min(lowest.values())
    feet = {name for name, z in lowest.items() if z <= floor + STANCE_BAND}
    grown = True
    while grown:  # a link tied to a foot by a loop closure carries it too (Cassie's plantar rods)
        ties = {c.joint.parent for c in robot.loop_closures if c.joint.child in feet}
        ties |= {c.joint.child for c in robot.loop_closures if c.joint.parent in feet}
        grown = not ties <= feet
        feet |= ties
    return feet


def write_armature(body_root: etree._Element, robot: Robot,
                   geared: Mapping[str, float] | None = None) -> dict[str, float]:
    """Set ``armature`` on joints whose transmission gives a rotor inertia, plus *geared* (the
    reflected rotor inertia of SDF gearbox closures); returns them."""
    armature: dict[str, float] = {
        name: d.armature for name, d in drives(robot).items() if d.armature is not None}
    for name, extra in (geared or {}).items():
        armature[name] = armature.get(name, 0.0) + extra
    if not armature:
        return {}
    for element in body_root.iter("joint"):
        value = armature.get(element.get("name", ""))
        if value is not None:
            element.set("armature", num(value))
    return armature


def write_actuators(root: etree._Element, robot: Robot, tree: KinematicTree, joints: Sequence[MjJoint],
                    inertials: Mapping[str, Inertial | None], mode: str,
                    armature: Mapping[str, float], free_base: bool = False) -> list[str]:
    """The ``<actuator>`` section for *mode*; returns the actuated joint names."""
    if mode == "none":
        return []
    actuated = actuated_joints(robot, joints)
    if not actuated:
        return []
    source = drives(robot) if mode == "auto" else {}
    wheels = (mobility(robot, tree) or "") == "wheels"
    home = dict(robot.home or {})
    section = etree.SubElement(root, "actuator")
    omega = 2 * math.pi * BANDWIDTH_HZ
    # a free robot stands on its limbs: each joint may carry the whole robot at its tip
    carried = sum(i.mass for i in inertials.values() if i is not None) if free_base else 0.0
    feet = stance_links(robot, tree, home) if carried else set()
    names = []
    for mj, joint, effort in actuated:
        kind = mode
        if mode == "auto":
            declared = source.get(joint.name, Drive()).interface
            kind = declared or ("velocity" if _is_wheel(robot, joint.name, wheels) else "position")
        reflected = moved_inertia(tree, inertials, joint, home) + armature.get(joint.name, 0.0)
        inertia = max(MIN_INERTIA, reflected)
        # an unlimited effort (SDF's default) gets no force range
        force = {"forcerange": vec((-effort, effort))} if math.isfinite(effort) else {}
        names.append(mj.name)
        if kind == "motor":
            limits = {"ctrlrange": force["forcerange"]} if force else {}
            etree.SubElement(section, "motor", {"name": mj.name, "joint": mj.name, **limits})
        elif kind == "velocity":
            etree.SubElement(section, "velocity", {"name": mj.name, "joint": mj.name,
                                                   "kv": num(inertia * omega), **force})
        else:
            stands = any(link.name in feet for _, link, _ in tree.walk(joint.child))
            load = gravity_moment(tree, inertials, joint, home, carried if stands else 0.0)
            hold = load / HOLD_ERROR[mj.kind]
            kp = max(inertia * omega * omega, hold)
            kv = max(2 * DAMPING_RATIO * math.sqrt(kp * inertia), kp * TIMESTEP)
            attrs = {"name": mj.name, "joint": mj.name, "kp": num(kp), "kv": num(kv), **force}
            if mj.range is not None:
                attrs["ctrlrange"] = vec(mj.range)
            etree.SubElement(section, "position", attrs)
    return names
