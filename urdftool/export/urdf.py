"""URDF export: a faithful, flattened URDF from any model (URDF, xacro or SDF).

The writer is reusable: :func:`robot_element` turns a :class:`Robot` into an
lxml tree for a :class:`UrdfFlavor` (plain URDF here; the PyBullet exporter
subclasses the flavor to accept its extensions and rewrite mesh paths), and
:func:`to_bytes` gives deterministic bytes. What URDF cannot hold refuses the
export with a located reason: closed chains, joint types outside the flavor
(ball, universal, revolute2, screw, gearbox). Numbers are written in Python's
shortest round-trip form, so re-reading the output gives the same floats.

From SDF sources, SDF-only link and joint children (sensors, self_collide,
axis2, ...) and model plugins go into ``<gazebo>`` blocks, where Gazebo's URDF
reader puts them back; ``<frame>`` elements become massless links on fixed
joints. From URDF sources, extensions are copied as written, without
urdftool's position stamps.
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Iterable
from dataclasses import field
from pathlib import Path

from lxml import etree

from urdftool.catalogue.conversion import ConversionDropped
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.export import ExportOptions, ExportResult
from urdftool.export.numbers import num, vec
from urdftool.model import (
    IDENTITY,
    Box,
    Collision,
    Cylinder,
    Extension,
    Geometry,
    Inertial,
    Joint,
    JointType,
    Link,
    Material,
    Mesh,
    Pose,
    Robot,
    Sphere,
    Visual,
)
from urdftool.records import record
from urdftool.source import SRC_ATTRIBUTE

URDF_JOINT_TYPES: dict[JointType, str] = {
    JointType.REVOLUTE: "revolute",
    JointType.CONTINUOUS: "continuous",
    JointType.PRISMATIC: "prismatic",
    JointType.FIXED: "fixed",
    JointType.FLOATING: "floating",
    JointType.PLANAR: "planar",
}


@record
class UrdfFlavor:
    """What the target URDF reader accepts; subclass to change a choice."""

    name: str = "URDF"
    joint_types: dict[JointType, str] = field(default_factory=lambda: dict(URDF_JOINT_TYPES))
    #: shapes beyond box, cylinder, sphere and mesh that the reader accepts (PyBullet: capsule)
    extra_shapes: frozenset[str] = frozenset()

    def mesh_filename(self, mesh: Mesh) -> str:
        """The filename written for *mesh* (as written in the source, by default)."""
        return mesh.filename


URDF = UrdfFlavor()

#: What an unlimited effort (N·m or N) or velocity (rad/s or m/s) is written as: URDF readers
#: (urdfdom, check_urdf) require both on a moving joint. Far above any real actuator.
UNLIMITED_STAND_INS = {"effort": 1e6, "velocity": 1e6}


def refusals(robot: Robot, flavor: UrdfFlavor = URDF) -> list[Diagnostic]:
    """What *flavor* cannot hold, each at the element that needs it (errors: nothing is written)."""
    out = []
    for closure in robot.loop_closures:
        joint = closure.joint
        out.append(_refuse(
            f"joint '{joint.name}' closes a kinematic loop; {flavor.name} holds only trees",
            joint, "closed chain",
            "convert to SDF or MJCF (which keep the loop), or remove the joint that closes it",
        ))
    for joint in robot.joints:
        if joint.type not in flavor.joint_types:
            out.append(_refuse(
                f"joint '{joint.name}' is a {joint.type.value} joint, which {flavor.name} cannot hold",
                joint, "joint type",
                "replace it by revolute joints through small massless links, or convert to SDF or MJCF",
            ))
    return out


def _refuse(message: str, joint: Joint, reason: str, help: str) -> Diagnostic:
    return ConversionDropped.diagnostic(
        message + "; not converted",
        joint.span,
        element=f"joint[{joint.name}]",
        help=help,
        data={"reason": reason, "joint": joint.name, "type": joint.type.value},
        severity=Severity.ERROR,
    )


# -- writing ---------------------------------------------------------------------


@record(frozen=False)
class UrdfWriter:
    """Builds the ``<robot>`` tree; ``diagnostics`` collects what was left out (warnings)."""

    robot: Robot
    flavor: UrdfFlavor = URDF
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def from_sdf(self) -> bool:
        return self.robot.format == "sdf"

    def build(self) -> etree._Element:
        robot = self.robot
        root = etree.Element("robot", name=robot.name or "robot")
        named = {m.name: m for m in robot.materials if m.name}
        for material in robot.materials:
            if material.name and (material.color or material.texture):
                root.append(self.material(material))
        for link in robot.links:
            root.append(self.link(link, named))
        for joint in robot.joints:
            root.append(self.joint(joint))
        for frame in (e for e in robot.extensions if e.tag == "frame" and self.from_sdf):
            root.extend(self.frame(frame))
        for element in self.robot_extensions():
            root.append(element)
        for link in robot.links:
            root.extend(self.gazebo_blocks(link.name, link.extensions))
        for joint in robot.joints:
            root.extend(self.gazebo_blocks(joint.name, joint.extensions, _spring(joint)))
        return root

    # -- links -----------------------------------------------------------------

    def link(self, link: Link, named: dict[str, Material]) -> etree._Element:
        element = etree.Element("link", name=link.name)
        if link.inertial is not None:
            element.append(inertial_element(link.inertial))
        for visual in link.visuals:
            item = self.shaped("visual", visual, link)
            if item is not None:
                if visual.material is not None:
                    item.append(self.visual_material(visual.material, named, link, len(element)))
                element.append(item)
        for collision in link.collisions:
            item = self.shaped("collision", collision, link)
            if item is not None:
                element.append(item)
        if not self.from_sdf:
            element.extend(clean_copy(ext.element) for ext in link.extensions)
        return element

    def shaped(self, tag: str, item: Visual | Collision, link: Link) -> etree._Element | None:
        geometry = self.geometry(item.geometry, f"link[{link.name}]/{tag}", item)
        if geometry is None:
            return None
        element = etree.Element(tag)
        if item.name:
            element.set("name", item.name)
        origin = origin_element(item.origin)
        if origin is not None:
            element.append(origin)
        element.append(geometry)
        return element

    def geometry(self, shape: Geometry | None, where: str, item: Visual | Collision) -> etree._Element | None:
        wrapper = etree.Element("geometry")
        if isinstance(shape, Box):
            etree.SubElement(wrapper, "box", size=vec(shape.size))
        elif isinstance(shape, Cylinder):
            etree.SubElement(wrapper, "cylinder", radius=num(shape.radius), length=num(shape.length))
        elif isinstance(shape, Sphere):
            etree.SubElement(wrapper, "sphere", radius=num(shape.radius))
        elif isinstance(shape, Mesh):
            mesh = etree.SubElement(wrapper, "mesh", filename=self.flavor.mesh_filename(shape))
            if shape.scale != (1.0, 1.0, 1.0):
                mesh.set("scale", vec(shape.scale))
        elif shape is not None and shape.kind == "capsule" and "capsule" in self.flavor.extra_shapes:
            etree.SubElement(wrapper, "capsule", radius=num(shape.radius), length=num(shape.length))  # type: ignore[union-attr]
        else:
            if shape is not None:
                self.diagnostics.append(ConversionDropped.diagnostic(
                    f"{where}: {self.flavor.name} has no {shape.kind} shape; the element is left out",
                    item.span, element=where, data={"reason": "shape", "shape": shape.kind},
                ))
            return None
        return wrapper

    def visual_material(self, material: Material, named: dict[str, Material], link: Link,
                        index: int) -> etree._Element:
        if material.name and material.name in named and material.color is None and material.texture is None:
            return etree.Element("material", name=material.name)
        element = etree.Element("material", name=material.name or f"{link.name}_material_{index}")
        if material.color is not None:
            etree.SubElement(element, "color", rgba=vec(material.color))
        if material.texture is not None:
            etree.SubElement(element, "texture", filename=material.texture)
        return element

    def material(self, material: Material) -> etree._Element:
        element = etree.Element("material", name=material.name or "")
        if material.color is not None:
            etree.SubElement(element, "color", rgba=vec(material.color))
        if material.texture is not None:
            etree.SubElement(element, "texture", filename=material.texture)
        return element

    # -- joints ----------------------------------------------------------------

    def _limit_values(self, joint: Joint) -> dict[str, float]:
        """The ``<limit>`` attributes to write; effort and velocity get finite stand-ins when the
        source leaves them unlimited (SDF), since URDF readers require both on a moving joint."""
        limit = joint.limit
        values = {key: value for key in ("lower", "upper", "effort", "velocity")
                  if limit is not None and (value := getattr(limit, key)) is not None}
        if self.robot.format != "sdf" or joint.type not in (
                JointType.REVOLUTE, JointType.PRISMATIC, JointType.CONTINUOUS):
            return values  # a URDF source is written as it is (its own findings say what is missing)
        if limit is None and joint.type is JointType.CONTINUOUS:
            return values
        for key, stand_in in UNLIMITED_STAND_INS.items():
            if key not in values:
                values[key] = stand_in
                self._note(joint, f"{key} is unlimited in the source; written as {num(stand_in)}, urdftool's "
                           "stand-in for unlimited", f"unlimited {key}", {key: stand_in})
        return values

    def _note(self, joint: Joint, what: str, reason: str, data: dict[str, float]) -> None:
        self.diagnostics.append(ConversionDropped.diagnostic(
            f"joint '{joint.name}': {what}",
            joint.span,
            element=f"joint[{joint.name}]",
            severity=Severity.INFO,
            data={"reason": reason, **data},
        ))

    def joint(self, joint: Joint) -> etree._Element:
        type_name = self.flavor.joint_types.get(joint.type, joint.type.value)
        limit_values = self._limit_values(joint)
        if self.robot.format == "sdf" and joint.type is JointType.REVOLUTE \
                and ("lower" not in limit_values or "upper" not in limit_values):
            # SDF writes an unlimited revolute joint with infinite (or no) limits: URDF's word is continuous.
            type_name = "continuous"
            limit_values.pop("lower", None)
            limit_values.pop("upper", None)
            self._note(joint, "a revolute joint without finite limits is written as continuous",
                       "unlimited revolute", {})
        element = etree.Element("joint", name=joint.name, type=type_name)
        origin = origin_element(joint.origin)
        if origin is not None:
            element.append(origin)
        etree.SubElement(element, "parent", link=joint.parent)
        etree.SubElement(element, "child", link=joint.child)
        if joint.type is not JointType.FIXED:
            etree.SubElement(element, "axis", xyz=vec(joint.axis))
        if limit_values:
            limit = etree.SubElement(element, "limit")
            for key in ("lower", "upper", "effort", "velocity"):
                if key in limit_values:
                    limit.set(key, num(limit_values[key]))
        if joint.dynamics is not None:
            etree.SubElement(element, "dynamics", damping=num(joint.dynamics.damping),
                             friction=num(joint.dynamics.friction))
        if joint.mimic is not None:
            etree.SubElement(
                element,
                "mimic",
                joint=joint.mimic.joint,
                multiplier=num(joint.mimic.multiplier),
                offset=num(joint.mimic.offset),
            )
        if joint.safety_controller is not None:
            sc = joint.safety_controller
            etree.SubElement(element, "safety_controller", k_velocity=num(sc.k_velocity),
                             k_position=num(sc.k_position), soft_lower_limit=num(sc.soft_lower_limit),
                             soft_upper_limit=num(sc.soft_upper_limit))
        if joint.calibration is not None:
            calibration = etree.SubElement(element, "calibration")
            for key in ("rising", "falling"):
                value = getattr(joint.calibration, key)
                if value is not None:
                    calibration.set(key, num(value))
        if not self.from_sdf:
            element.extend(clean_copy(ext.element) for ext in joint.extensions)
        return element

    # -- SDF frames and extensions ---------------------------------------------

    def frame(self, frame: Extension) -> list[etree._Element]:
        """An SDF ``<frame>`` as a massless link on a fixed joint to the link it moves with."""
        name = frame.attributes["name"]
        link = etree.Element("link", name=name)
        joint = etree.Element("joint", name=f"{name}_frame", type="fixed")
        etree.SubElement(
            joint, "origin", xyz=_vec_text(frame.attributes["xyz"]), rpy=_vec_text(frame.attributes["rpy"])
        )
        etree.SubElement(joint, "parent", link=frame.attributes["attached_to"])
        etree.SubElement(joint, "child", link=name)
        return [link, joint]

    def robot_extensions(self) -> list[etree._Element]:
        kept = [e for e in self.robot.extensions if not (self.from_sdf and e.tag == "frame")]
        if not self.from_sdf:
            return [clean_copy(e.element) for e in kept]
        if not kept:
            return []
        gazebo = etree.Element("gazebo")
        gazebo.extend(clean_copy(e.element) for e in kept)
        return [gazebo]

    def gazebo_blocks(self, reference: str, extensions: Iterable[Extension],
                      written: Iterable[etree._Element] = ()) -> list[etree._Element]:
        """SDF-only children of a link or joint, inside ``<gazebo reference>`` (SDF sources only),
        after the *written* elements urdftool composed for it (a joint's spring)."""
        items = list(extensions)
        composed = list(written)
        if not self.from_sdf or not (items or composed):
            return []
        gazebo = etree.Element("gazebo", reference=reference)
        gazebo.extend(composed)
        gazebo.extend(clean_copy(e.element) for e in items)
        return [gazebo]


def _spring(joint: Joint) -> list[etree._Element]:
    """An SDF joint spring as the Gazebo URDF extension sdformat reads back
    (``springStiffness``, ``springReference`` in ``<gazebo reference="JOINT">``)."""
    dynamics = joint.dynamics
    if dynamics is None or dynamics.spring_stiffness <= 0:
        return []
    stiffness = etree.Element("springStiffness")
    stiffness.text = num(dynamics.spring_stiffness)
    reference = etree.Element("springReference")
    reference.text = num(dynamics.spring_reference)
    return [stiffness, reference]


def _vec_text(text: str) -> str:
    return vec(float(v) for v in text.split())


def origin_element(pose: Pose) -> etree._Element | None:
    """``<origin>`` for *pose*, or ``None`` for the identity."""
    if all(v == 0.0 for v in pose.xyz) and all(v == 0.0 for v in pose.rpy):
        return None
    return etree.Element("origin", xyz=vec(pose.xyz), rpy=vec(pose.rpy))


def inertial_element(inertial: Inertial) -> etree._Element:
    element = etree.Element("inertial")
    origin = origin_element(inertial.origin)
    if origin is not None:
        element.append(origin)
    etree.SubElement(element, "mass", value=num(inertial.mass))
    i = inertial.inertia
    etree.SubElement(element, "inertia", ixx=num(i[0][0]), ixy=num(i[0][1]), ixz=num(i[0][2]),
                     iyy=num(i[1][1]), iyz=num(i[1][2]), izz=num(i[2][2]))
    return element


def clean_copy(element: etree._Element) -> etree._Element:
    """A deep copy of a kept element without urdftool's position stamps."""
    out = copy.deepcopy(element)
    for node in out.iter():
        if isinstance(node.tag, str) and SRC_ATTRIBUTE in node.attrib:
            del node.attrib[SRC_ATTRIBUTE]
    out.tail = None
    return out


def to_bytes(root: etree._Element) -> bytes:
    """Deterministic, indented UTF-8 with an XML declaration and a trailing newline."""
    etree.indent(root, space="  ")
    data: bytes = etree.tostring(root, xml_declaration=True, encoding="utf-8", pretty_print=True)
    return data


def robot_element(robot: Robot, flavor: UrdfFlavor = URDF) -> tuple[etree._Element, list[Diagnostic]]:
    """The ``<robot>`` tree for *robot* and what was left out; check :func:`refusals` first."""
    writer = UrdfWriter(robot, flavor)
    return writer.build(), writer.diagnostics


def split_two_axis_joints(robot: Robot) -> tuple[Robot, list[Diagnostic]]:
    """*robot* with each universal or revolute2 joint written as URDF can hold it: a revolute
    joint about the first axis to a massless link ``<joint>_cross``, then a revolute joint
    about the second axis (which turns with the first) to the child. Each is reported."""
    links, joints, notes = list(robot.links), [], []
    names = {link.name for link in robot.links}
    for joint in robot.joints:
        if joint.type not in (JointType.UNIVERSAL, JointType.REVOLUTE2) or joint.axis2 is None:
            joints.append(joint)
            continue
        cross = f"{joint.name}_cross"
        while cross in names:
            cross += "_"
        names.add(cross)
        links.append(Link(cross, span=joint.span))
        first = dataclasses.replace(joint, name=f"{joint.name}_1", type=JointType.REVOLUTE, child=cross,
                                    axis2=None, limit2=None)
        second = dataclasses.replace(joint, name=f"{joint.name}_2", type=JointType.REVOLUTE, parent=cross,
                                     origin=IDENTITY, axis=joint.axis2, limit=joint.limit2, axis2=None,
                                     limit2=None)
        joints += [first, second]
        notes.append(ConversionDropped.diagnostic(
            f"joint '{joint.name}' ({joint.type.value}) is written as revolute joints '{joint.name}_1' and "
            f"'{joint.name}_2' with a massless link '{cross}' between them",
            joint.span, element=f"joint[{joint.name}]", severity=Severity.INFO,
            data={"reason": "two revolute joints", "link": cross},
        ))
    if not notes:
        return robot, []
    return dataclasses.replace(robot, links=tuple(links), joints=tuple(joints)), notes


def export(robot: Robot, out: Path, options: ExportOptions) -> ExportResult:
    """URDF text for *robot* as ``{out.name: bytes}``; refused (no files) when URDF cannot hold it."""
    robot, split = split_two_axis_joints(robot)
    refused = refusals(robot)
    if refused:
        return ExportResult({}, refused)
    root, dropped = robot_element(robot)
    return ExportResult({out.name: to_bytes(root)}, split + dropped)
