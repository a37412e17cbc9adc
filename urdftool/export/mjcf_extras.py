"""Equality constraints (mimic joints, loop closures), the home keyframe, the scene, and the
joints that may carry actuators (written by :mod:`urdftool.export.mjcf_actuators`).

Joints without a positive effort get no actuator, nor do mimic followers (their
equality drives them); a joint whose source sets no effort limit (SDF's default,
unlimited) is actuated when it has a finite range, without a force range.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
from lxml import etree

from urdftool.catalogue.conversion import ConversionDropped
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.export.mjcf_bodies import MjJoint, clamp, unit_axis
from urdftool.export.mjcf_format import pose_attributes, transform_attributes
from urdftool.export.numbers import vec
from urdftool.model import Inertial, Joint, JointType, KinematicTree, LoopClosure, Robot
from urdftool.model.pose import Matrix


def _effort(joint: Joint) -> float | None:
    """The joint's effort limit; ``inf`` when the source sets none (SDF's default: unlimited) on a
    joint with a finite range; ``None`` (no actuator) for 0, or unlimited without a range."""
    limit = joint.limit
    effort = limit.effort if limit else None
    if effort is not None and 0 < effort < math.inf:
        return effort
    if limit is None or (effort is not None and effort < math.inf):
        return None
    lower, upper = limit.lower, limit.upper
    ranged = lower is not None and upper is not None and math.isfinite(lower) and math.isfinite(upper)
    return math.inf if ranged and lower < upper else None  # type: ignore[operator]


def actuated_joints(robot: Robot, joints: Sequence[MjJoint]) -> list[tuple[MjJoint, Joint, float]]:
    """1-DOF source joints with a positive effort (``inf``: unlimited, with a range) that are not
    mimic followers."""
    out = []
    for mj in joints:
        source = robot.joint(mj.source) if mj.source else None
        if source is None or mj.kind not in ("hinge", "slide") or mj.name != source.name:
            continue
        effort = _effort(source)
        if effort is not None and source.mimic is None:
            out.append((mj, source, effort))
    return out


def moved_inertia(tree: KinematicTree, inertials: Mapping[str, Inertial | None], joint: Joint,
                  q: Mapping[str, float] | None = None) -> float:
    """Inertia (kg·m²) about a hinge's axis, or mass (kg) along a slide, of everything it moves
    at the configuration *q* (zero by default)."""
    poses = tree.forward_kinematics(dict(q or {}))
    frame = poses[joint.child]
    axis = frame[:3, :3] @ np.asarray(unit_axis(joint))
    anchor = frame[:3, 3]
    total = 0.0
    for _, link, _ in tree.walk(joint.child):
        inertial = inertials.get(link.name)
        if inertial is None:
            continue
        if joint.type is JointType.PRISMATIC:
            total += inertial.mass
            continue
        pose: Matrix = poses[link.name] @ inertial.origin.matrix
        rot = pose[:3, :3]
        offset = pose[:3, 3] - anchor
        perpendicular = offset - float(offset @ axis) * axis
        total += float(axis @ (rot @ inertial.inertia_matrix @ rot.T) @ axis)
        total += inertial.mass * float(perpendicular @ perpendicular)
    return total


#: Distance (m) along a hinged cut joint's axis of the second ``connect`` that keeps the axis aligned.
AXIS_ARM = 0.05
_HINGED = (JointType.REVOLUTE, JointType.CONTINUOUS)
#: Loop closures are stiffer than MuJoCo's default equality (time constant 2 × the 2 ms step, the
#: smallest MuJoCo advises; impedance 0.95–0.99): Cassie standing keeps its loops within 1 mm.
LOOP_SOLVER = {"solref": "0.004 1", "solimp": "0.95 0.99 0.001"}


def loop_sites(robot: Robot) -> dict[str, list[dict[str, str]]]:
    """Sites marking each loop closure's joint frame in its parent and child bodies (and, for a
    revolute or continuous cut, a second pair :data:`AXIS_ARM` along its axis)."""
    sites: dict[str, list[dict[str, str]]] = {}
    for closure in robot.loop_closures:
        joint = closure.joint
        for side, body, anchor in (("parent", joint.parent, closure.parent_anchor),
                                   ("child", joint.child, closure.child_anchor)):
            sites.setdefault(body, []).append({"name": f"{joint.name}_{side}", **pose_attributes(anchor)})
            if joint.type in _HINGED:
                shift = np.eye(4)
                shift[:3, 3] = AXIS_ARM * np.asarray(unit_axis(joint))
                sites[body].append({"name": f"{joint.name}_{side}_axis",
                                    **transform_attributes(anchor.matrix @ shift)})
    return sites


def write_equality(root: etree._Element, robot: Robot, joints: Sequence[MjJoint],
                   diagnostics: list[Diagnostic]) -> dict[str, float]:
    """Mimic joints as ``<joint>`` equalities (follower = offset + multiplier · leader), loops as
    ``<connect>`` or ``<weld>`` between the sites of the cut joint; a revolute or continuous cut gets
    a second ``connect`` (``NAME_axis``) :data:`AXIS_ARM` along its axis, so the axis stays aligned.
    Returns the armature (kg·m²) that SDF gearbox closures add to their output joints."""
    exported = {mj.name for mj in joints}
    items: list[tuple[str, dict[str, str]]] = []
    for mj in joints:
        source = robot.joint(mj.source) if mj.source else None
        if source is None or source.mimic is None or mj.name != source.name:
            continue
        mimic = source.mimic
        if mimic.joint not in exported:
            diagnostics.append(ConversionDropped.diagnostic(
                f"joint '{source.name}': mimics '{mimic.joint}', which is not an exported joint",
                mimic.span or source.span, element=f"joint[{source.name}]/mimic",
                data={"element": f"joint[{source.name}]/mimic", "reason": "mimic target missing"}))
            continue
        # solref: time constant 2 × MuJoCo's 2 ms step (the stiffest it advises); the default
        # 0.02 s lets TIAGo Pro's five gripper followers lag by 0.03 rad, this holds 0.002.
        items.append(("joint", {"name": f"{source.name}_mimic", "joint1": source.name,
                                "joint2": mimic.joint,
                                "polycoef": vec((mimic.offset, mimic.multiplier, 0, 0, 0)),
                                "solref": "0.004 1"}))
    geared: dict[str, float] = {}
    for closure in robot.loop_closures:
        if closure.joint.type is JointType.GEARBOX:
            gear = _gearbox(robot, closure.joint, exported, diagnostics)
            if gear is not None:
                geared[gear[0]] = geared.get(gear[0], 0.0) + gear[1]
            continue
        item = _closure(closure, diagnostics)
        if item is None:
            continue
        _spring_of_cut(closure.joint, diagnostics)
        items.append((item[0], {**item[1], **LOOP_SOLVER}))
        if closure.joint.type in _HINGED:
            name = closure.joint.name
            items.append(("connect", {"name": f"{name}_axis", "site1": f"{name}_parent_axis",
                                      "site2": f"{name}_child_axis", **LOOP_SOLVER}))
    if items:
        section = etree.SubElement(root, "equality")
        for tag, attrs in items:
            etree.SubElement(section, tag, attrs)
    return geared


#: Gearbox ratios written as armature: beyond 1e6 either way the reflected inertia (I / ratio²)
#: is no number MuJoCo can integrate, and such a ratio is a typo.
MIN_GEAR_RATIO = 1e-6


def _gearbox(robot: Robot, joint: Joint, exported: set[str],
             diagnostics: list[Diagnostic]) -> tuple[str, float] | None:
    """An SDF gearbox closure as the armature it gives its output joint: (joint, kg·m²).

    SDFormat couples θ₂ = −ratio · θ₁ (θ₁ the parent's angle, θ₂ the child's, both relative to
    ``gearbox_reference_body``). Where the parent is a motor rotor and the child the joint output,
    each on one hinge hanging from the reference body (Cassie), the rotor's spin inertia I about
    its hinge reaches the output as I / ratio², which is MuJoCo's ``armature``, the way MuJoCo
    Menagerie models geared motors. A ``<joint>`` equality of coefficient 1/ratio (25 to 50) was
    tried and is unstable at MuJoCo's 2 ms step. The rotor then spins free (nothing drives it)."""
    where = f"joint[{joint.name}]"
    fields = {e.tag: e.element for e in joint.extensions if e.element is not None}
    ratio_element = fields.get("gearbox_ratio")
    reference_element = fields.get("gearbox_reference_body")
    ratio = _number(ratio_element.text or "") if ratio_element is not None else None
    reference = (reference_element.text or "").strip() if reference_element is not None else ""
    by_child = {j.child: j for j in robot.joints}
    rotor, output = by_child.get(joint.parent), by_child.get(joint.child)
    rotor_link = robot.link(joint.parent) if rotor is not None else None
    usable_ratio = ratio is not None and MIN_GEAR_RATIO <= abs(ratio) <= 1.0 / MIN_GEAR_RATIO
    if (not usable_ratio or rotor is None or output is None or rotor_link is None
            or rotor.type not in _HINGED or output.type not in _HINGED
            or rotor.parent != reference or output.parent != reference
            or output.name not in exported or rotor_link.inertial is None):
        diagnostics.append(ConversionDropped.diagnostic(
            f"{where}: a gearbox closure is written only between a rotor and an output that each "
            "hang from its reference body by a hinge; the loop is open", joint.span, element=where,
            data={"element": where, "reason": "gearbox not between two hinges on its reference body"}))
        return None
    inertial = rotor_link.inertial
    axis = np.asarray(rotor.axis, dtype=float)
    axis = axis / (np.linalg.norm(axis) or 1.0)
    offset = np.asarray(inertial.origin.xyz, dtype=float)  # centre of mass, rotor frame = hinge frame
    spin = float(axis @ inertial.inertia_in_link_frame @ axis) + inertial.mass * float(
        offset @ offset - (axis @ offset) ** 2)
    assert ratio is not None  # usable_ratio says so
    armature = spin / ratio**2
    diagnostics.append(ConversionDropped.diagnostic(
        f"{where}: the gearbox (ratio {ratio:g}) is written as armature {armature:.4g} kg·m² on "
        f"'{output.name}', the rotor '{rotor.name}' spinning free", joint.span, element=where,
        severity=Severity.INFO,
        data={"element": where, "reason": "gearbox written as reflected rotor inertia",
              "joint": output.name, "armature": armature}))
    return output.name, armature


