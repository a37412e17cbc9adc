"""SDF export (SDF 1.7) of tree-shaped models, URDF's numbers kept exactly.

Each link's pose is written ``relative_to`` its parent link with the joint's
origin as written, the joint frame sits on the child link (SDF's default),
and the axis is in the joint frame: URDF's own convention, so no number is
recomputed. A root link named ``world`` without a body becomes SDF's world
frame: a fixed joint to it stays a joint to ``world``, a floating one is left
out (the model is free). ``continuous`` joints are written as revolute joints
without position limits. What SDF 1.7 cannot hold (planar joints, mimic) is
refused or reported; ``<gazebo>`` blocks are mapped where the mapping is
obvious (plugins, sensors, self_collide, gravity, friction and contact settings,
Gazebo material names) and reported otherwise. A massless link on a fixed joint
is written as a ``<frame>`` (:mod:`urdftool.export.sdf_frames`), not as a link
that SDF readers would give 1 kg.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import field, replace
from pathlib import Path

from lxml import etree

from urdftool.catalogue.conversion import ConversionDropped
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.export import ExportOptions, ExportResult
from urdftool.export.numbers import num, vec
from urdftool.export.sdf_frames import ON_COLLISIONS, ON_MASS, FramePlan, plan_frames
from urdftool.export.urdf import clean_copy, to_bytes
from urdftool.model import (
    Box,
    Capsule,
    Collision,
    Cylinder,
    Ellipsoid,
    Extension,
    Geometry,
    Joint,
    JointType,
    KinematicTree,
    Link,
    Material,
    Mesh,
    Plane,
    Pose,
    Robot,
    Sphere,
    Visual,
)
from urdftool.parse.locate import span_of
from urdftool.records import record

SDF_VERSION = "1.7"
_SDF_TYPES = {
    JointType.REVOLUTE: "revolute",
    JointType.CONTINUOUS: "revolute",
    JointType.PRISMATIC: "prismatic",
    JointType.FIXED: "fixed",
    JointType.SPHERICAL: "ball",
    JointType.UNIVERSAL: "universal",
    JointType.REVOLUTE2: "revolute2",
    JointType.SCREW: "screw",
    JointType.GEARBOX: "gearbox",
}
#: <gazebo reference="link"> children copied into the SDF link, with their SDF name
_LINK_ELEMENTS = {"sensor": "sensor", "selfCollide": "self_collide", "self_collide": "self_collide",
                  "gravity": "gravity", "kinematic": "kinematic", "velocity_decay": "velocity_decay"}
#: <gazebo reference="link"> contact settings -> (block of the collision's ODE <surface>, SDF name),
#: as libsdformat's URDF reader writes them into every collision of the link
_SURFACE = {"mu1": ("friction", "mu"), "mu2": ("friction", "mu2"), "fdir1": ("friction", "fdir1"),
            "kp": ("contact", "kp"), "kd": ("contact", "kd"), "minDepth": ("contact", "min_depth"),
            "maxVel": ("contact", "max_vel")}
#: <gazebo reference="link"> settings of each collision itself -> SDF name
_COLLISION = {"maxContacts": "max_contacts", "laserRetro": "laser_retro"}
_FRICTION = (*_SURFACE, *_COLLISION)  # what a link's collisions carry


def pose_text(pose: Pose) -> str:
    return vec((*pose.xyz, *pose.rpy))


#: Below this (m, rad), a number of a composed pose is rounding (sin π = 1.2e-16), written as 0.
ROUNDING = 1e-15


def composed(outer: Pose, inner: Pose) -> Pose:
    """``outer ∘ inner`` with rounding noise written as 0, so a frame turned by π does not leave
    1.2e-18 in every pose it carries."""
    pose = outer.compose(inner)
    tidy = tuple(0.0 if abs(v) < ROUNDING else v for v in (*pose.xyz, *pose.rpy))
    return Pose((tidy[0], tidy[1], tidy[2]), (tidy[3], tidy[4], tidy[5]))


def _sensor_moved(sensor: etree._Element, offset: Pose) -> etree._Element:
    """*sensor* with its ``<pose>`` (in the frame it was written in) composed with *offset*, the
    frame's pose in the link that now carries it; a pose ``relative_to`` a named frame is kept."""
    pose = sensor.find("pose")
    if pose is not None and pose.get("relative_to"):
        return sensor
    try:
        values = [float(v) for v in (pose.text or "").split()] if pose is not None else []
    except ValueError:
        return sensor  # not six numbers: left as written, for the SDF reader to report
    if pose is not None and len(values) != 6:
        return sensor
    own = Pose((values[0], values[1], values[2]), (values[3], values[4], values[5])) if values else Pose()
    if pose is None:
        pose = etree.Element("pose")
        sensor.insert(0, pose)
    pose.text = pose_text(composed(offset, own))
    return sensor


