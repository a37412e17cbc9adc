"""File-level SDFormat rules that the model reader does not see on its own.

The model reader (:mod:`urdftool.parse.sdf_model`) resolves one model's frames
and poses. This module checks what the specification says about the file as
a whole, per the declared version (see docs/sdf.md):

* elements newer, older or unknown to the declared version (``unknown-element``);
* names: one namespace per model for links, joints, frames and nested models
  (1.7+), per world for models, frames and joints, unique visuals and
  collisions per link, unique worlds (``sdf-name-collision``), reserved names
  (``sdf-reserved-name``);
* a non-static model needs a link or a nested model (``empty-robot``);
* ``canonical_link`` names a link, ``placement_frame`` a frame, a top-level
  model's pose has no ``relative_to`` (``unknown-frame-reference``);
* world frames and world joints (1.7+, 1.10+): names, attachments, cycles;
* the root holds at most one model (``repeated-element``);
* numbers the model reader does not read (world gravity, velocity decay, ...).
* every ``<pose>``'s angles, which must not read as degrees (``angle-looks-like-degrees``);
* attributes the spec requires or a version dropped (:mod:`urdftool.parse.sdf_attributes`).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import field

from lxml import etree

from urdftool.catalogue.sdf import FrameCycle, SdfNameCollision, SdfReservedName, UnknownFrameReference
from urdftool.catalogue.suggest import did_you_mean
from urdftool.catalogue.syntax import (
    EmptyRobot,
    MissingAttribute,
    RepeatedElement,
    SelfLoopJoint,
    UnknownElement,
)
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.parse.angles import degree_poses
from urdftool.parse.locate import span_of
from urdftool.parse.sdf_attributes import attribute_findings
from urdftool.parse.sdf_include import include_uri, standard_model
from urdftool.parse.sdf_spec import ELEMENTS, custom_element, fmt, versions_of
from urdftool.parse.sdf_state import in_state, state_findings
from urdftool.parse.sdf_values import SdfValues
from urdftool.records import record
from urdftool.source import SourceIndex

Version = tuple[int, int]

#: parents whose children are checked against the version table (geometry: by the shape reader)
_CHECKED_PARENTS = {"sdf", "world", "model", "link", "joint", "axis", "limit", "frame", "include",
                    "visual", "collision", "inertial"}
#: numbers the model reader does not read: (parent, child) -> count
_NUMBERS = {
    ("world", "gravity"): 3, ("world", "magnetic_field"): 3, ("wind", "linear_velocity"): 3,
    ("velocity_decay", "linear"): 1, ("velocity_decay", "angular"): 1,
    ("physics", "max_step_size"): 1, ("physics", "real_time_factor"): 1,
    ("physics", "real_time_update_rate"): 1,
}
_FRAMES = ("link", "joint", "frame", "model")


def _elements(parent: etree._Element, *tags: str) -> list[etree._Element]:
    return [c for c in parent if isinstance(c.tag, str) and c.tag in tags]


def reserved(name: str) -> bool:
    return name == "world" or (len(name) >= 4 and name.startswith("__") and name.endswith("__"))


@record(frozen=False)
class _Scope:
    """Scoped frame names of a world: ``M``, ``M::L``, ``M::N::F``, with each model's canonical link."""

    names: set[str] = field(default_factory=set)
    #: scoped names under an ``<include>`` whose content is not read here
    opaque: set[str] = field(default_factory=set)
    canonical: dict[str, str] = field(default_factory=dict)

    def knows(self, name: str) -> bool:
        if name in self.names or name == "world":
            return True
        return any(name.startswith(prefix + "::") for prefix in self.opaque)