def _number(text: str) -> float | None:
    try:
        value = float(text.strip())
    except ValueError:
        return None
    return value if math.isfinite(value) else None


def _closure(closure: LoopClosure, diagnostics: list[Diagnostic]) -> tuple[str, dict[str, str]] | None:
    joint = closure.joint
    sites = {"name": joint.name, "site1": f"{joint.name}_parent", "site2": f"{joint.name}_child"}
    where = f"joint[{joint.name}]"
    if joint.type is JointType.FIXED:
        return ("weld", sites)
    if joint.type in (JointType.SPHERICAL, JointType.REVOLUTE, JointType.CONTINUOUS,
                      JointType.UNIVERSAL, JointType.REVOLUTE2):
        if joint.type not in (JointType.SPHERICAL, *_HINGED):
            diagnostics.append(ConversionDropped.diagnostic(
                f"{where}: the loop is closed with a point constraint (connect); the cut "
                f"{joint.type.value} joint's axis alignment is not enforced", joint.span,
                element=where, severity=Severity.INFO,
                data={"element": where, "reason": "connect keeps the anchor, not the axis"}))
        return ("connect", sites)
    diagnostics.append(ConversionDropped.diagnostic(
        f"{where}: a {joint.type.value} joint closing a loop has no MJCF equality; the loop is open",
        joint.span, element=where, data={"element": where, "reason": "no equality for this joint type"}))
    return None


