"""The second pass of reading an SDF ``<model>``: the collected links, joints and frames, with
every pose resolved in the model frame, built into the URDF-style :class:`Robot`
(see :mod:`urdftool.parse.sdf_model` for the whole reading).

:class:`ModelBuilding` is a part of :class:`~urdftool.parse.sdf_model.SdfModelReader`, as
:mod:`urdftool.parse.urdf_links` is of the URDF reader: the first pass fills the tables these
methods read. Poses are 4×4 homogeneous matrices in metres and radians, in the model frame
unless named otherwise.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from lxml import etree

from urdftool.model import Collision, Extension, Joint, JointType, Link, LoopClosure, Pose, Robot, Visual
from urdftool.model.pose import Matrix
from urdftool.parse.locate import span_of
from urdftool.parse.packages import PackageResolver
from urdftool.parse.sdf_elements import LinkBodyReader, joint_details, mimic
from urdftool.parse.sdf_frames import MODEL_FRAME, WORLD_FRAME, FrameGraph
from urdftool.parse.sdf_tree import spanning_tree
from urdftool.parse.sdf_values import SdfValues
from urdftool.records import record
from urdftool.source import SRC_ATTRIBUTE

_LINK_PARTS = {"pose", "inertial", "visual", "collision"}
_JOINT_PARTS = {"pose", "parent", "child", "axis"}
#: joints whose motion is a rotation about the joint frame's origin
_ROTATIONAL = {JointType.REVOLUTE, JointType.CONTINUOUS, JointType.SPHERICAL, JointType.UNIVERSAL,
               JointType.REVOLUTE2, JointType.SCREW, JointType.GEARBOX}
_TOLERANCE = 1e-12


@record(frozen=False)
class RawLink:
    name: str
    element: etree._Element
    version: tuple[int, int]


@record(frozen=False)
class RawJoint:
    name: str
    element: etree._Element
    parent: str
    child: str
    scope: str
    version: tuple[int, int]
    #: the joint's key in the frame graph (its name, unless a link took it)
    key: str = ""
    #: the frame ``use_parent_model_frame`` means (a merged include's proxy frame, else ``scope::__model__``)
    model_frame: str = ""


@record(frozen=False)
class RawFrame:
    name: str
    element: etree._Element


class ModelBuilding:
    """Builds the robot from what the first pass collected; the reader supplies these tables."""

    path: str
    resolver: PackageResolver
    values: SdfValues
    graph: FrameGraph
    links: list[RawLink]
    joints: list[RawJoint]
    frames: list[RawFrame]
    extensions: list[Extension]

    def _build(self, name: str | None, model: etree._Element, canonical: str | None,
               world_pose: Matrix, static: bool) -> Robot:
        link_frames = {raw.name: self.graph.pose_in_model(raw.name) for raw in self.links}
        joints = [self._joint(raw, link_frames) for raw in self.joints]
        world_links = [] if any(raw.name == WORLD_FRAME for raw in self.links) else [WORLD_FRAME]
        names = [raw.name for raw in self.links]
        if any(j.parent == WORLD_FRAME for j in joints) or static:
            names = world_links + names
            link_frames[WORLD_FRAME] = np.linalg.inv(world_pose)
        else:
            world_links = []
        if static:
            joints += self._weld_to_world(names, joints, model)
        tree, cut = spanning_tree(names, joints, canonical)
        offsets = self._joint_offsets(tree)
        frames = {n: link_frames[n] @ _translation(offsets.get(n)) for n in link_frames}
        links = [Link(WORLD_FRAME, span=span_of(model)) for _ in world_links]
        links += [self._link(raw, link_frames[raw.name], offsets.get(raw.name)) for raw in self.links]
        tree = [self._place(j, frames) for j in tree]
        closures = [self._closure(j, frames) for j in cut]
        self.extensions.extend(self._frame_extensions(frames))
        children = {j.child for j in tree}
        roots = {n: Pose.from_matrix(frames[n]) for n in names if n not in children and n in frames}
        static_el = self.values.child(model, "static")
        static_span = (span_of(static_el) if static_el is not None else span_of(model)) if static else None
        return Robot(name=name, links=tuple(links), joints=tuple(tree), extensions=tuple(self.extensions),
                     loop_closures=tuple(closures), path=self.path, format="sdf", span=span_of(model),
                     root_poses=roots if len(roots) > 1 else None, static_span=static_span)

    def _weld_to_world(self, names: list[str], joints: list[Joint], model: etree._Element) -> list[Joint]:
        """Fixed joints from ``world`` to each free link of a static model."""
        children = {j.child for j in joints}
        static_el = self.values.child(model, "static")
        span = span_of(static_el) if static_el is not None else span_of(model)
        taken = {j.name for j in joints}
        out = []
        for link in names:
            if link == WORLD_FRAME or link in children:
                continue
            joint_name = f"world_to_{link}"
            while joint_name in taken:
                joint_name += "_"
            out.append(Joint(joint_name, JointType.FIXED, WORLD_FRAME, link, span=span))
        return out

    def _joint(self, raw: RawJoint, link_frames: dict[str, Matrix]) -> Joint:
        where = f"joint[{raw.name}]"
        details = joint_details(self.values, raw.element, where, raw.version)
        parent, child = self._end_link(raw.parent), self._end_link(raw.child)
        joint_frame = self.graph.pose_in_model(raw.key or raw.name)
        axis = self._axis_in_model(details.axis, details.axis_frame, joint_frame, raw, where)
        axis2 = (self._axis_in_model(details.axis2, details.axis2_frame, joint_frame, raw, where)
                 if details.axis2 is not None else None)
        follows = mimic(self.values, raw.element, where)
        if follows is not None:  # the leader is named in the joint's own model scope (a::j below it)
            follows = dataclasses.replace(follows, joint=scoped(raw.scope, follows.joint))
        return Joint(
            name=raw.name, type=details.type, parent=parent, child=child,
            # provisional: the joint frame in the model frame and the axis in the
            # model frame; _place and _closure express them in the links' frames
            origin=Pose.from_matrix(joint_frame), axis=axis,
            limit=details.limit, dynamics=details.dynamics, span=span_of(raw.element),
            axis_span=details.axis_span,  # type: ignore[arg-type]
            axis2=axis2, limit2=details.limit2, mimic=follows,
            extensions=tuple(extension_of(c) for c in raw.element
                             if isinstance(c.tag, str) and c.tag not in _JOINT_PARTS
                             and not (c.tag == "axis2" and axis2 is not None)),
        )

    def _end_link(self, ref: str) -> str:
        """The link a joint end names (an SDF 1.8+ frame is followed to the link it is attached to)."""
        if not ref or ref == WORLD_FRAME:
            return ref
        if any(raw.name == ref for raw in self.links):
            return ref
        if not self.graph.known(ref):
            return ref  # unknown-link-reference reports it on the model
        return self.graph.link_of(ref) or ref

    def _axis_in_model(self, axis: tuple[float, float, float], frame: str, joint_frame: Matrix,
                       raw: RawJoint, where: str) -> tuple[float, float, float]:
        if frame == "joint":
            rotation = joint_frame[:3, :3]
        elif frame == "model":
            rotation = self.graph.pose_in_model(raw.model_frame or raw.scope + MODEL_FRAME)[:3, :3]
        else:
            merged = frame == MODEL_FRAME and raw.model_frame
            target = raw.model_frame if merged else scoped(raw.scope, frame)
            xyz = self.values.child(self.values.child(raw.element, "axis"), "xyz")
            span = self.values.attr_span(xyz, "expressed_in") if xyz is not None else None
            if target == WORLD_FRAME or not self.graph.check_reference(target, span, f"{where}/axis/xyz"):
                rotation = np.eye(3)
            else:
                rotation = self.graph.pose_in_model(target)[:3, :3]
        vector = rotation @ np.asarray(axis, dtype=float)
        return (float(vector[0]), float(vector[1]), float(vector[2]))

    def _joint_offsets(self, tree: list[Joint]) -> dict[str, np.ndarray]:
        """Child link -> the joint frame's origin in that link's frame, where the frame must move."""
        offsets: dict[str, np.ndarray] = {}
        for joint in tree:
            if joint.type not in _ROTATIONAL or joint.child == WORLD_FRAME:
                continue
            child_frame = self.graph.pose_in_model(joint.child)
            offset = np.linalg.inv(child_frame) @ joint.origin.matrix
            if np.linalg.norm(offset[:3, 3]) > _TOLERANCE:
                offsets[joint.child] = offset[:3, 3]
        return offsets

    def _place(self, joint: Joint, frames: dict[str, Matrix]) -> Joint:
        if joint.parent not in frames or joint.child not in frames:
            return dataclasses.replace(joint, origin=Pose())
        origin = np.linalg.inv(frames[joint.parent]) @ frames[joint.child]
        axis = frames[joint.child][:3, :3].T @ np.asarray(joint.axis)
        turn = frames[joint.child][:3, :3].T
        axis2 = _vec(turn @ np.asarray(joint.axis2)) if joint.axis2 is not None else None
        return dataclasses.replace(joint, origin=Pose.from_matrix(origin), axis=_vec(axis), axis2=axis2)

    def _closure(self, joint: Joint, frames: dict[str, Matrix]) -> LoopClosure:
        joint_frame = joint.origin.matrix
        parent_anchor = Pose.from_matrix(np.linalg.inv(frames[joint.parent]) @ joint_frame)
        child_anchor = Pose.from_matrix(np.linalg.inv(frames[joint.child]) @ joint_frame)
        axis = joint_frame[:3, :3].T @ np.asarray(joint.axis)
        axis2 = _vec(joint_frame[:3, :3].T @ np.asarray(joint.axis2)) if joint.axis2 is not None else None
        placed = dataclasses.replace(joint, origin=parent_anchor, axis=_vec(axis), axis2=axis2)
        return LoopClosure(placed, parent_anchor, child_anchor)

    def _link(self, raw: RawLink, frame: Matrix, offset: np.ndarray | None) -> Link:
        where = f"link[{raw.name}]"
        body = LinkBodyReader(self.values, self.resolver, self.path)
        shift = np.linalg.inv(_translation(offset))
        inertial_el = self.values.child(raw.element, "inertial")
        inertial = body.inertial(inertial_el, where) if inertial_el is not None else None
        if inertial is not None:
            inertial = dataclasses.replace(inertial, origin=_moved(shift, inertial.origin.matrix))
        visuals: list[Visual] = []
        collisions: list[Collision] = []
        for child in raw.element:
            if child.tag == "visual":
                placed = body.visual(child, where)
            elif child.tag == "collision":
                placed = body.collision(child, where)
            else:
                continue
            item_in_link = placed.item.origin.matrix
            pose_el = self.values.child(child, "pose")
            if raw.version >= (1, 7) and pose_el is not None and not pose_el.get("relative_to"):
                placed.relative_to = None  # libsdformat 1.7+ ignores the old frame="…" (unknown-attribute)
            if placed.relative_to:
                target = scoped(scope_of(raw.name), placed.relative_to)
                if self.graph.check_reference(target, placed.pose_span, f"{where}/{child.tag}/pose"):  # type: ignore[arg-type]
                    item_in_link = np.linalg.inv(frame) @ self.graph.pose_in_model(target) @ item_in_link
            moved = dataclasses.replace(placed.item, origin=_moved(shift, item_in_link))
            (visuals if child.tag == "visual" else collisions).append(moved)  # type: ignore[arg-type]
        extras = tuple(
            extension_of(c) for c in raw.element if isinstance(c.tag, str) and c.tag not in _LINK_PARTS
        )
        return Link(raw.name, inertial, tuple(visuals), tuple(collisions), span_of(raw.element), extras)

    def _frame_extensions(self, frames: dict[str, Matrix]) -> list[Extension]:
        """Each ``<frame>`` as an extension: its link and its pose in that link's (model) frame."""
        out = []
        for raw in self.frames:
            link = self.graph.link_of(raw.name)
            if link is None or link not in frames:
                continue
            pose = Pose.from_matrix(np.linalg.inv(frames[link]) @ self.graph.pose_in_model(raw.name))
            attributes = {
                "name": raw.name,
                "attached_to": link,
                "xyz": " ".join(repr(v) for v in pose.xyz),
                "rpy": " ".join(repr(v) for v in pose.rpy),
            }
            out.append(Extension("frame", attributes, raw.element, span_of(raw.element)))
        return out


def scoped(scope: str, name: str) -> str:
    if name == WORLD_FRAME:
        return name
    return scope + name


def scope_of(name: str) -> str:
    head, sep, _ = name.rpartition("::")
    return head + sep


def _translation(offset: np.ndarray | None) -> Matrix:
    out = np.eye(4)
    if offset is not None:
        out[:3, 3] = offset
    return out


def _moved(shift: Matrix, pose: Matrix) -> Pose:
    return Pose.from_matrix(shift @ pose)


def _vec(vector: np.ndarray) -> tuple[float, float, float]:
    return (float(vector[0]), float(vector[1]), float(vector[2]))


def extension_of(element: etree._Element) -> Extension:
    return Extension(
        tag=element.tag if isinstance(element.tag, str) else str(element.tag),
        attributes={k: v for k, v in element.attrib.items() if k != SRC_ATTRIBUTE},
        element=element,
        span=span_of(element),
    )
