"""Reading MoveIt's SRDF (Semantic Robot Description Format) with positions.

An SRDF names parts of a robot that the URDF describes: planning groups, named
states, end effectors, virtual and passive joints, and the link pairs whose
collisions are never checked. It is read here into plain dataclasses whose
every name carries the :class:`~urdftool.source.Span` where it was written, so
the rules in :mod:`urdftool.rules.srdf` can check it against the robot and
locate each finding in the ``.srdf`` (or the ``.srdf.xacro`` it came from).

The reader uses the same safe XML reader as the URDF reader; a ``.xacro`` SRDF
goes through the same xacro expansion. Reading never raises on content: what
cannot be read becomes a diagnostic of a reader rule (``xml-syntax``,
``not-a-robot``, ``missing-attribute``, ``invalid-number``, ``unknown-element``).
"""

from __future__ import annotations

import functools
import os
from collections.abc import Callable, Mapping
from dataclasses import field

from lxml import etree

from urdftool.catalogue.suggest import did_you_mean
from urdftool.catalogue.syntax import InvalidNumber, MissingAttribute, NotARobot, UnknownElement
from urdftool.diagnostics import Diagnostic
from urdftool.parse.locate import span_of
from urdftool.parse.packages import PackageResolver
from urdftool.parse.values import parse_number
from urdftool.parse.xmlio import read_file
from urdftool.records import record
from urdftool.source import Span

#: Top-level elements of the SRDF specification (srdfdom).
SRDF_ELEMENTS = frozenset(
    {"group", "group_state", "end_effector", "virtual_joint", "passive_joint",
     "disable_collisions", "enable_collisions", "disable_default_collisions", "link_sphere_approximation",
     "joint_property"}
)
#: Extensions other readers define and srdfdom ignores: Pinocchio's rotor parameters,
#: HPP's grippers, handles and contacts, and example-robot-data's per-robot notes.
#: Skipped without a finding.
EXTENSION_ELEMENTS = frozenset({"rotor_params", "specificities", "gripper", "handle", "contact"})
#: Children a ``<group>`` may have.
GROUP_CHILDREN = frozenset({"link", "joint", "chain", "group"})
#: Reasons MoveIt Setup Assistant writes on ``<disable_collisions>``.
KNOWN_REASONS = frozenset({"Adjacent", "Default", "Always", "Never", "User"})
VIRTUAL_JOINT_TYPES = frozenset({"fixed", "floating", "planar"})


@record
class Named:
    """A name as written, and where."""

    name: str
    span: Span | None = None


@record
class Chain:
    base: Named
    tip: Named
    span: Span | None = None


@record
class Group:
    name: str
    links: tuple[Named, ...] = ()
    joints: tuple[Named, ...] = ()
    chains: tuple[Chain, ...] = ()
    subgroups: tuple[Named, ...] = ()
    span: Span | None = None


@record
class JointValue:
    """One ``<joint name value>`` of a group state; ``values`` is empty when none could be read."""

    name: str
    values: tuple[float, ...]
    span: Span | None = None


@record
class GroupState:
    name: str
    #: ``None`` when not written: Pinocchio reads such a state, MoveIt skips it
    group: Named | None
    joints: tuple[JointValue, ...] = ()
    span: Span | None = None


@record
class EndEffector:
    name: str
    parent_link: Named
    group: Named
    parent_group: Named | None = None
    span: Span | None = None


@record
class VirtualJoint:
    name: str
    type: str
    parent_frame: str
    child_link: Named
    span: Span | None = None


@record
class CollisionPair:
    """A ``<disable_collisions>`` (or ``<enable_collisions>``) entry."""

    link1: Named
    link2: Named
    reason: str | None
    span: Span | None = None
    enable: bool = False


#: ``(link1, link2, reason, enable)`` of a collision entry (:attr:`Srdf.collision_names`)
PairNames = tuple[str, str, str | None, bool]