@record(frozen=False)
class SdfSemantics:
    """Collects the findings of :func:`check_document`."""

    version: Version
    values: SdfValues = field(default_factory=lambda: SdfValues(SourceIndex()))
    out: list[Diagnostic] = field(default_factory=list)
    #: id of a world ``<include>`` element -> the name of the model it brought in (the reader's)
    include_names: dict[int, str] = field(default_factory=dict)

    def check(self, root: etree._Element) -> list[Diagnostic]:
        self._versions(root)
        for state in (s for world in _elements(root, "world") for s in _elements(world, "state")):
            self.out.extend(state_findings(state, self.version))
        models = _elements(root, "model")
        if len(models) > 1:
            self.out.append(RepeatedElement.diagnostic(
                f"<sdf> holds {len(models)} <model> elements; a file holds one model (or worlds)",
                span_of(models[1]), element="sdf",
                help="put the models in a <world>, or in one file each"))
        for model in models:
            self._model(model, top=True)
        self._unique(_elements(root, "world"), "world", "sdf", always=True)
        for world in _elements(root, "world"):
            self._world(world)
        self._numbers(root)
        self.out.extend(degree_poses(root, span_of))
        self.out.extend(attribute_findings(root, self.version, self.values))
        self.out.extend(self.values.diagnostics)
        return self.out

    # -- versions ----------------------------------------------------------------

    def _versions(self, root: etree._Element) -> None:
        for element in root.iter():
            if not isinstance(element.tag, str) or element.tag not in _CHECKED_PARENTS:
                continue
            parent = element.getparent()
            if element.tag != "sdf" and (parent is None or not isinstance(parent.tag, str)
                                         or parent.tag == "plugin" or in_state(element)):
                continue
            for child in element:
                if not isinstance(child.tag, str) or custom_element(child.tag):
                    continue
                self._version_of(element.tag, child)

    def _version_of(self, parent: str, child: etree._Element) -> None:
        tag = str(child.tag)
        known = versions_of(parent, tag)
        if known is not None and known[0] <= self.version <= known[1]:
            return
        if known is None:
            if tag == "plugin" or (parent == "limit" and tag == "stiffness"):
                return
            message = f"<{tag}> is not an SDFormat element of <{parent}>"
            message += did_you_mean(tag, list(ELEMENTS.get(parent, {})))
        elif known[0] > self.version:
            message = (f"<{tag}> in <{parent}> is SDFormat {fmt(known[0])}+, "
                       f"but the file declares version {fmt(self.version)}")
        else:
            message = (f"<{tag}> in <{parent}> was removed after SDFormat {fmt(known[1])}; "
                       f"the file declares version {fmt(self.version)}")
        self.out.append(UnknownElement.diagnostic(
            message, span_of(child), element=parent,
            help="libsdformat copies the element and otherwise ignores it",
            data={"element": tag, "parent": parent, "versions": [fmt(v) for v in known] if known else None}))

    # -- names -------------------------------------------------------------------

    def _name(self, element: etree._Element) -> str:
        if element.tag == "include":
            return (element.findtext("name") or "").strip()
        return element.get("name") or ""

    def _effective_name(self, element: etree._Element) -> str:
        """The name an element takes in its scope. An ``<include>`` without ``<name>`` takes the
        included model's (as the reader found it, else the NAME of its ``model://NAME`` URI; ``""``
        when unknown); a merged include (1.9+) brings no name of its own."""
        name = self._name(element)
        if name or element.tag != "include" or _merged(element):
            return name
        if id(element) in self.include_names:
            return self.include_names[id(element)]
        last = include_uri(element).rstrip("/").rpartition("/")[2]
        return "" if "." in last else last

    def _unique(self, elements: list[etree._Element], what: str, where: str, always: bool,
                pairs: Callable[[etree._Element, etree._Element], bool] | None = None) -> None:
        """Report elements of *elements* sharing a name (an error from 1.7, or *always*); only the
        pairs *pairs* accepts (first, later) when it is given."""
        seen: dict[str, etree._Element] = {}
        for element in elements:
            name = self._effective_name(element)
            if not name:
                continue
            first = seen.get(name)
            if first is None:
                seen[name] = element
                continue
            if first.tag == element.tag and element.tag in ("link", "joint"):
                continue  # duplicate-link-name / duplicate-joint-name
            if pairs is not None and not pairs(first, element):
                continue
            error = always or self.version >= (1, 7)
            self.out.append(SdfNameCollision.diagnostic(
                f"{_described(element, name)} in {where} has the name of the <{first.tag}>"
                + (f" of '{include_uri(first)}'" if first.tag == "include" else "")
                + f" on line {_line(first)}"
                + ("" if error else " (allowed before SDFormat 1.7; libsdformat warns)"),
                span_of(element), element=where,
                severity=None if error else Severity.WARNING,
                help=(f"{what} names must be unique" + (" in one namespace since SDFormat 1.7"
                                                         if not always else ""))
                + ("; give each <include> its own <name>" if element.tag == "include" else ""),
                data={"name": name}))

    def _reserved(self, elements: list[etree._Element], where: str) -> None:
        if self.version < (1, 7):
            return
        for element in elements:
            name = element.get("name") or ""
            if reserved(name):
                self.out.append(SdfReservedName.diagnostic(
                    f"<{element.tag} name=\"{name}\"> in {where}: '{name}' is reserved",
                    span_of(element), element=where, data={"name": name}))

    # -- models ------------------------------------------------------------------

    def _model(self, model: etree._Element, top: bool, where: str = "") -> None:
        name = model.get("name") or ""
        here = f"{where}{name}"
        frames = _elements(model, "link", "joint", "frame", "model", "include")
        self._unique(frames, "link, joint, frame and nested model", f"model '{here}'", always=False)
        self._reserved(_elements(model, *_FRAMES), f"model '{here}'")
        for link in _elements(model, "link"):
            for kind in ("visual", "collision"):
                self._unique(_elements(link, kind), kind, f"link '{link.get('name')}'", always=True)
                self._reserved(_elements(link, kind), f"link '{link.get('name')}'")
        static = (model.findtext("static") or "").strip() in ("1", "true")
        if not static and not _elements(model, "link", "model", "include"):
            self.out.append(EmptyRobot.diagnostic(
                f"model '{here}' has no link: a model that is not static needs one",
                span_of(model), element=f"model[{here}]",
                help="add a link, or mark the model <static>true</static>"))
        local = self._local_names(model)
        canonical = model.get("canonical_link")
        if canonical and canonical not in local["links"]:
            self.out.append(UnknownFrameReference.diagnostic(
                f"model '{here}': canonical_link '{canonical}' is not a link of the model"
                + did_you_mean(canonical, sorted(local["links"])),
                self.values.attr_span(model, "canonical_link"), element=f"model[{here}]",
                data={"frame": canonical}))
        placement = model.get("placement_frame")
        if placement and placement not in local["frames"] and not _opaque(placement, local):
            self.out.append(UnknownFrameReference.diagnostic(
                f"model '{here}': placement_frame '{placement}' is not a frame of the model"
                + did_you_mean(placement, sorted(local["frames"])),
                self.values.attr_span(model, "placement_frame"), element=f"model[{here}]",
                data={"frame": placement}))
        pose = model.find("pose")
        if top and pose is not None and pose.get("relative_to"):
            self.out.append(UnknownFrameReference.diagnostic(
                f"model '{here}' is at the top of the file: its pose has no frame to be relative_to "
                f"('{pose.get('relative_to')}')",
                self.values.attr_span(pose, "relative_to"), element=f"model[{here}]/pose",
                data={"frame": pose.get("relative_to")}))
        for nested in _elements(model, "model"):
            self._model(nested, top=False, where=f"{here}::")

    def _local_names(self, model: etree._Element, prefix: str = "") -> dict[str, set[str]]:
        """Links and frames of *model* by scoped name, nested models included (``a::b``)."""
        links: set[str] = set()
        frames: set[str] = {f"{prefix}__model__"} if prefix else {"__model__"}
        opaque: set[str] = set()
        for child in _elements(model, "link", "joint", "frame", "model", "include"):
            name = self._name(child) or (child.findtext("uri") or "").rstrip("/").rpartition("/")[2]
            if not name:
                continue
            frames.add(prefix + name)
            if child.tag == "link":
                links.add(prefix + name)
            elif child.tag == "model":
                inner = self._local_names(child, f"{prefix}{name}::")
                links |= inner["links"]
                frames |= inner["frames"]
                opaque |= inner["opaque"]
            elif child.tag == "include":
                opaque.add(prefix + name)
        return {"links": links, "frames": frames, "opaque": opaque}

    # -- worlds ------------------------------------------------------------------

    def _world(self, world: etree._Element) -> None:
        name = world.get("name")
        if not name:
            self.out.append(MissingAttribute.diagnostic(
                "<world> needs a 'name' attribute", span_of(world), element="world"))
        where = f"world '{name or ''}'"
        models = [c for c in _elements(world, "model", "include") if not _sun(c)]
        self._unique(models, "model", where, always=True)
        frames = _elements(world, "frame")
        joints = _elements(world, "joint") if self.version >= (1, 10) else []
        # two models are the error above; a model against a frame or joint is this one's
        self._unique([*models, *frames, *joints], "model, frame and joint", where, always=False,
                     pairs=lambda first, later: not (_model_like(first) and _model_like(later)))
        # Lights are unique among lights (libsdformat: "light with name[…] already exists");
        # model://sun brings the light "sun".
        self._unique([c for c in _elements(world, "light", "include") if c.tag == "light" or _sun(c)],
                     "light", where, always=True)
        self._reserved([*_elements(world, "model"), *frames, *joints], where)
        for model in _elements(world, "model"):
            self._model(model, top=False)
        if self.version < (1, 7):
            return
        scope = self._world_scope(world)
        for frame in frames:
            self._world_frame_refs(frame, scope, frames)
        for model in _elements(world, "model"):
            self._world_ref(model.find("pose"), "relative_to", scope, f"model[{model.get('name')}]/pose")
        for joint in joints:
            self._world_joint(joint, scope, frames)

    def _world_scope(self, world: etree._Element) -> _Scope:
        scope = _Scope()
        for child in _elements(world, "model", "include", "frame", "joint"):
            name = self._name(child) or (child.findtext("uri") or "").rstrip("/").rpartition("/")[2]
            if not name:
                continue
            scope.names.add(name)
            if child.tag == "model":
                local = self._local_names(child, f"{name}::")
                scope.names |= local["frames"]
                scope.opaque |= local["opaque"]
                links = [n for n in local["links"]]
                first = _elements(child, "link")
                canonical = child.get("canonical_link")
                if canonical:
                    scope.canonical[name] = f"{name}::{canonical}"
                elif first:
                    scope.canonical[name] = f"{name}::{first[0].get('name')}"
                elif links:
                    scope.canonical[name] = sorted(links)[0]
            elif child.tag == "include":
                scope.opaque.add(name)
        return scope

    def _world_ref(self, element: etree._Element | None, attribute: str, scope: _Scope, where: str) -> bool:
        if element is None:
            return True
        target = element.get(attribute) if attribute else (element.text or "").strip()
        if not target or scope.knows(target):
            return True
        span = self.values.attr_span(element, attribute) if attribute else span_of(element)
        self.out.append(UnknownFrameReference.diagnostic(
            f"{where}: there is no frame '{target}' in this world"
            + did_you_mean(target, sorted(n for n in scope.names if "::" not in n)),
            span, element=where, data={"frame": target}))
        return False

    def _world_frame_refs(self, frame: etree._Element, scope: _Scope, frames: list[etree._Element]) -> None:
        name = frame.get("name") or ""
        self._world_ref(frame, "attached_to", scope, f"frame[{name}]")
        self._world_ref(frame.find("pose"), "relative_to", scope, f"frame[{name}]/pose")
        if not name:
            return  # nothing can refer to an unnamed frame, so it closes no cycle
        by_name = {n: f for f in frames if (n := f.get("name"))}
        for via in ("attached_to", "relative_to"):
            chain = [name]
            current = _step(frame, via)
            while current in by_name and current not in chain:
                chain.append(current)
                current = _step(by_name[current], via)
            if current == name and chain[0] == min(chain):
                self.out.append(FrameCycle.diagnostic(
                    f"world frames refer to each other through {via} in a cycle: "
                    + " → ".join(f"'{n}'" for n in [*chain, name]),
                    self.values.attr_span(frame, "attached_to") or span_of(frame),
                    element=f"frame[{name}]", data={"cycle": chain, "via": via}))

    def _resolve(self, name: str, scope: _Scope, frames: list[etree._Element]) -> str:
        """The link a world-scope frame name moves with (as far as it can be told here)."""
        by_name = {f.get("name"): f for f in frames}
        seen: set[str] = set()
        while name in by_name and name not in seen:
            seen.add(name)
            name = by_name[name].get("attached_to") or "world"
        return scope.canonical.get(name, name)

    def _world_joint(self, joint: etree._Element, scope: _Scope, frames: list[etree._Element]) -> None:
        name = joint.get("name") or ""
        ends = {}
        for role in ("parent", "child"):
            end = joint.find(role)
            if end is None:
                continue  # joint-missing-parent-or-child is the model reader's
            ends[role] = (end.text or "").strip()
            self._world_ref(end, "", scope, f"joint[{name}]/{role}")
        if ends.get("child") == "world":
            self.out.append(UnknownFrameReference.diagnostic(
                f"joint[{name}]: the child cannot be 'world'", span_of(joint.find("child")),
                element=f"joint[{name}]/child", data={"frame": "world"}))
        elif "parent" in ends and "child" in ends:
            parent, child = (self._resolve(ends[r], scope, frames) for r in ("parent", "child"))
            if parent == child:
                self.out.append(SelfLoopJoint.diagnostic(
                    f"joint[{name}]: parent '{ends['parent']}' and child '{ends['child']}' "
                    f"are both on '{child}'",
                    span_of(joint), element=f"joint[{name}]", data={"link": child}))

    # -- numbers -----------------------------------------------------------------

    def _numbers(self, root: etree._Element) -> None:
        for element in root.iter():
            if not isinstance(element.tag, str):
                continue
            parent = element.getparent()
            if parent is None or not isinstance(parent.tag, str):
                continue
            count = _NUMBERS.get((parent.tag, element.tag))
            if count is not None:
                self.values.text_numbers(element, f"{parent.tag}/{element.tag}", (count,))


