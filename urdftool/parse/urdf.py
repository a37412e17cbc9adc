"""URDF reader: an lxml tree (already stamped with positions) into a typed Robot.

It follows urdfdom's reading of the format (the first of a repeated element
wins, ``<axis>`` defaults to x, a missing ``<origin>`` is the identity) and
reports everything urdfdom would refuse or silently ignore, then carries on.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import field

from lxml import etree

from urdftool.catalogue.suggest import closest, did_you_mean
from urdftool.catalogue.syntax import (
    JointMissingParentOrChild,
    NotARobot,
    RepeatedElement,
    RobotNameMissing,
    UnknownAttribute,
    UnknownElement,
    VendorExtension,
)
from urdftool.catalogue.units import ONE_TURN, AngleLooksLikeDegrees
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.model import (
    IDENTITY,
    Collision,
    Extension,
    Joint,
    Link,
    Material,
    Pose,
    Robot,
    Visual,
)
from urdftool.parse.angles import degree_poses
from urdftool.parse.locate import span_of
from urdftool.parse.packages import PackageResolver
from urdftool.parse.urdf_joints import JointParts
from urdftool.parse.urdf_links import LinkParts
from urdftool.parse.urdf_schema import (
    ATTRIBUTES,
    CHILDREN,
    COSMETIC_REPEATS,
    KNOWN_EXTENSIONS,
    LINK_EXTENSIONS,
    SDF_ISMS,
    VENDOR_ELEMENTS,
    attribute_verdict,
    is_extension_name,
)
from urdftool.parse.values import ValueReader
from urdftool.parse.xmlio import XmlDocument
from urdftool.records import record
from urdftool.source import SRC_ATTRIBUTE, SourceIndex, Span

_ZERO = (0.0, 0.0, 0.0)

#: Attribute layouts (the names of one element, in lxml's order) already judged to hold only
#: names its tag allows, by tag. A file repeats a few layouts thousands of times (``xyz rpy``,
#: ``name type``); comparing lxml's fresh list of names with a known one costs less than hashing
#: every name for a set test.
_CLEAN_LAYOUTS: dict[str, list[list[str]]] = {tag: [] for tag in ATTRIBUTES}
#: Layouts remembered per tag; any other layout is judged by the set test each time.
_LAYOUTS_KEPT = 8
#: The child tags each parent allows, as sets: ``issuperset`` of a dict of groups looks up each
#: group's tag, where comparing two dicts' key views builds both views and an iterator first.
_CHILD_TAGS = {parent: frozenset(children) for parent, children in CHILDREN.items()}
_NO_CHILDREN: frozenset[str] = frozenset()


@record(frozen=False, eq=False)  # one run's state, equal only to itself
class UrdfReader(JointParts, LinkParts):
    """Reads one URDF document. Create, call :meth:`read`, take ``values.diagnostics``."""

    path: str
    sources: SourceIndex
    resolver: PackageResolver
    #: the document came out of xacro (substitutions were already expanded)
    expanded: bool = False
    #: the document being read when its positions are in a table (``None``: its elements are stamped)
    document: XmlDocument | None = None
    values: ValueReader = field(init=False)
    span: Callable[[etree._Element], Span | None] = field(init=False)  #: where a start tag was written

    def __post_init__(self) -> None:
        self.span = self.document.locator() if self.document is not None else span_of
        self.values = ValueReader(self.sources, check_substitutions=not self.expanded, locate=self.span)
        #: (element, who reads it) -> (where first seen, elements carrying it, the names seen)
        self.vendor: dict[tuple[str, str], tuple[Span | None, int, list[str]]] = {}
        #: the poses read from ``<origin>``s that had nothing to report, by their ``xyz`` and ``rpy``
        #: texts (``None``: not written). example-robot-data's files write 2,800 distinct origins
        #: 6,800 times (``xyz="0 0 0" rpy="0 0 0"``); a pose is a value, so one read serves every
        #: element of the document that writes the same texts. A text with a finding is not kept:
        #: each element that writes it is read, and reported, on its own.
        self.poses: dict[tuple[str | None, str | None], Pose] = {}

    def _vendor(self, tag: str, names: list[str], span: Span | None, reader: str) -> None:
        first, count, seen = self.vendor.get((tag, reader), (span, 0, []))
        self.vendor[tag, reader] = (first, count + 1, [*seen, *(n for n in names if n not in seen)])

    def _report_vendor(self) -> None:
        for (tag, reader), (span, count, seen) in sorted(self.vendor.items()):
            names = sorted(seen)  # the same message however the attributes are ordered
            times = f" on {count} elements" if count > 1 else ""
            key = f"<{tag} {' '.join(names)}>" if tag.isidentifier() else f"{tag}{''.join(names)}"
            self._report(VendorExtension.diagnostic(
                f"{key}{times}: {reader}", span,
                data={"extension": key, "count": count, "names": names, "read_by": reader},
            ))

    @property
    def diagnostics(self) -> list[Diagnostic]:
        return self.values.diagnostics

    # -- helpers -----------------------------------------------------------------

    def _report(self, diagnostic: Diagnostic) -> None:
        self.values.diagnostics.append(diagnostic)

    def _check_attributes(self, element: etree._Element, tag: str, where: str) -> None:
        """Report the attributes of *element* (a ``<tag>``: the caller has its tag already, and
        lxml builds a new string each time it is asked) that its tag does not have."""
        layouts = _CLEAN_LAYOUTS.get(tag)
        if layouts is None:  # a tag the schema gives no attribute list: nothing to judge
            return
        names = element.keys()
        if names in layouts:  # the common case: compared with a few lists, no name hashed
            return
        allowed = ATTRIBUTES[tag]
        if allowed.issuperset(names):
            if len(layouts) < _LAYOUTS_KEPT:
                layouts.append(names)
            return
        unknown, vendor = attribute_verdict(tag, tuple(names))
        if unknown:
            for name in unknown:
                # The closest name is no suggestion when the tag has it already (ANYmal's
                # <limit command_effort="…"> stands beside its effort="…"), and the next closest
                # is a guess.
                match = closest(name, allowed)
                hint = f"; did you mean '{match}'?" if match and element.get(match) is None else ""
                self._report(
                    UnknownAttribute.diagnostic(
                        f"{where}: <{tag}> has no attribute '{name}'" + hint,
                        self.values.attr_span(element, name),
                        element=where,
                        data={"attribute": name, "allowed": sorted(allowed)},
                    )
                )
        for reader, names in vendor:
            self._vendor(tag, list(names), self.values.attr_span(element, names[0]), reader)

    def _children(self, element: etree._Element, parent: str, where: str) -> dict[str, list[etree._Element]]:
        """Group the child elements of *element* (a ``<parent>``) by tag, reporting unknown and
        repeated ones."""
        groups: dict[str, list[etree._Element]] = {}
        repeated = False
        # element[:] is the list of children built in C: iterating the element instead costs an
        # iterator and a tag matcher per element and a step per child (iterchildren(etree.Element)
        # more, with its filter)
        for child in element[:]:
            tag = child.tag
            if tag in groups:
                groups[tag].append(child)
                repeated = True
            elif isinstance(tag, str):  # an element, not a comment kept by xacro
                groups[tag] = [child]
        if not repeated and _CHILD_TAGS.get(parent, _NO_CHILDREN).issuperset(groups):  # the common case
            return groups
        allowed = CHILDREN.get(parent, {})
        for tag, items in groups.items():
            if tag in allowed:
                if not allowed[tag] and len(items) > 1:
                    first = getattr(self.span(items[0]), "line", None) or "?"
                    for extra in items[1:]:
                        # A copy of the first says what the first says: loaders that keep the
                        # first and those that keep the last build the same robot.
                        copy = _same_element(items[0], extra)
                        self._report(
                            RepeatedElement.diagnostic(
                                f"{where}: <{tag}> is repeated, a copy of the first one (line "
                                f"{first}): whichever a loader keeps, the robot is the same"
                                if copy else
                                f"{where}: <{tag}> is repeated; the first one (line "
                                f"{first}) is used and this one ignored",
                                self.span(extra),
                                element=f"{where}/{tag}",
                                # CAD exporters write several colours per visual; every loader
                                # shows the first, and nothing but the look depends on it.
                                severity=Severity.WARNING
                                if copy or tag in COSMETIC_REPEATS else None,
                            )
                        )
            elif (parent, tag) in VENDOR_ELEMENTS:
                reader = VENDOR_ELEMENTS[parent, tag]
                for item in items:
                    self._vendor(f"<{parent}>", [f"<{tag}>"], self.span(item), reader)
            elif not self._tolerated(parent, tag):
                for item in items:
                    self._report(
                        UnknownElement.diagnostic(
                            f"{where}: <{parent}> has no child <{tag}>"
                            + did_you_mean(tag, allowed),
                            self.span(item),
                            element=f"{where}/{tag}",
                        )
                    )
        return groups

    def _extension(self, element: etree._Element) -> Extension:
        """*element* kept in the model as written; marked, since rules and exporters locate
        its children with ``span_of`` after the reading."""
        attributes = dict(element.items())  # (copied in C, before the mark adds its attribute)
        attributes.pop(SRC_ATTRIBUTE, None)  # a stamp (xacro output) is no attribute of the block
        if self.document is not None:
            self.document.mark(element)
        tag = element.tag
        return Extension(  # tag, attributes, element, span (by position: no dict of keywords)
            tag if isinstance(tag, str) else str(tag),
            attributes,
            element,
            self.span(element),
        )

    @staticmethod
    def _tolerated(parent: str, tag: str) -> bool:
        if is_extension_name(tag):
            return True
        if parent in ("link", "joint") and tag in SDF_ISMS:
            return True
        return parent in ("link", "collision") and tag in LINK_EXTENSIONS

    def _origin(self, groups: dict[str, list[etree._Element]], where: str) -> Pose:
        items = groups.get("origin")
        if not items:
            return IDENTITY
        origin = items[0]
        here = f"{where}/origin"
        self._check_attributes(origin, "origin", here)
        written = (origin.get("xyz"), origin.get("rpy"))
        pose = self.poses.get(written)
        if pose is not None:  # read before from the same texts, with nothing to report
            return pose
        diagnostics = self.values.diagnostics
        reported = len(diagnostics)
        xyz = self.values.vector(origin, "xyz", here) or _ZERO
        rpy = self.values.vector(origin, "rpy", here) or _ZERO
        # (the numbers are finite: three comparisons say what max() of their sizes would)
        if not (-ONE_TURN <= rpy[0] <= ONE_TURN and -ONE_TURN <= rpy[1] <= ONE_TURN
                and -ONE_TURN <= rpy[2] <= ONE_TURN):  # rare: judged off the hot path
            text = f'<origin rpy="{origin.get("rpy", "").strip()}">'
            found = AngleLooksLikeDegrees.judge(rpy, self.values.attr_span(origin, "rpy"), here, text)
            if found is not None:
                self._report(found)
        pose = Pose(xyz, rpy)
        if len(diagnostics) == reported:
            self.poses[written] = pose
        return pose

    # -- document ----------------------------------------------------------------

    def read(self, root: etree._Element) -> Robot | None:
        """The robot in *root*, or ``None`` when the root is not ``<robot>`` (reported)."""
        if root.tag != "robot":
            self._report(
                NotARobot.diagnostic(
                    f"root element is <{root.tag}>, not <robot>",
                    self.span(root),
                    help="urdftool reads URDF (<robot>), xacro and SDF (<sdf>) files",
                )
            )
            return None
        self._check_attributes(root, "robot", "robot")
        name = root.get("name")
        if not name or not name.strip():
            self._report(
                RobotNameMissing.diagnostic(
                    "<robot> has no name" if name is None else "<robot> has an empty name",
                    self.span(root),
                    element="robot",
                )
            )
            name = None
        links: list[Link] = []
        joints: list[Joint] = []
        materials: list[Material] = []
        extensions: list[Extension] = []
        #: whether the document holds a <pose> at all (looked for at the first <gazebo> block)
        poses: bool | None = None
        for child in root[:]:  # (the children listed in C, as _children does)
            tag = child.tag
            if not isinstance(tag, str):
                continue
            if tag == "link":
                links.append(self._link(child))
            elif tag == "joint":
                joint = self._joint(child)
                if joint is not None:
                    joints.append(joint)
            elif tag == "material":
                materials.append(self._material(child, "robot/material"))
            else:
                if ("robot", tag) in VENDOR_ELEMENTS:
                    self._vendor("<robot>", [f"<{tag}>"], self.span(child), VENDOR_ELEMENTS["robot", tag])
                elif tag not in KNOWN_EXTENSIONS and not is_extension_name(tag):
                    self._report(
                        UnknownElement.diagnostic(
                            f"<robot> has no child <{tag}>"
                            + did_you_mean(tag, ["link", "joint", "material", *KNOWN_EXTENSIONS]),
                            self.span(child),
                            element=f"robot/{tag}",
                        )
                    )
                extensions.append(self._extension(child))
                if tag == "gazebo":  # SDF inside: a sensor's or plugin's <pose> in degrees
                    if poses is None:
                        # One walk of the document in C settles most files, which have no <pose>:
                        # example-robot-data has 1,143 <gazebo> blocks, each a walk of its own.
                        poses = next(root.iter("pose"), None) is not None
                    if poses:
                        self.diagnostics.extend(degree_poses(child, self.span))
        self._report_vendor()
        return Robot(
            name=name,
            links=tuple(links),
            joints=tuple(joints),
            materials=tuple(materials),
            extensions=tuple(extensions),
            path=self.path,
            format="urdf",
            span=self.span(root),
        )

    # -- links -------------------------------------------------------------------

    def _link(self, element: etree._Element) -> Link:
        name = self.values.text(element, "name", "link", required=True) or ""
        where = f"link[{name}]"
        self._check_attributes(element, "link", where)
        groups = self._children(element, "link", where)
        inertial = self._inertial(groups["inertial"][0], where) if "inertial" in groups else None
        # (lists, not generators, into the tuples: a generator costs more than the one or two
        # parts most links have)
        visuals: tuple[Visual, ...] = ()
        if "visual" in groups:
            here = f"{where}/visual"
            visuals = tuple([self._visual(v, here) for v in groups["visual"]])
        collisions: tuple[Collision, ...] = ()
        if "collision" in groups:
            here = f"{where}/collision"
            collisions = tuple([self._collision(c, here) for c in groups["collision"]])
        extras = () if _CHILD_TAGS["link"].issuperset(groups) else tuple(
            self._extension(item)
            for tag, items in groups.items()
            if tag not in CHILDREN["link"]
            for item in items
        )
        return Link(name, inertial, visuals, collisions, self.span(element), extras)

    def _joint(self, element: etree._Element) -> Joint | None:
        v = self.values
        name = v.text(element, "name", "joint", required=True) or ""
        where = f"joint[{name}]"
        self._check_attributes(element, "joint", where)
        groups = self._children(element, "joint", where)
        jtype = self._joint_type(element, where)
        ends: dict[str, str] = {}
        for role in ("parent", "child"):
            items = groups.get(role)
            link = None
            if items:
                self._check_attributes(items[0], role, f"{where}/{role}")
                link = v.text(items[0], "link", f"{where}/{role}")
            if not link:
                self._report(
                    JointMissingParentOrChild.diagnostic(
                        f"joint '{name}' has no {role} link", self.span(element), element=where
                    )
                )
            ends[role] = link or ""
        axis: tuple[float, float, float] = (1.0, 0.0, 0.0)
        axis_span = None
        if "axis" in groups:
            axis_el = groups["axis"][0]
            here = f"{where}/axis"
            self._check_attributes(axis_el, "axis", here)
            value = v.vector(axis_el, "xyz", here)
            if value is not None:
                axis = value
            axis_span = self.span(axis_el)
        # The fields in Joint's order, not by keyword: a call by keywords builds a dict of them
        # (about 6,000 instructions a joint). Most joints have few of the optional parts: an absent
        # one costs a dict test, not a call.
        return Joint(
            name,
            jtype,
            ends["parent"],
            ends["child"],
            self._origin(groups, where),
            axis,
            self._limit(groups, where) if "limit" in groups else None,
            self._dynamics(groups, where) if "dynamics" in groups else None,
            self._mimic(groups, where) if "mimic" in groups else None,
            self._safety(groups, where) if "safety_controller" in groups else None,
            self._calibration(groups, where) if "calibration" in groups else None,
            self.span(element),
            axis_span,
            None,  # axis2 and limit2: SDF's universal and revolute2 joints
            None,
            () if _CHILD_TAGS["joint"].issuperset(groups) else tuple(
                self._extension(item)
                for tag, items in groups.items()
                if tag not in CHILDREN["joint"]
                for item in items
            ),
        )


def _same_element(first: etree._Element, other: etree._Element) -> bool:
    """Whether two elements say the same: tag, attributes (but the position stamp), text and
    child elements alike, whitespace and comments aside."""
    if first.tag != other.tag or (first.text or "").strip() != (other.text or "").strip():
        return False
    attributes = {k: v for k, v in first.attrib.items() if k != SRC_ATTRIBUTE}
    if attributes != {k: v for k, v in other.attrib.items() if k != SRC_ATTRIBUTE}:
        return False
    children = [c for c in first if isinstance(c.tag, str)]
    others = [c for c in other if isinstance(c.tag, str)]
    return len(children) == len(others) and all(map(_same_element, children, others))


def iter_elements(root: etree._Element) -> Iterator[etree._Element]:
    return (e for e in root.iter() if isinstance(e.tag, str))


__all__ = ["UrdfReader"]