@record(frozen=False)
class Srdf:
    """One SRDF file, read; ``diagnostics`` are the reader's findings."""

    path: str
    robot_name: str | None = None
    groups: list[Group] = field(default_factory=list)
    group_states: list[GroupState] = field(default_factory=list)
    end_effectors: list[EndEffector] = field(default_factory=list)
    virtual_joints: list[VirtualJoint] = field(default_factory=list)
    passive_joints: list[Named] = field(default_factory=list)
    #: every ``<disable_default_collisions link>``
    default_disabled: list[Named] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    span: Span | None = None
    #: every file read (the xacro includes), the SRDF first
    files: list[str] = field(default_factory=list)
    #: builds :attr:`collisions` when they are first read (``None``: there are none)
    collision_pairs: Callable[[], list[CollisionPair]] | None = field(default=None, repr=False, compare=False)
    #: builds :attr:`collision_names` when they are first read (``None``: from :attr:`collisions`)
    collision_names_of: Callable[[], list[PairNames]] | None = field(default=None, repr=False, compare=False)

    @functools.cached_property
    def collisions(self) -> list[CollisionPair]:
        """Every ``<disable_collisions>`` and ``<enable_collisions>`` pair that names both links,
        in document order. MoveIt Setup Assistant writes hundreds to thousands of them and a
        structural check reads none, so they are built when first read; the reader has already
        reported the entries it skips."""
        return self.collision_pairs() if self.collision_pairs is not None else []

    @functools.cached_property
    def collision_names(self) -> list[PairNames]:
        """``(link1, link2, reason, enable)`` of each pair of :attr:`collisions`, in the same order,
        without their spans and records: what a rule tests every pair for, at a fifth of the cost
        of building the pairs. A rule reads :attr:`collisions` only when a pair has a finding."""
        if self.collision_names_of is None or "collisions" in self.__dict__:
            return [(p.link1.name, p.link2.name, p.reason, p.enable) for p in self.collisions]
        return self.collision_names_of()

    def group(self, name: str) -> Group | None:
        return next((g for g in self.groups if g.name == name), None)

    def __getstate__(self) -> dict[str, object]:
        """Pickled with its pairs built, and without the reader that builds them."""
        state = dict(self.__dict__)
        state.update(collisions=self.collisions, collision_pairs=None, collision_names_of=None)
        return state


def is_srdf_xacro(path: str) -> bool:
    return path.lower().endswith(".xacro")


def read_srdf(path: str, resolver: PackageResolver | None = None,
              args: Mapping[str, str] | None = None) -> Srdf:
    """Read the SRDF at *path* (expanding it first when it is a ``.xacro``).

    *args* are the model's xacro arguments: MoveIt launch files pass an
    ``.srdf.xacro`` the mappings they pass the URDF (UR's ``ur.srdf.xacro``
    reads ``$(arg name)`` before it declares it, so xacro stops without one).
    Arguments the SRDF does not know are not reported: they were given for the model.
    Raises :class:`OSError` only when the file cannot be opened.
    """
    path = os.fspath(path)
    if is_srdf_xacro(path):
        # Function-level: the xacro processor (and its minidom) is needed only for an .srdf.xacro.
        from urdftool.parse.xacro import expand

        result = expand(path, resolver or PackageResolver.create(), args)
        ignored = {"macros-only", "misspelt-xacro-argument"}
        found = [d for d in result.diagnostics if d.name not in ignored]
        if result.document is None:
            return Srdf(path, diagnostics=found, span=Span(path, 1, 1), files=result.files or [path])
        srdf = _Reader(path).read(result.document.root)
        srdf.diagnostics[:0] = found
        srdf.files = result.files or [path]
        return srdf
    document, problems = read_file(path, table=True)  # the SRDF keeps no element: no stamps
    if document is None:
        return Srdf(path, diagnostics=problems, span=Span(path, 1, 1), files=[path])
    srdf = _Reader(path, document.locator()).read(document.root)
    srdf.diagnostics[:0] = problems
    srdf.files = [path]
    return srdf


_PAIR_TAGS = frozenset({"disable_collisions", "enable_collisions"})