def _spring_of_cut(joint: Joint, diagnostics: list[Diagnostic]) -> None:
    """A spring on the joint that closes a loop has no joint to act on in MJCF: reported."""
    if joint.dynamics is None or joint.dynamics.spring_stiffness <= 0:
        return
    where = f"joint[{joint.name}]/axis/dynamics/spring_stiffness"
    unit = "N/m" if joint.type is JointType.PRISMATIC else "N·m/rad"
    diagnostics.append(ConversionDropped.diagnostic(
        f"joint[{joint.name}]: closes a loop, so MJCF has no joint for its spring "
        f"({joint.dynamics.spring_stiffness:g} {unit}); the loop is closed without it",
        joint.dynamics.span or joint.span, element=where,
        data={"element": where, "reason": "the cut joint of a loop carries no spring"}))


def home_qpos(robot: Robot, joints: Sequence[MjJoint]) -> list[float]:
    """The home keyframe's qpos: zero (or the robot's home) clamped into limits; mimic
    followers at offset + multiplier × leader."""
    values = {mj.name: mj.home for mj in joints}
    qpos: list[float] = []
    for mj in joints:
        source = robot.joint(mj.source) if mj.source else None
        if source is not None and source.mimic is not None and mj.name == source.name:
            leader = values.get(source.mimic.joint, (0.0,))
            value = source.mimic.offset + source.mimic.multiplier * leader[0]
            qpos.append(clamp(value, mj.range))
        else:
            qpos.extend(mj.home)
    return qpos