def _world_root(robot: Robot, tree: KinematicTree) -> str | None:
    """The root link named ``world`` that carries nothing, if the model has one."""
    root = tree.root
    link = robot.link(root) if root else None
    if (
        link is not None
        and link.name == "world"
        and not link.inertial
        and not link.visuals
        and not link.collisions
    ):
        return link.name
    return None


def refusals(robot: Robot) -> list[Diagnostic]:
    out = []
    for joint in robot.joints:
        if joint.type is JointType.PLANAR:
            out.append(ConversionDropped.diagnostic(
                f"joint '{joint.name}' is planar, which SDF cannot hold; not converted",
                joint.span, element=f"joint[{joint.name}]", severity=Severity.ERROR,
                help="replace it by two prismatic and one revolute joint through massless links",
                data={"reason": "joint type", "joint": joint.name, "type": joint.type.value},
            ))
    return out


@record(frozen=False)
class SdfWriter:
    robot: Robot
    tree: KinematicTree
    diagnostics: list[Diagnostic] = field(default_factory=list)
    frames: FramePlan = field(default_factory=FramePlan)

    def build(self) -> etree._Element:
        robot = self.robot
        world = _world_root(robot, self.tree)
        sdf = etree.Element("sdf", version=SDF_VERSION)
        model = etree.SubElement(sdf, "model", name=robot.name or "robot")
        gazebo = self._gazebo_by_reference()
        self.frames = plan_frames(robot, self.tree, world, gazebo)
        for _, link, joint in self.tree.walk():
            if link.name == world:
                continue
            if link.name in self.frames.body:
                model.append(self.frame(link, joint, gazebo.get(link.name, [])))
                continue
            names: set[str] = set()  # of the visuals and collisions: unique per SDF link
            element = self.link(link, joint, world, gazebo.get(link.name, []), names)
            self.lump(element, link, gazebo, names)
            model.append(element)
        for joint in self.tree.joints_in_order:
            if joint.child in self.frames.body or self.frames.link_for(joint.parent) == joint.child:
                continue  # written as the child's <frame>, or the root's frame hangs from its child
            element = self.joint(joint, world)
            if element is not None:
                model.append(element)
        for closure in robot.loop_closures:
            element = self.joint(closure.joint, world)
            if element is not None:
                # the joint frame, in its child link's frame (SDF's default for a joint pose)
                pose = etree.Element("pose")
                pose.text = pose_text(closure.child_anchor)
                element.insert(0, pose)
                model.append(element)
        for ext in robot.extensions:
            model.extend(self.model_extension(ext))
        return sdf

    def _gazebo_by_reference(self) -> dict[str, list[etree._Element]]:
        out: dict[str, list[etree._Element]] = {}
        for ext in self.robot.extensions:
            reference = ext.attributes.get("reference")
            if ext.tag == "gazebo" and reference:
                out.setdefault(reference, []).append(ext.element)
        return out

    # -- links -----------------------------------------------------------------

    def link(self, link: Link, joint: Joint | None, world: str | None,
             gazebo: list[etree._Element], names: set[str]) -> etree._Element:
        element = etree.Element("link", name=link.name)
        if joint is not None and joint.parent != world:
            etree.SubElement(element, "pose", relative_to=joint.parent).text = pose_text(joint.origin)
        elif joint is not None:
            etree.SubElement(element, "pose").text = pose_text(joint.origin)
        if link.inertial is not None:
            inertial = etree.SubElement(element, "inertial")
            etree.SubElement(inertial, "pose").text = pose_text(link.inertial.origin)
            etree.SubElement(inertial, "mass").text = num(link.inertial.mass)
            inertia = etree.SubElement(inertial, "inertia")
            i = link.inertial.inertia
            for key, value in (("ixx", i[0][0]), ("ixy", i[0][1]), ("ixz", i[0][2]),
                               ("iyy", i[1][1]), ("iyz", i[1][2]), ("izz", i[2][2])):
                etree.SubElement(inertia, key).text = num(value)
        elif joint is not None and joint.type.is_moving:
            self._drop(f"link '{link.name}' has no <inertial>; SDF readers give it 1 kg and unit inertia",
                       link.span, f"link[{link.name}]", "missing inertial", Severity.WARNING)
        elif joint is None and link.name not in self.frames.kept:
            self._drop(f"root link '{link.name}' has no <inertial> and no link with mass fixed under it "
                       "to carry it as a <frame>; SDF readers give it 1 kg and unit inertia",
                       link.span, f"link[{link.name}]", "missing inertial", Severity.WARNING)
        elif link.name in self.frames.kept:
            self._drop(f"link '{link.name}' has no <inertial> and stays an SDF link, not a <frame>, because "
                       f"{self.frames.kept[link.name]}; SDF readers give it 1 kg and unit inertia",
                       link.span, f"link[{link.name}]", "missing inertial", Severity.WARNING)
        self.shapes(element, link, gazebo, names)
        element.extend(self.link_extras(link, gazebo))
        return element

    # -- massless links on fixed joints: frames (urdftool/export/sdf_frames.py) ----------

    def frame(self, link: Link, joint: Joint | None, gazebo: list[etree._Element]) -> etree._Element:
        """``<frame name="LINK" attached_to="PARENT">`` at the joint's origin in PARENT; a root
        at the model frame, attached to the link fixed under it."""
        if joint is None:
            element = etree.Element("frame", name=link.name, attached_to=self.frames.link_for(link.name))
            etree.SubElement(element, "pose", relative_to="__model__").text = pose_text(Pose())
        else:
            element = etree.Element("frame", name=link.name, attached_to=joint.parent)
            etree.SubElement(element, "pose", relative_to=joint.parent).text = pose_text(joint.origin)
        for block in gazebo:  # what lump() does not carry into the link the frame moves with
            for child in block:
                if not isinstance(child.tag, str) or child.tag in (*_FRICTION, "material", "sensor"):
                    continue
                where = f"link[{link.name}]/gazebo/{child.tag}"
                if child.tag in ON_MASS or child.tag in ON_COLLISIONS:
                    self._drop(f"{where}: '{link.name}' is massless and written as a <frame>, with no mass "
                               "or collision for it to act on; left out", span_of(child), where,
                               "frame", Severity.INFO)
                else:
                    self._drop_element(child, where)
        return element

    def lump(self, element: etree._Element, link: Link, gazebo: dict[str, list[etree._Element]],
             names: set[str]) -> None:
        """Into *link*'s element, the visuals, collisions and sensors of the frames it carries,
        with their poses composed into *link*'s frame (Gazebo reads them there)."""
        for name in self.frames.lumped(link.name):
            frame = self.robot.link(name)
            assert frame is not None
            offset = self.frames.in_body[name]
            blocks = gazebo.get(name, [])
            self.shapes(element, frame, blocks, names, offset)
            for block in blocks:
                for child in block:
                    if isinstance(child.tag, str) and child.tag == "sensor":
                        element.append(_sensor_moved(clean_copy(child), offset))

    def shapes(self, element: etree._Element, link: Link, gazebo: list[etree._Element], names: set[str],
               offset: Pose | None = None) -> None:
        """Into *element*, *link*'s visuals (with their materials) and collisions (with their
        friction); *offset*: *link*'s frame in the SDF link's, for a frame lumped into it."""
        for index, visual in enumerate(link.visuals):
            if offset is not None:
                visual = replace(visual, origin=composed(offset, visual.origin))
            item = self.shaped("visual", visual, link, index, names)
            if item is not None:
                material = self.material(visual.material, gazebo)
                if material is not None:
                    item.append(material)
                element.append(item)
        for index, collision in enumerate(link.collisions):
            if offset is not None:
                collision = replace(collision, origin=composed(offset, collision.origin))
            item = self.shaped("collision", collision, link, index, names)
            if item is not None:
                item.extend(self.friction(gazebo))
                element.append(item)

    def shaped(self, tag: str, item: Visual | Collision, link: Link, index: int,
               names: set[str]) -> etree._Element | None:
        geometry = self.geometry(item.geometry)
        if geometry is None:
            return None
        name = item.name or f"{link.name}_{tag}" + (f"_{index}" if index else "")
        while name in names:
            name += "_"
        names.add(name)
        element = etree.Element(tag, name=name)
        etree.SubElement(element, "pose").text = pose_text(item.origin)
        element.append(geometry)
        return element

    def geometry(self, shape: Geometry | None) -> etree._Element | None:
        if shape is None:
            return None
        wrapper = etree.Element("geometry")
        body = etree.SubElement(wrapper, shape.kind)
        if isinstance(shape, Box):
            etree.SubElement(body, "size").text = vec(shape.size)
        elif isinstance(shape, (Cylinder, Capsule)):
            etree.SubElement(body, "radius").text = num(shape.radius)
            etree.SubElement(body, "length").text = num(shape.length)
        elif isinstance(shape, Sphere):
            etree.SubElement(body, "radius").text = num(shape.radius)
        elif isinstance(shape, Ellipsoid):
            etree.SubElement(body, "radii").text = vec(shape.radii)
        elif isinstance(shape, Plane):
            etree.SubElement(body, "normal").text = vec(shape.normal)
            etree.SubElement(body, "size").text = vec(shape.size)
        elif isinstance(shape, Mesh):
            etree.SubElement(body, "uri").text = shape.filename
            if shape.scale != (1.0, 1.0, 1.0):
                etree.SubElement(body, "scale").text = vec(shape.scale)
        return wrapper

    def material(self, material: Material | None, gazebo: list[etree._Element]) -> etree._Element | None:
        color = material.color if material else None
        if material is not None and color is None and material.name:
            named = next((m for m in self.robot.materials if m.name == material.name), None)
            color = named.color if named else None
        script = next((g.findtext("material") for g in gazebo if g.findtext("material")), None)
        if color is None and not script:
            return None
        element = etree.Element("material")
        if script:
            block = etree.SubElement(element, "script")
            etree.SubElement(block, "uri").text = "file://media/materials/scripts/gazebo.material"
            etree.SubElement(block, "name").text = script.strip()
        if color is not None:
            etree.SubElement(element, "ambient").text = vec(color)
            etree.SubElement(element, "diffuse").text = vec(color)
        return element

    def friction(self, gazebo: list[etree._Element]) -> list[etree._Element]:
        """A collision's ``<max_contacts>``, ``<laser_retro>`` and ``<surface>`` from the link's
        Gazebo contact settings (a later block's value wins, as Gazebo merges them)."""
        values: dict[str, str] = {}
        for block in gazebo:
            for urdf_name in _FRICTION:
                text = block.findtext(urdf_name)
                if text and text.strip():
                    values[urdf_name] = text.strip()
        out = []
        for urdf_name, sdf_name in _COLLISION.items():
            if urdf_name in values:
                element = etree.Element(sdf_name)
                element.text = values[urdf_name]
                out.append(element)
        blocks = {part for name, (part, _) in _SURFACE.items() if name in values}
        if blocks:
            surface = etree.Element("surface")
            for part in ("friction", "contact"):
                if part in blocks:
                    ode = etree.SubElement(etree.SubElement(surface, part), "ode")
                    for urdf_name, (where, sdf_name) in _SURFACE.items():
                        if where == part and urdf_name in values:
                            etree.SubElement(ode, sdf_name).text = values[urdf_name]
            out.append(surface)
        return out

    def link_extras(self, link: Link, gazebo: list[etree._Element]) -> list[etree._Element]:
        out = []
        for block in gazebo:
            for child in block:
                if not isinstance(child.tag, str):
                    continue
                if child.tag in _LINK_ELEMENTS:
                    copied = clean_copy(child)
                    copied.tag = _LINK_ELEMENTS[child.tag]
                    out.append(copied)
                elif child.tag not in _FRICTION and child.tag != "material":
                    self._drop_element(child, f"link[{link.name}]/gazebo/{child.tag}")
        return out

    # -- joints ----------------------------------------------------------------

    def joint(self, joint: Joint, world: str | None) -> etree._Element | None:
        if joint.parent == world and joint.type is JointType.FLOATING:
            return None  # a free model: SDF needs no joint
        sdf_type = _SDF_TYPES.get(joint.type)
        if sdf_type is None:
            self._drop(f"joint '{joint.name}' ({joint.type.value}) has no SDF equivalent; left out",
                       joint.span, f"joint[{joint.name}]", "joint type", Severity.WARNING)
            return None
        element = etree.Element("joint", name=self.joint_name(joint), type=sdf_type)
        # a joint hangs from a link (SDF 1.7); from a frame's, with the child posed relative_to the frame
        parent = "world" if joint.parent == world else self.frames.link_for(joint.parent)
        etree.SubElement(element, "parent").text = parent
        etree.SubElement(element, "child").text = joint.child
        if joint.type.is_moving:
            element.append(self.axis(joint))
        if joint.mimic is not None:
            self._drop(
                f"joint '{joint.name}': mimic is not in SDF 1.7; the joint moves freely",
                joint.mimic.span or joint.span,
                f"joint[{joint.name}]/mimic",
                "mimic",
                Severity.WARNING,
            )
        return element

    def joint_name(self, joint: Joint) -> str:
        """The joint's name, or ``NAME_joint`` when a link has the name (SDF frames share one namespace)."""
        if self.robot.link(joint.name) is None:
            return joint.name
        renamed = joint.name + "_joint"
        while self.robot.link(renamed) is not None or self.robot.joint(renamed) is not None:
            renamed += "_"
        self._drop(f"joint '{joint.name}' has the name of a link, which SDF does not allow; written as "
                   f"'{renamed}'", joint.span, f"joint[{joint.name}]", "name clash", Severity.WARNING)
        return renamed

    def axis(self, joint: Joint) -> etree._Element:
        axis = etree.Element("axis")
        etree.SubElement(axis, "xyz").text = vec(joint.axis)
        limit = joint.limit
        if limit is not None:
            element = etree.SubElement(axis, "limit")
            bounded = joint.type is not JointType.CONTINUOUS
            for key in ("lower", "upper", "effort", "velocity"):
                value = getattr(limit, key)
                if value is not None and (bounded or key in ("effort", "velocity")):
                    etree.SubElement(element, key).text = num(value)
        if joint.dynamics is not None:
            dynamics = etree.SubElement(axis, "dynamics")
            etree.SubElement(dynamics, "damping").text = num(joint.dynamics.damping)
            etree.SubElement(dynamics, "friction").text = num(joint.dynamics.friction)
            if joint.dynamics.spring_stiffness > 0:
                etree.SubElement(dynamics, "spring_reference").text = num(joint.dynamics.spring_reference)
                etree.SubElement(dynamics, "spring_stiffness").text = num(joint.dynamics.spring_stiffness)
        return axis

    # -- model-level extensions -----------------------------------------------

    def model_extension(self, ext: Extension) -> Iterable[etree._Element]:
        if ext.tag == "gazebo" and not ext.attributes.get("reference"):
            for child in ext.element:
                if isinstance(child.tag, str) and child.tag == "plugin":
                    yield clean_copy(child)
                elif isinstance(child.tag, str):
                    self._drop_element(child, f"gazebo/{child.tag}")
        elif ext.tag == "gazebo" and self.robot.joint(ext.attributes["reference"]) is not None:
            for child in ext.element:
                if isinstance(child.tag, str):
                    self._drop_element(child, f"joint[{ext.attributes['reference']}]/gazebo/{child.tag}")
        elif ext.tag != "gazebo":
            self._drop(f"<{ext.tag}> has no SDF equivalent; left out", ext.span, ext.tag, ext.tag,
                       Severity.WARNING)

    def _drop_element(self, element: etree._Element, where: str) -> None:
        self._drop(f"{where}: no SDF equivalent that urdftool maps; left out", span_of(element), where,
                   "gazebo extension", Severity.WARNING)

    def _drop(self, message: str, span: object, where: str, reason: str, severity: Severity) -> None:
        self.diagnostics.append(ConversionDropped.diagnostic(
            message, span, element=where, data={"reason": reason}, severity=severity,  # type: ignore[arg-type]
        ))


def export(robot: Robot, out: Path, options: ExportOptions) -> ExportResult:
    """SDF 1.7 text for a tree-shaped *robot* as ``{out.name: bytes}``."""
    refused = refusals(robot)
    if refused:
        return ExportResult({}, refused)
    writer = SdfWriter(robot, KinematicTree.of(robot))
    root = writer.build()
    return ExportResult({out.name: to_bytes(root)}, writer.diagnostics)
