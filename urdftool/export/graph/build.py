"""The DOT text of a robot's kinematic tree.

Links are boxes, joints are ellipses between them (filled by joint type), and
the edge from a parent link to a joint carries the joint's origin. Joints that
are not part of the tree (loop closures of closed chains, a second parent, a
cycle, a reference to a missing link) are dashed and do not pull on the layout.
Everything is emitted in tree order, so the same robot gives the same text.
"""

from __future__ import annotations

from collections.abc import Sequence

from urdftool.diagnostics import Diagnostic, Severity
from urdftool.export.graph.dot import DotWriter, Html, html_text
from urdftool.export.graph.findings import SEVERITY_COLOURS, Findings, code_notes, tooltip, worst
from urdftool.export.graph.groups import LinkGroups
from urdftool.export.graph.labels import (
    JOINT_COLOURS,
    html_label,
    joint_lines,
    mass_text,
    origin_text,
    significant,
)
from urdftool.model import Joint, KinematicTree, Link, Pose, Robot
from urdftool.records import record

FONT = "Helvetica"
_LINK_FILL = "#f7f7f7"
_FINDING_FILL = {"error": "#fde0dd", "warning": "#fff2cc"}
_MEMBERS_PER_LINE = 3
Attributes = dict[str, "str | float | bool"]


@record
class GraphSettings:
    """How to draw: ``rankdir`` TB|LR|BT|RL, fixed chains merged or not."""

    rankdir: str = "TB"
    collapse_fixed: bool = False


class _Ids:
    """Unique node ids: ``link:NAME``; a repeated name gets ``#2``, ``#3``."""

    def __init__(self) -> None:
        self._used: set[str] = set()

    def new(self, kind: str, name: str) -> str:
        base = f"{kind}:{name}"
        node_id, count = base, 1
        while node_id in self._used:
            count += 1
            node_id = f"{base}#{count}"
        self._used.add(node_id)
        return node_id


