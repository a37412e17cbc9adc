"""Which massless URDF links the SDF export writes as ``<frame>`` instead of ``<link>``.

A URDF link without ``<inertial>`` weighs nothing; an SDF ``<link>`` without one
weighs SDFormat's default, 1 kg with 1 kg·m² about each axis, and gz-sim does not
lump fixed joints of an SDF file, so a tool flange (``iiwa_link_ee``) or a sensor
mount written as a link adds that mass to the robot. libsdformat's own URDF reader
never makes such a link: it lumps a link on a fixed joint into its parent and keeps
its name as a ``<frame>`` (SDF 1.7+; sdf_tutorials ``urdf_to_sdf/zero_mass_links``,
gazebosim/sdformat#262 and #1238). The export does the same for a massless link on a
fixed joint: a ``<frame name="LINK" attached_to="PARENT">`` with the joint's origin
``relative_to`` the parent, so every ``relative_to`` and every joint that hangs from
it still finds the name, and the numbers are URDF's. Its visuals, collisions and
``<sensor>``s move into the SDF link it is fixed to, their poses composed. A massless
root (``base_footprint``) with a fixed child that carries mass becomes a frame at the
model frame (``relative_to="__model__"``), attached to that child, which hangs from it
as before; libsdformat lumps the other way (the child into the root) and renames
nothing either, but moving the child's inertial would change URDF's numbers.

The link stays a ``<link>`` (and is reported) where a frame would break a
reference: a plugin naming it as a link to look up (``<bodyName>``, ``<link_name>``:
Gazebo finds a link by that name, never a frame), a loop closure at it, or a
``selfCollide`` for its own collisions. Settings that act on a link's mass
(``gravity``, ``turnGravityOff``, ``kinematic``, damping) act on nothing in a
massless link; they are left out of its frame, reported as info. A massless link
fixed to the world root stays a link too: it never moves, so its mass acts on nothing.
"""

from __future__ import annotations

from dataclasses import field

from lxml import etree

from urdftool.model import Inertial, Joint, JointType, KinematicTree, Link, Pose, Robot
from urdftool.records import record

#: ``<gazebo reference>`` children that act on a link's mass, which a massless link has none of:
#: left out of its frame (reported as info)
ON_MASS = frozenset({"gravity", "turnGravityOff", "kinematic", "velocity_decay", "dampingFactor"})
#: ``<gazebo reference>`` children that act on a link's collisions: a massless link that has
#: collisions and sets them stays a link (its collisions would take the carrying link's setting)
ON_COLLISIONS = frozenset({"selfCollide", "self_collide"})


def massless(inertial: Inertial | None) -> bool:
    """No ``<inertial>``, or mass 0 with an all-zero tensor."""
    return inertial is None or (
        inertial.mass == 0.0 and not any(value for row in inertial.inertia for value in row))


@record(frozen=False)
class FramePlan:
    """The links written as frames, and where everything they carried goes.

    ``body``: frame link -> the SDF link it moves with; ``in_body``: its pose (m, rad) in
    that link's frame; ``kept``: massless links on fixed joints (or massless roots) kept as
    links -> why.
    """

    body: dict[str, str] = field(default_factory=dict)
    in_body: dict[str, Pose] = field(default_factory=dict)
    kept: dict[str, str] = field(default_factory=dict)
    #: a massless root written as a frame at the model frame (``relative_to="__model__"``)
    root: str | None = None

    def link_for(self, name: str) -> str:
        """The SDF link that carries *name* (itself when it is written as a link)."""
        return self.body.get(name, name)

    def lumped(self, body: str) -> list[str]:
        """The frame links whose visuals, collisions and sensors go into link *body*."""
        return [name for name, carrier in self.body.items() if carrier == body]


#: Plugin parameters that name a link the plugin looks up in the model (lower case, no ``_``):
#: gazebo_ros_p3d's and the classic IMU's ``<bodyName>``, ``<link_name>`` of gz-sim systems. Frame
#: ids for message headers (``<frame_name>``, ``<frameName>``, ``<frame_id>``) are only strings.
LOOKUPS = frozenset({"bodyname", "linkname", "link", "body", "childlink", "parentlink"})


def _named_by_plugins(robot: Robot) -> dict[str, str]:
    """Every link name a plugin looks up (:data:`LOOKUPS`) -> that plugin's name."""
    named: dict[str, str] = {}
    elements = [e.element for e in robot.extensions]
    elements.extend(e.element for link in robot.links for e in link.extensions)
    elements.extend(e.element for joint in robot.joints for e in joint.extensions)
    for element in elements:
        if element is None:
            continue
        for plugin in element.iter("plugin"):
            for node in plugin.iter():
                if not isinstance(node.tag, str) or node.tag.lower().replace("_", "") not in LOOKUPS:
                    continue
                text = (node.text or "").strip()
                if text:
                    named.setdefault(text, plugin.get("name") or plugin.get("filename") or "plugin")
    return named


def _collision_setting(link: Link, gazebo: list[etree._Element]) -> str | None:
    if not link.collisions:
        return None
    for block in gazebo:
        for child in block:
            if isinstance(child.tag, str) and child.tag in ON_COLLISIONS:
                return child.tag
    return None


def plan_frames(robot: Robot, tree: KinematicTree, world: str | None,
                gazebo: dict[str, list[etree._Element]]) -> FramePlan:
    """The :class:`FramePlan` of *robot* (*world*: the root link that is SDF's world, if any;
    *gazebo*: the ``<gazebo reference>`` blocks of each link)."""
    plan = FramePlan()
    named = _named_by_plugins(robot)
    closing = {name for c in robot.loop_closures for name in (c.joint.parent, c.joint.child)}
    for _, link, joint in tree.walk():
        carrier = _root_carrier(robot, tree, link, world) if joint is None else None
        if not _candidate(link, joint, world) and carrier is None:
            continue
        reason = None
        if link.name in named:
            reason = f"plugin '{named[link.name]}' names it"
        elif link.name in closing:
            reason = "a loop-closing joint ends at it"
        elif (setting := _collision_setting(link, gazebo.get(link.name, []))) is not None:
            reason = f"its <gazebo> block sets <{setting}> for its collisions"
        if reason is not None:
            plan.kept[link.name] = reason
            continue
        if carrier is not None:
            # a massless root (base_footprint): a frame on the link fixed under it, at the model
            # frame, so the links keep their poses and that link its own name
            plan.body[link.name] = carrier.child
            plan.in_body[link.name] = carrier.origin.inverse()
            plan.root = link.name
            continue
        assert joint is not None  # _candidate says so
        parent = joint.parent
        plan.body[link.name] = plan.link_for(parent)
        above = plan.in_body.get(parent, Pose())
        plan.in_body[link.name] = above.compose(joint.origin)
    return plan


def _root_carrier(robot: Robot, tree: KinematicTree, link: Link, world: str | None) -> Joint | None:
    """For a massless root link that is not SDF's world, the first fixed joint to a child that
    carries mass: the child becomes the link the root's frame moves with."""
    if link.name == world or not massless(link.inertial):
        return None
    for joint in tree.child_joints.get(link.name, []):
        child = robot.link(joint.child)
        if joint.type is JointType.FIXED and child is not None and not massless(child.inertial):
            return joint
    return None


def _candidate(link: Link, joint: Joint | None, world: str | None) -> bool:
    return (joint is not None and joint.type is JointType.FIXED and joint.parent != world
            and massless(link.inertial))
