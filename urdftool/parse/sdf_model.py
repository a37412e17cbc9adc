"""One SDF ``<model>`` (with its nested models and includes) into a typed :class:`Robot`.

Reading happens in two passes. The first collects every link, joint, frame
and nested model under scoped names (``arm::elbow``) and registers each
frame's pose in a :class:`~urdftool.parse.sdf_frames.FrameGraph`. The second
resolves all poses into the model frame and builds the URDF-style model:

* a joint's ``origin`` is its child link's frame in its parent link's frame
  at q = 0, and its ``axis`` is expressed in the child link's frame;
* inertial, visual and collision origins are in their link's frame;
* when a rotational joint's frame is offset from its child link's origin
  (a ``<pose>`` in the joint), the child's frame is moved onto the joint so
  that the joint turns about the frame's origin, as URDF requires; the link's
  contents are re-expressed so nothing moves in the world;
* closed chains are cut into a spanning tree (:mod:`urdftool.parse.sdf_tree`)
  and each cut joint kept as a :class:`~urdftool.model.LoopClosure`;
* a ``<static>`` model, and joints to ``world``, hang from a link named
  ``world`` placed at the world origin.
"""

from __future__ import annotations

import dataclasses
from dataclasses import field

import numpy as np
from lxml import etree

from urdftool.catalogue.syntax import JointMissingParentOrChild, MissingAttribute
from urdftool.diagnostics import Diagnostic
from urdftool.model import Collision, Extension, Joint, JointType, Link, LoopClosure, Pose, Robot, Visual
from urdftool.model.pose import Matrix
from urdftool.parse.locate import span_of
from urdftool.parse.packages import PackageResolver
from urdftool.parse.sdf_elements import LinkBodyReader, joint_details, mimic
from urdftool.parse.sdf_frames import MODEL_FRAME, WORLD_FRAME, FrameGraph, FrameNode
from urdftool.parse.sdf_include import read_include
from urdftool.parse.sdf_tree import spanning_tree
from urdftool.parse.sdf_values import SdfValues
from urdftool.records import record
from urdftool.source import SRC_ATTRIBUTE, SourceIndex, Span

#: model children the reader turns into the model; everything else is kept as an extension
_MODEL_PARTS = {"link", "joint", "frame", "model", "include", "pose", "static", "name", "uri"}
_LINK_PARTS = {"pose", "inertial", "visual", "collision"}
_JOINT_PARTS = {"pose", "parent", "child", "axis"}
#: joints whose motion is a rotation about the joint frame's origin
_ROTATIONAL = {JointType.REVOLUTE, JointType.CONTINUOUS, JointType.SPHERICAL, JointType.UNIVERSAL,
               JointType.REVOLUTE2, JointType.SCREW, JointType.GEARBOX}
_TOLERANCE = 1e-12


@record(frozen=False)
class _RawLink:
    name: str
    element: etree._Element
    version: tuple[int, int]


@record(frozen=False)
class _RawJoint:
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
class _RawFrame:
    name: str
    element: etree._Element