def _sun(element: etree._Element) -> bool:
    """An ``<include>`` of Gazebo's standard ``model://sun``, which is a light."""
    return element.tag == "include" and standard_model(include_uri(element)) == "sun"


def _model_like(element: etree._Element) -> bool:
    return element.tag in ("model", "include")


def _merged(include: etree._Element) -> bool:
    return (include.get("merge") or "").strip().lower() in {"true", "1"}


def _described(element: etree._Element, name: str) -> str:
    if element.tag == "include":
        if (element.findtext("name") or "").strip():
            return f"<include> of '{include_uri(element)}' named '{name}'"
        return f"<include> of '{include_uri(element)}' (model '{name}', no <name>)"
    return f'<{element.tag} name="{name}">'


def _line(element: etree._Element) -> str:
    span = span_of(element)
    return str(span.line) if span is not None and span.line is not None else "?"


def _step(frame: etree._Element, via: str) -> str | None:
    """The frame that *frame* names through *via* (``attached_to``, or its pose's ``relative_to``)."""
    pose = frame.find("pose")
    if via == "attached_to":
        target = frame.get("attached_to")
    else:
        target = pose.get("relative_to") if pose is not None else None
    return str(target) if target is not None else None


def _opaque(name: str, local: dict[str, set[str]]) -> bool:
    return any(name.startswith(prefix + "::") for prefix in local["opaque"])


def check_document(root: etree._Element, version: Version,
                   include_names: dict[int, str] | None = None) -> Iterator[Diagnostic]:
    """File-level SDFormat findings of the document whose root is *root* (an ``<sdf>``);
    *include_names* gives the model name each world ``<include>`` brought in (by element id)."""
    yield from SdfSemantics(version, include_names=dict(include_names or {})).check(root)