def write_keyframe(root: etree._Element, robot: Robot, joints: Sequence[MjJoint]) -> None:
    """The ``home`` keyframe: its qpos, and with actuators its ctrl (position servos commanded to
    their joint's home value, velocity and motor actuators to 0), so that resetting to it holds."""
    qpos = home_qpos(robot, joints)
    if not qpos:
        return
    attrs = {"name": "home", "qpos": vec(qpos)}
    offsets: dict[str, int] = {}
    at = 0
    for mj in joints:
        offsets[mj.name] = at
        at += len(mj.home)
    actuators = root.find("actuator")
    if actuators is not None and len(actuators):
        attrs["ctrl"] = vec([qpos[offsets[a.get("joint", "")]]
                             if a.tag == "position" and a.get("joint") in offsets else 0.0
                             for a in actuators])
    section = etree.SubElement(root, "keyframe")
    etree.SubElement(section, "key", attrs)


def write_scene(root: etree._Element, worldbody: etree._Element, floor: float = 0.0) -> None:
    """A checkered ground plane at z = *floor* (0 unless a fixed robot reaches below it) and a
    directional light."""
    asset = root.find("asset")
    if asset is None:
        asset = etree.Element("asset")
        root.insert(list(root).index(worldbody), asset)
    etree.SubElement(asset, "texture", {"name": "groundplane", "type": "2d", "builtin": "checker",
                                        "rgb1": "0.2 0.3 0.4", "rgb2": "0.1 0.2 0.3",
                                        "width": "300", "height": "300"})
    etree.SubElement(asset, "material", {"name": "groundplane", "texture": "groundplane",
                                         "texrepeat": "5 5", "reflectance": "0.2"})
    plane = {"name": "floor", "type": "plane", "size": "0 0 0.05", "material": "groundplane"}
    if floor:
        plane["pos"] = vec((0.0, 0.0, floor))
    worldbody.insert(0, etree.Element("geom", plane))
    worldbody.insert(0, etree.Element("light", {"name": "sun", "pos": "0 0 3", "dir": "0 0 -1",
                                                "directional": "true"}))