class _Reader:
    def __init__(self, path: str, locate: Callable[[etree._Element], Span | None] = span_of) -> None:
        self.path = path
        self.locate = locate
        self.diagnostics: list[Diagnostic] = []

    def span(self, element: etree._Element) -> Span:
        return self.locate(element) or Span(self.path)

    def attr(self, element: etree._Element, name: str, where: str) -> str | None:
        value = (element.get(name) or "").strip()
        if not value:
            self.diagnostics.append(
                MissingAttribute.diagnostic(
                    f"<{element.tag}> in {where} has no '{name}' attribute; MoveIt skips the element",
                    self.span(element),
                    element=f"{where}/{element.tag}",
                )
            )
            return None
        return value

    def named(self, element: etree._Element, name: str, where: str, span: Span | None = None) -> Named | None:
        """The attribute *name* with the element's span (*span* when the caller has it already)."""
        value = self.attr(element, name, where)
        return None if value is None else Named(value, span or self.span(element))

    def read(self, root: etree._Element) -> Srdf:
        srdf = Srdf(self.path, span=self.span(root))
        if root.tag != "robot":
            self.diagnostics.append(
                NotARobot.diagnostic(
                    f"the SRDF's root element is <{root.tag}>, not <robot>", self.span(root),
                    element=str(root.tag),
                )
            )
            srdf.diagnostics = self.diagnostics
            return srdf
        srdf.robot_name = root.get("name")
        where = f"robot[{srdf.robot_name or ''}]"
        pairs: list[etree._Element] = []
        # each pair's link names, two by two: the rules read them, not the attributes again
        names: list[str] = []
        for element in root:
            tag = element.tag
            if tag in _PAIR_TAGS:  # most of a MoveIt SRDF: asked first, and inline when complete
                link1 = (element.get("link1") or "").strip()
                link2 = (element.get("link2") or "").strip()
                if link1 and link2:
                    pairs.append(element)
                    names.append(link1)
                    names.append(link2)
                else:
                    self.names_both_links(element)
                continue
            if not isinstance(tag, str):
                continue
            if tag == "group":
                group = self.group(element)
                if group is not None:
                    srdf.groups.append(group)
            elif tag == "group_state":
                state = self.group_state(element)
                if state is not None:
                    srdf.group_states.append(state)
            elif tag == "end_effector":
                effector = self.end_effector(element)
                if effector is not None:
                    srdf.end_effectors.append(effector)
            elif tag == "virtual_joint":
                virtual = self.virtual_joint(element)
                if virtual is not None:
                    srdf.virtual_joints.append(virtual)
            elif tag == "passive_joint":
                passive = self.named(element, "name", where)
                if passive is not None:
                    srdf.passive_joints.append(passive)
            elif tag == "disable_default_collisions":
                link = self.named(element, "link", where)
                if link is not None:
                    srdf.default_disabled.append(link)
            elif tag in SRDF_ELEMENTS or tag in EXTENSION_ELEMENTS:
                continue
            else:
                self.unknown(element, where, SRDF_ELEMENTS)
        if pairs:
            srdf.collision_pairs = functools.partial(self.collision_pairs, pairs, names)
            srdf.collision_names_of = functools.partial(_collision_names, pairs, names)
        srdf.diagnostics = self.diagnostics
        return srdf

    def unknown(self, element: etree._Element, where: str, known: frozenset[str]) -> None:
        tag, parent = str(element.tag), element.getparent()
        if tag in SRDF_ELEMENTS and parent is not None and parent.tag != "robot":
            # a real element in the wrong place (a <passive_joint> inside a <group>)
            message = (f"<{tag}> is an SRDF element of <robot>, not of <{parent.tag}>; MoveIt "
                       "ignores it here")
            help_text: str | None = f"move <{tag}> out of <{parent.tag}>, to the top level"
        else:
            message = f"<{tag}> is not an SRDF element; MoveIt ignores it" + did_you_mean(tag, known)
            help_text = None
        self.diagnostics.append(
            UnknownElement.diagnostic(message, self.span(element), element=f"{where}/{tag}",
                                      help=help_text)
        )

    def group(self, element: etree._Element) -> Group | None:
        name = self.attr(element, "name", "robot")
        if name is None:
            return None
        where = f"group[{name}]"
        links: list[Named] = []
        joints: list[Named] = []
        chains: list[Chain] = []
        subgroups: list[Named] = []
        members = {"link": links, "joint": joints, "group": subgroups}
        for child in element:
            tag = child.tag
            if not isinstance(tag, str):
                continue
            if tag == "chain":
                base = self.named(child, "base_link", where)
                tip = self.named(child, "tip_link", where)
                if base and tip:
                    chains.append(Chain(base, tip, self.span(child)))
                continue
            if tag not in GROUP_CHILDREN:
                self.unknown(child, where, GROUP_CHILDREN)
                continue
            ref = self.named(child, "name", where)
            if ref is not None:
                members[tag].append(ref)
        return Group(name, tuple(links), tuple(joints), tuple(chains), tuple(subgroups), self.span(element))

    def group_state(self, element: etree._Element) -> GroupState | None:
        name = self.attr(element, "name", "robot")
        written = (element.get("group") or "").strip()
        group = Named(written, self.span(element)) if written else None
        if name is None:
            return None
        values: list[JointValue] = []
        where = f"group_state[{name}]"
        for child in element:
            tag = child.tag
            if not isinstance(tag, str):
                continue
            if tag != "joint":
                self.unknown(child, where, frozenset({"joint"}))
                continue
            joint = self.attr(child, "name", where)
            raw = self.attr(child, "value", where)
            if joint is None or raw is None:
                continue
            tokens = raw.split()
            numbers = [n for n in map(parse_number, tokens) if n is not None]
            if len(numbers) != len(tokens) or not numbers:
                self.diagnostics.append(
                    InvalidNumber.diagnostic(
                        f"group state '{name}': joint '{joint}' has value \"{raw}\", not a number",
                        self.span(child),
                        element=f"group_state[{name}]/joint[{joint}]",
                    )
                )
                values.append(JointValue(joint, (), self.span(child)))
                continue
            values.append(JointValue(joint, tuple(numbers), self.span(child)))
        return GroupState(name, group, tuple(values), self.span(element))

    def end_effector(self, element: etree._Element) -> EndEffector | None:
        name = self.attr(element, "name", "robot")
        where = f"end_effector[{name or ''}]"
        link = self.named(element, "parent_link", where)
        group = self.named(element, "group", where)
        if name is None or link is None or group is None:
            return None
        parent_group = (element.get("parent_group") or "").strip()
        parent = Named(parent_group, self.span(element)) if parent_group else None
        return EndEffector(name, link, group, parent, self.span(element))

    def virtual_joint(self, element: etree._Element) -> VirtualJoint | None:
        name = self.attr(element, "name", "robot")
        where = f"virtual_joint[{name or ''}]"
        kind = self.attr(element, "type", where)
        parent = self.attr(element, "parent_frame", where)
        child = self.named(element, "child_link", where)
        if name is None or kind is None or parent is None or child is None:
            return None
        return VirtualJoint(name, kind, parent, child, self.span(element))

    def names_both_links(self, element: etree._Element) -> None:
        """Reports each link a collision entry does not name (one of them at least)."""
        where = str(element.tag)
        span = self.span(element)
        for name in ("link1", "link2"):
            self.named(element, name, where, span)

    def collision_pairs(self, elements: list[etree._Element], names: list[str]) -> list[CollisionPair]:
        """The pairs of *elements*, each of which names both links, two by two in *names*."""
        pairs = []
        for element, link1, link2 in zip(elements, names[::2], names[1::2], strict=True):
            span = self.span(element)  # one span for the pair and both its links
            pairs.append(CollisionPair(Named(link1, span), Named(link2, span), element.get("reason"), span,
                                       enable=element.tag == "enable_collisions"))
        return pairs


def _collision_names(elements: list[etree._Element], names: list[str]) -> list[PairNames]:
    """The names of :meth:`_Reader.collision_pairs`, without their spans and records."""
    return [(link1, link2, e.get("reason"), e.tag == "enable_collisions")
            for e, link1, link2 in zip(elements, names[::2], names[1::2], strict=True)]


__all__ = [
    "KNOWN_REASONS",
    "VIRTUAL_JOINT_TYPES",
    "Chain",
    "CollisionPair",
    "EndEffector",
    "Group",
    "GroupState",
    "JointValue",
    "Named",
    "PairNames",
    "Srdf",
    "VirtualJoint",
    "is_srdf_xacro",
    "read_srdf",
]