class TreeDiagram:
    """Builds the DOT text for one robot; see :func:`build_dot`."""

    def __init__(self, robot: Robot, settings: GraphSettings, findings: Findings) -> None:
        self.robot = robot
        self.settings = settings
        self.findings = findings
        self.tree = KinematicTree.of(robot)
        self.groups = LinkGroups.of(self.tree, settings.collapse_fixed)
        self.ids = _Ids()
        self.link_node: dict[str, str] = {}
        self.out = DotWriter(robot.name or "robot")

    def text(self) -> str:
        self._header()
        self._links()
        self.out.blank()
        tree_joints = self.tree.joints_in_order
        in_tree = {id(joint) for joint in tree_joints}
        for joint in tree_joints:
            if not self.groups.is_merged(joint):
                self._joint(joint, joint.origin, in_tree=True)
        closures = {closure.joint.name for closure in self.robot.loop_closures}
        for joint in self.robot.joints:
            if id(joint) not in in_tree and joint.name not in closures:
                self._joint(joint, joint.origin, in_tree=False)
        for closure in self.robot.loop_closures:
            self._joint(closure.joint, closure.parent_anchor, in_tree=False, note="loop closure")
        return self.out.text()

    # -- header -------------------------------------------------------------

    def _header(self) -> None:
        self.out.comment("kinematic tree drawn by urdftool (urdftool graph)")
        self.out.defaults(
            "graph",
            {
                "rankdir": self.settings.rankdir,
                "label": self._title(),
                "labelloc": "t",
                "fontname": FONT,
                "fontsize": 9,
                "nodesep": 0.2,
                "ranksep": 0.3,
            },
        )
        self.out.defaults("node", {"fontname": FONT, "fontsize": 11, "margin": "0.08,0.03"})
        self.out.defaults(
            "edge", {"fontname": FONT, "fontsize": 8, "arrowsize": 0.6, "color": "#606060"}
        )
        self.out.blank()

    def _title(self) -> Html:
        """Name, DOF, mass and counts, the joint-type colours used, and robot-wide findings."""
        robot = self.robot
        facts = [
            f"{self.tree.dof} DOF",
            f"{significant(robot.total_mass)} kg",
            _count(len(robot.links), "link"),
            _count(len(robot.joints), "joint"),
        ]
        if robot.loop_closures:
            facts.append(_count(len(robot.loop_closures), "loop closure"))
        lines = [
            f'<FONT POINT-SIZE="14"><B>{html_text(robot.name or "(unnamed robot)")}</B></FONT>',
            f'<FONT POINT-SIZE="10">{html_text(" · ".join(facts))}</FONT>',
        ]
        lines += [
            f'<FONT COLOR="{colour}">robot {html_text(note)}</FONT>'
            for colour, note in code_notes(self.findings.other)
        ]
        used = sorted(
            {j.type for j in (*robot.joints, *(c.joint for c in robot.loop_closures))},
            key=lambda t: t.value,
        )
        # An HTML label is text or one table; the legend needs the table, so the
        # text rows span all the legend's columns (one per joint type, stretched
        # by Graphviz to the title's width: a colour bar).
        span = max(1, len(used))
        rows = [f'<TR><TD COLSPAN="{span}">{line}</TD></TR>' for line in lines]
        if used:
            cells = "".join(f'<TD BGCOLOR="{JOINT_COLOURS[t]}">{t.value}</TD>' for t in used)
            rows.insert(2, f"<TR>{cells}</TR>")
        body = "".join(rows)
        return Html(f'<TABLE BORDER="0" CELLSPACING="2" CELLPADDING="1">{body}</TABLE>')

    # -- links --------------------------------------------------------------

    def _links(self) -> None:
        for name in self.tree.order:
            if self.groups.top.get(name) == name:
                self._group_node(name)
        # Links the tree could not place: a repeated name draws a box of its own.
        first: set[str] = set()
        for link in self.robot.links:
            if link.name in first:
                self._link_node([link], self.ids.new("link", link.name), found=[])
                continue
            first.add(link.name)
            if link.name not in self.link_node:
                self._group_node(link.name)

    def _group_node(self, top: str) -> None:
        names = self.groups.members.get(top, [top])
        node_id = self.ids.new("link", top)
        for name in names:
            self.link_node[name] = node_id
        links = [link for link in map(self.robot.link, names) if link is not None]
        self._link_node(links, node_id, self.findings.for_links(names))

    def _link_node(self, links: Sequence[Link], node_id: str, found: Sequence[Diagnostic]) -> None:
        """One box: the first link's name, the group's mass, the merged links, the findings."""
        masses = [link.inertial.mass for link in links if link.inertial is not None]
        lines = [mass_text(sum(masses) if masses else None)]
        merged = [link.name for link in links[1:]]
        for start in range(0, len(merged), _MEMBERS_PER_LINE):
            chunk = ", ".join(merged[start : start + _MEMBERS_PER_LINE])
            more = "," if start + _MEMBERS_PER_LINE < len(merged) else ""
            lines.append(("+ " if start == 0 else "") + chunk + more)
        attributes: Attributes = {
            "shape": "box",
            "style": "rounded,filled",
            "fillcolor": _LINK_FILL,
        }
        attributes.update(_finding_style(found))
        attributes["label"] = html_label(links[0].name, lines, code_notes(found))
        self.out.node(node_id, attributes)

    def _node_for_link(self, name: str) -> str:
        """The node drawing link *name*; a dashed placeholder when no such link exists."""
        if name not in self.link_node:
            node_id = self.ids.new("missing", name)
            self.link_node[name] = node_id
            self.out.node(
                node_id,
                {
                    "shape": "box",
                    "style": "dashed",
                    "color": SEVERITY_COLOURS[Severity.ERROR],
                    "label": html_label(name, ["no such link"]),
                },
            )
        return self.link_node[name]

    # -- joints -------------------------------------------------------------

    def _joint(self, joint: Joint, origin: Pose, in_tree: bool, note: str | None = None) -> None:
        found = self.findings.for_joint(joint.name)
        lines = joint_lines(joint) + ([note] if note else [])
        style = "filled" if in_tree else "filled,dashed"
        attributes: Attributes = {
            "shape": "ellipse",
            "style": style,
            "fillcolor": JOINT_COLOURS[joint.type],
        }
        attributes.update(_finding_style(found, keep_fill=True))
        attributes["label"] = html_label(joint.name, lines, code_notes(found))
        joint_id = self.ids.new("joint", joint.name)
        parent = self._node_for_link(joint.parent)
        child = self._node_for_link(joint.child)
        self.out.node(joint_id, attributes)
        to_joint: Attributes = {}
        label = origin_text(self.groups.in_top_frame(joint.parent, origin))
        if label:
            to_joint["label"] = label
        to_child: Attributes = {}
        if not in_tree:
            # Off-tree joints must not pull the tree's layout out of shape.
            to_joint.update(style="dashed")
            to_child.update(style="dashed", constraint=False)
        self.out.edge(parent, joint_id, to_joint)
        self.out.edge(joint_id, child, to_child)


def _count(number: int, noun: str) -> str:
    return f"{number} {noun}" + ("" if number == 1 else "s")


def _finding_style(found: Sequence[Diagnostic], keep_fill: bool = False) -> Attributes:
    """Border (and for links, fill) in the colour of the worst finding, with a tooltip."""
    severity = worst(found)
    if severity is None:
        return {}
    style: Attributes = {"color": SEVERITY_COLOURS[severity], "penwidth": 2.0}
    if not keep_fill:
        style["fillcolor"] = _FINDING_FILL[severity.value]
    style["tooltip"] = tooltip(found)
    return style


def build_dot(
    robot: Robot, settings: GraphSettings | None = None, diagnostics: Sequence[Diagnostic] = ()
) -> str:
    """DOT text of *robot*'s kinematic tree, with *diagnostics* marked on their links and joints."""
    settings = settings or GraphSettings()
    return TreeDiagram(robot, settings, Findings.of(robot, diagnostics)).text()