@record(frozen=False)
class SdfModelReader:
    """Reads one top-level ``<model>``; create, then call :meth:`read`."""

    path: str
    resolver: PackageResolver
    values: SdfValues = field(default_factory=lambda: SdfValues(SourceIndex()))
    graph: FrameGraph = field(default_factory=FrameGraph)
    files: list[str] = field(default_factory=list)
    links: list[_RawLink] = field(default_factory=list)
    joints: list[_RawJoint] = field(default_factory=list)
    frames: list[_RawFrame] = field(default_factory=list)
    extensions: list[Extension] = field(default_factory=list)
    #: scope -> the frame ``__model__`` means there, while a merged include is read into that scope
    merged_frames: dict[str, str] = field(default_factory=dict)

    @property
    def diagnostics(self) -> list[Diagnostic]:
        return self.values.diagnostics + self.graph.diagnostics

    def read(self, model: etree._Element, version: tuple[int, int], name: str | None = None,
             world_pose: Matrix | None = None, static: bool | None = None) -> Robot:
        """The robot for *model*; *name*, *world_pose* and *static* override what it says (an include)."""
        name = name or model.get("name")
        if not name:
            self.values.diagnostics.append(
                MissingAttribute.diagnostic(
                    "<model> needs a 'name' attribute", span_of(model), element="model"
                )
            )
        canonical = self._collect(model, "", version)
        self.graph.add(FrameNode(MODEL_FRAME, "model", Pose(), "", canonical or "", span_of(model)))
        if world_pose is None:
            world_pose = self.values.pose(self.values.child(model, "pose"), "model/pose").matrix
        if static is None:
            static = self.values.text_bool(model, "static", "model")
        return self._build(name, model, canonical, world_pose, static)

    # -- pass 1: collect ---------------------------------------------------------

    def _collect(self, model: etree._Element, scope: str, version: tuple[int, int]) -> str | None:
        """Register *model*'s frames under *scope*; return its canonical link (scoped)."""
        first_link: str | None = None
        nested_canonical: str | None = None
        for child in model:
            if not isinstance(child.tag, str):
                continue
            tag = child.tag
            if tag == "link":
                link = self._collect_link(child, scope, version)
                first_link = first_link or link
            elif tag == "joint":
                self._collect_joint(child, scope, version)
            elif tag == "frame":
                self._collect_frame(child, scope, version)
            elif tag == "model":
                found = self._collect_nested(child, scope, child.get("name") or "", version, None)
                nested_canonical = nested_canonical or found
            elif tag == "include" and _merges(child):
                # A merged model's first link is a link of this model, at the include's place.
                found = self._collect_include(child, scope)
                first_link = first_link or found
            elif tag == "include":
                found = self._collect_include(child, scope)
                nested_canonical = nested_canonical or found
            elif tag not in _MODEL_PARTS and not scope:
                self.extensions.append(_extension(child))
        attribute: str | None = model.get("canonical_link")
        if attribute:
            return scope + attribute
        return first_link or nested_canonical

    def _pose_node(self, element: etree._Element, name: str, kind: str, scope: str, default_to: str,
                   attached_to: str, version: tuple[int, int]) -> None:
        pose_el = self.values.child(element, "pose")
        pose = self.values.pose(pose_el, f"{kind}[{name}]/pose")
        relative = _relative(pose_el, version)
        span = None
        if pose_el is not None:
            attr = "relative_to" if pose_el.get("relative_to") else "frame"
            span = self.values.attr_span(pose_el, attr)
        target = self._scoped(scope, relative) if relative else default_to
        self.graph.add(FrameNode(name, kind, pose, target, attached_to, span or span_of(element),
                                 self.values.attr_span(element, "attached_to")))

    def _collect_link(self, element: etree._Element, scope: str, version: tuple[int, int]) -> str:
        name = scope + (self.values.text(element, "name", "link", required=True) or "")
        self.links.append(_RawLink(name, element, version))
        self._pose_node(element, name, "link", scope, self._model_frame(scope), name, version)
        return name

    def _collect_joint(self, element: etree._Element, scope: str, version: tuple[int, int]) -> None:
        name = scope + (self.values.text(element, "name", "joint", required=True) or "")
        ends = {}
        for role in ("parent", "child"):
            end = self.values.child(element, role)
            text = (end.text or "").strip() if end is not None else ""
            if not text:
                self.values.diagnostics.append(
                    JointMissingParentOrChild.diagnostic(
                        f"joint '{name}' has no {role} link", span_of(element), element=f"joint[{name}]"
                    )
                )
            ends[role] = self._scoped(scope, text) if text else ""
        # A joint named like a link is refused by libsdformat (one namespace for
        # frames) but common in converted URDF; its frame gets a private key.
        key = name if name not in self.graph.nodes else f"{name}\x00joint"
        self.joints.append(_RawJoint(name, element, ends["parent"], ends["child"], scope, version, key,
                                     self._model_frame(scope)))
        self._pose_node(
            element, key, "joint", scope, ends["child"] or self._model_frame(scope), ends["child"], version
        )

    def _collect_frame(self, element: etree._Element, scope: str, version: tuple[int, int]) -> None:
        name = scope + (self.values.text(element, "name", "frame", required=True) or "")
        attached = element.get("attached_to")
        target = self._scoped(scope, attached) if attached else self._model_frame(scope)
        self.frames.append(_RawFrame(name, element))
        self._pose_node(element, name, "frame", scope, target, target, version)

    def _collect_nested(self, model: etree._Element, scope: str, name: str, version: tuple[int, int],
                        pose_source: etree._Element | None) -> str | None:
        inner = f"{scope}{name}::"
        canonical = self._collect(model, inner, version)
        frame = inner + MODEL_FRAME
        self.graph.aliases[scope + name] = frame
        self._pose_node(pose_source if pose_source is not None else model, frame, "model", scope,
                        self._model_frame(scope), canonical or "", version)
        return canonical

    def _collect_merged(self, model: etree._Element, scope: str, name: str, version: tuple[int, int],
                        pose_source: etree._Element) -> str | None:
        """An ``<include merge="true">`` (1.9+): the model's links, joints, frames and plugins join
        *scope* under their own names; its ``__model__`` becomes the frame
        ``_merged__NAME__model__``, placed by the include's pose and attached to the merged model's
        canonical link, as libsdformat's merge does."""
        proxy = f"{scope}_merged__{name}__model__"
        outer = self.merged_frames.get(scope)
        self.merged_frames[scope] = proxy
        try:
            canonical = self._collect(model, scope, version)
        finally:
            if outer is None:
                del self.merged_frames[scope]
            else:
                self.merged_frames[scope] = outer
        self._pose_node(pose_source, proxy, "frame", scope, self._model_frame(scope), canonical or "",
                        version)
        return canonical

    def _model_frame(self, scope: str) -> str:
        """The frame ``__model__`` names in *scope* (a merged include's proxy while it is read)."""
        return self.merged_frames.get(scope, scope + MODEL_FRAME)

    def _scoped(self, scope: str, name: str) -> str:
        return self._model_frame(scope) if name == MODEL_FRAME else _scoped(scope, name)

    def _collect_include(self, include: etree._Element, scope: str) -> str | None:
        found = read_include(include, self.resolver, self.path)
        self.values.diagnostics.extend(found.diagnostics)
        if found.document is None:
            return None
        if found.path:
            self.files.append(found.path)
        root = found.document.root
        model = root.find("model") if root.tag == "sdf" else (root if root.tag == "model" else None)
        if model is None:
            return None
        version = parse_version(root.get("version"))
        name = (include.findtext("name") or "").strip() or model.get("name") or "model"
        source = include if include.find("pose") is not None else model
        if _merges(include):
            return self._collect_merged(model, scope, name, version, source)
        return self._collect_nested(model, scope, name, version, source)

    # -- pass 2: build -----------------------------------------------------------

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

    def _joint(self, raw: _RawJoint, link_frames: dict[str, Matrix]) -> Joint:
        where = f"joint[{raw.name}]"
        details = joint_details(self.values, raw.element, where, raw.version)
        parent, child = self._end_link(raw.parent), self._end_link(raw.child)
        joint_frame = self.graph.pose_in_model(raw.key or raw.name)
        axis = self._axis_in_model(details.axis, details.axis_frame, joint_frame, raw, where)
        axis2 = (self._axis_in_model(details.axis2, details.axis2_frame, joint_frame, raw, where)
                 if details.axis2 is not None else None)
        follows = mimic(self.values, raw.element, where)
        if follows is not None:  # the leader is named in the joint's own model scope (a::j below it)
            follows = dataclasses.replace(follows, joint=_scoped(raw.scope, follows.joint))
        return Joint(
            name=raw.name, type=details.type, parent=parent, child=child,
            # provisional: the joint frame in the model frame and the axis in the
            # model frame; _place and _closure express them in the links' frames
            origin=Pose.from_matrix(joint_frame), axis=axis,
            limit=details.limit, dynamics=details.dynamics, span=span_of(raw.element),
            axis_span=details.axis_span,  # type: ignore[arg-type]
            axis2=axis2, limit2=details.limit2, mimic=follows,
            extensions=tuple(_extension(c) for c in raw.element
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
                       raw: _RawJoint, where: str) -> tuple[float, float, float]:
        if frame == "joint":
            rotation = joint_frame[:3, :3]
        elif frame == "model":
            rotation = self.graph.pose_in_model(raw.model_frame or raw.scope + MODEL_FRAME)[:3, :3]
        else:
            merged = frame == MODEL_FRAME and raw.model_frame
            target = raw.model_frame if merged else _scoped(raw.scope, frame)
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

    def _link(self, raw: _RawLink, frame: Matrix, offset: np.ndarray | None) -> Link:
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
                target = _scoped(_scope_of(raw.name), placed.relative_to)
                if self.graph.check_reference(target, placed.pose_span, f"{where}/{child.tag}/pose"):  # type: ignore[arg-type]
                    item_in_link = np.linalg.inv(frame) @ self.graph.pose_in_model(target) @ item_in_link
            moved = dataclasses.replace(placed.item, origin=_moved(shift, item_in_link))
            (visuals if child.tag == "visual" else collisions).append(moved)  # type: ignore[arg-type]
        extras = tuple(
            _extension(c) for c in raw.element if isinstance(c.tag, str) and c.tag not in _LINK_PARTS
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


def parse_version(text: str | None) -> tuple[int, int]:
    """``"1.6"`` -> ``(1, 6)``; unreadable or missing -> ``(1, 11)``."""
    try:
        major, minor = (text or "").strip().split(".")[:2]
        return (int(major), int(minor))
    except ValueError:
        return (1, 11)


def _relative(pose: etree._Element | None, version: tuple[int, int]) -> str | None:
    if pose is None:
        return None
    value = pose.get("relative_to") if version >= (1, 7) else (pose.get("frame") or pose.get("relative_to"))
    return value or None


def _merges(include: etree._Element) -> bool:
    """``<include merge="true">`` (SDFormat 1.9+)."""
    return (include.get("merge") or "").strip().lower() in {"true", "1"}


def _scoped(scope: str, name: str) -> str:
    if name == WORLD_FRAME:
        return name
    return scope + name


def _scope_of(name: str) -> str:
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


def _extension(element: etree._Element) -> Extension:
    return Extension(
        tag=element.tag if isinstance(element.tag, str) else str(element.tag),
        attributes={k: v for k, v in element.attrib.items() if k != SRC_ATTRIBUTE},
        element=element,
        span=span_of(element),
    )


__all__ = ["SdfModelReader", "Span", "parse_version"]
