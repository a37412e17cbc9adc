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

from dataclasses import field

from lxml import etree

from urdftool.catalogue.syntax import JointMissingParentOrChild, MissingAttribute
from urdftool.diagnostics import Diagnostic
from urdftool.model import Extension, Pose, Robot
from urdftool.model.pose import Matrix
from urdftool.parse.locate import span_of
from urdftool.parse.packages import PackageResolver
from urdftool.parse.sdf_build import ModelBuilding, RawFrame, RawJoint, RawLink, extension_of, scoped
from urdftool.parse.sdf_frames import MODEL_FRAME, FrameGraph, FrameNode
from urdftool.parse.sdf_include import read_include
from urdftool.parse.sdf_values import SdfValues
from urdftool.records import record
from urdftool.source import SourceIndex, Span

#: model children the reader turns into the model; everything else is kept as an extension
_MODEL_PARTS = {"link", "joint", "frame", "model", "include", "pose", "static", "name", "uri"}


@record(frozen=False)
class SdfModelReader(ModelBuilding):
    """Reads one top-level ``<model>``; create, then call :meth:`read`."""

    path: str
    resolver: PackageResolver
    values: SdfValues = field(default_factory=lambda: SdfValues(SourceIndex()))
    graph: FrameGraph = field(default_factory=FrameGraph)
    files: list[str] = field(default_factory=list)
    links: list[RawLink] = field(default_factory=list)
    joints: list[RawJoint] = field(default_factory=list)
    frames: list[RawFrame] = field(default_factory=list)
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
                self.extensions.append(extension_of(child))
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
        self.links.append(RawLink(name, element, version))
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
        self.joints.append(RawJoint(name, element, ends["parent"], ends["child"], scope, version, key,
                                     self._model_frame(scope)))
        self._pose_node(
            element, key, "joint", scope, ends["child"] or self._model_frame(scope), ends["child"], version
        )

    def _collect_frame(self, element: etree._Element, scope: str, version: tuple[int, int]) -> None:
        name = scope + (self.values.text(element, "name", "frame", required=True) or "")
        attached = element.get("attached_to")
        target = self._scoped(scope, attached) if attached else self._model_frame(scope)
        self.frames.append(RawFrame(name, element))
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
        return self._model_frame(scope) if name == MODEL_FRAME else scoped(scope, name)

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


__all__ = ["SdfModelReader", "Span", "parse_version"]
