"""The body tree: one body per link, joints by type, inertials, sites for loop closures.

Joint types map as follows (the child body's frame is the URDF joint frame,
so every joint sits at the body origin with its axis in the body frame):

=============  ==========================================================
revolute       hinge with ``range`` (when lower < upper)
continuous     hinge without range
prismatic      slide with ``range``
floating       free joint (only on a body directly under the world)
planar         slides ``NAME_x``, ``NAME_y`` along two in-plane directions,
               then hinge ``NAME_rot`` about the plane normal
spherical      ball
fixed          no joint: the child is a body welded to its parent
=============  ==========================================================
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import field

import numpy as np
from lxml import etree

from urdftool.catalogue.conversion import ConversionDropped
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.export.mjcf_format import pose_attributes
from urdftool.export.mjcf_geoms import GeomWriter
from urdftool.export.numbers import num, vec
from urdftool.model import Inertial, Joint, JointType, KinematicTree, Link, Robot
from urdftool.model.pose import planar_directions
from urdftool.physics.mobility import BasePlan
from urdftool.records import record

#: The motion types of MJCF joints and the qpos each takes.
QPOS_SIZE = {"free": 7, "ball": 4, "hinge": 1, "slide": 1}


@record
class MjJoint:
    """One MJCF joint: its name, kind, the source joint it carries, and its home qpos."""

    name: str
    kind: str
    source: str
    home: tuple[float, ...]
    range: tuple[float, float] | None = None


@record(frozen=False)
class BodyTree:
    """What writing the bodies produced, for the actuators, equality and keyframe."""

    joints: list[MjJoint] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)


def unit_axis(joint: Joint) -> tuple[float, float, float]:
    """The joint axis normalised; x when it is zero (as the tree view does)."""
    axis = np.asarray(joint.axis, dtype=float)
    norm = float(np.linalg.norm(axis))
    if norm == 0.0:
        return (1.0, 0.0, 0.0)
    return (float(axis[0] / norm), float(axis[1] / norm), float(axis[2] / norm))


def joint_range(joint: Joint) -> tuple[float, float] | None:
    """(lower, upper) of a revolute or prismatic joint, when written and lower < upper."""
    if joint.type not in (JointType.REVOLUTE, JointType.PRISMATIC) or joint.limit is None:
        return None
    lower, upper = joint.limit.lower, joint.limit.upper
    if lower is None or upper is None or not lower < upper:
        return None
    return (lower, upper)


def clamp(value: float, bounds: tuple[float, float] | None) -> float:
    if bounds is None:
        return value
    return min(max(value, bounds[0]), bounds[1])


def inertial_attributes(inertial: Inertial) -> dict[str, str]:
    """``<inertial>`` in the body frame: diaginertia + quat when the tensor is written
    diagonal, else fullinertia rotated into the body frame."""
    attrs = {"pos": vec(inertial.origin.xyz), "mass": num(inertial.mass)}
    tensor = inertial.inertia_matrix
    if not np.any(tensor - np.diag(np.diag(tensor))):
        attrs.update({k: v for k, v in pose_attributes(inertial.origin).items() if k == "quat"})
        attrs["diaginertia"] = vec(np.diag(tensor))
    else:
        t = inertial.inertia_in_link_frame if any(inertial.origin.rpy) else tensor
        attrs["fullinertia"] = vec((t[0, 0], t[1, 1], t[2, 2], t[0, 1], t[0, 2], t[1, 2]))
    return attrs


class BodyWriter:
    """Writes ``<body>`` elements for the robot's tree under ``<worldbody>``."""

    def __init__(self, robot: Robot, tree: KinematicTree, base: BasePlan,
                 inertials: Mapping[str, Inertial | None], geoms: GeomWriter,
                 sites: Mapping[str, list[dict[str, str]]]):
        self.robot = robot
        self.tree = tree
        self.base = base
        self.inertials = inertials
        self.geoms = geoms
        self.sites = sites
        self.home = dict(robot.home or {})
        self.result = BodyTree(diagnostics=geoms.diagnostics)

    def write(self, worldbody: etree._Element) -> BodyTree:
        root = self.tree.root
        if root is None:
            return self.result
        links = {link.name: link for link in self.robot.links}
        if self.base.kind == "world":
            self._fill(worldbody, links[root], moving=False)
            self._bodies(worldbody, links, root, top_level=True)
            return self.result
        body = etree.SubElement(worldbody, "body", {"name": root})
        if self.base.kind == "free":
            assert self.base.free_joint is not None
            etree.SubElement(body, "freejoint", {"name": self.base.free_joint})
            self.result.joints.append(MjJoint(self.base.free_joint, "free", "", (0, 0, 0, 1, 0, 0, 0)))
        self._fill(body, links[root], moving=self.base.kind == "free")
        self._bodies(body, links, root, top_level=False)
        self._free_bodies(worldbody, links, root)
        return self.result

    def _free_bodies(self, worldbody: etree._Element, links: Mapping[str, Link], root: str) -> None:
        """SDF's free bodies (the model's other roots): each a body with a free joint, placed where
        the model puts it relative to the first root."""
        poses = self.robot.root_poses or {}
        if root not in poses:
            return
        to_root = poses[root].inverse()
        taken = {j.name for j in self.robot.joints} | {j.name for j in self.result.joints}
        for other in self.tree.roots[1:]:
            if other not in poses:
                continue
            placed = to_root.compose(poses[other])
            body = etree.SubElement(worldbody, "body", {"name": other, **pose_attributes(placed)})
            name = f"{other}_free"
            while name in taken:
                name += "_"
            taken.add(name)
            etree.SubElement(body, "freejoint", {"name": name})
            self.result.joints.append(MjJoint(name, "free", "", (*placed.xyz, *placed.quaternion)))
            self._fill(body, links[other], moving=True)
            self._bodies(body, links, other, top_level=False)

    def _bodies(self, parent: etree._Element, links: Mapping[str, Link], root: str, top_level: bool) -> None:
        """The bodies below *root*, depth first in file order, without recursion (chains can be deep)."""
        stack = [(parent, joint, top_level) for joint in reversed(self.tree.child_joints.get(root, []))]
        while stack:
            into, joint, top = stack.pop()
            link = links[joint.child]
            body = etree.SubElement(into, "body", {"name": link.name, **pose_attributes(joint.origin)})
            self._joint(body, joint, top)
            self._fill(body, link, moving=joint.type.is_moving)
            below = self.tree.child_joints.get(link.name, [])
            stack.extend((body, child, False) for child in reversed(below))

    def _fill(self, body: etree._Element, link: Link, moving: bool) -> None:
        inertial = self.inertials.get(link.name)
        if inertial is not None and body.tag == "body":
            etree.SubElement(body, "inertial", inertial_attributes(inertial))
        elif inertial is not None:
            self._drop(link, f"link[{link.name}]/inertial", "the world body carries no mass")
        self.geoms.write(body, link, moving)
        for site in self.sites.get(link.name, []):
            etree.SubElement(body, "site", site)

    def _joint(self, body: etree._Element, joint: Joint, top_level: bool) -> None:
        kind = joint.type
        if kind is JointType.FIXED:
            return
        if kind in (JointType.REVOLUTE, JointType.CONTINUOUS, JointType.PRISMATIC):
            self._one_dof(body, joint)
        elif kind is JointType.FLOATING:
            if top_level:
                etree.SubElement(body, "freejoint", {"name": joint.name})
                self.result.joints.append(MjJoint(joint.name, "free", joint.name,
                                                  _free_home(joint)))
            else:
                self._unsupported(joint, "a free joint below the root cannot be written in MJCF")
        elif kind is JointType.SPHERICAL:
            etree.SubElement(body, "joint", {"name": joint.name, "type": "ball", **self._dynamics(joint)})
            self.result.joints.append(MjJoint(joint.name, "ball", joint.name, (1.0, 0.0, 0.0, 0.0)))
        elif kind is JointType.PLANAR:
            self._planar(body, joint)
        elif kind in (JointType.UNIVERSAL, JointType.REVOLUTE2) and joint.axis2 is not None:
            self._two_hinges(body, joint)
        else:
            self._unsupported(joint, f"{kind.value} joints are not exported")

    def _one_dof(self, body: etree._Element, joint: Joint) -> None:
        mj_kind = "slide" if joint.type is JointType.PRISMATIC else "hinge"
        attrs = {"name": joint.name, "type": mj_kind, "axis": vec(unit_axis(joint))}
        bounds = joint_range(joint)
        if bounds is not None:
            attrs["range"] = vec(bounds)
        attrs.update(self._dynamics(joint))
        effort = joint.limit.effort if joint.limit else None
        if effort is not None and 0 < effort < math.inf:
            attrs["actuatorfrcrange"] = vec((-effort, effort))
        etree.SubElement(body, "joint", attrs)
        home = clamp(self.home.get(joint.name, 0.0), bounds)
        if joint.mimic is not None:
            home = 0.0  # followers take their value from the leader in the keyframe
        self.result.joints.append(MjJoint(joint.name, mj_kind, joint.name, (home,), bounds))

    def _two_hinges(self, body: etree._Element, joint: Joint) -> None:
        """A universal (or revolute2) joint as two hinges in one body: MuJoCo turns the second
        hinge's axis with the first, as the joint's second axis turns with the child."""
        assert joint.axis2 is not None
        for suffix, axis, limit in (("1", joint.axis, joint.limit), ("2", joint.axis2, joint.limit2)):
            name = f"{joint.name}_{suffix}"
            single = Joint(name, JointType.REVOLUTE, joint.parent, joint.child, axis=axis, limit=limit)
            bounds = joint_range(single)
            attrs = {"name": name, "type": "hinge", "axis": vec(unit_axis(single)), **self._dynamics(joint)}
            if bounds is not None:
                attrs["range"] = vec(bounds)
            etree.SubElement(body, "joint", attrs)
            self.result.joints.append(MjJoint(name, "hinge", joint.name, (clamp(0.0, bounds),), bounds))
        self.result.diagnostics.append(ConversionDropped.diagnostic(
            f"joint '{joint.name}' ({joint.type.value}) is written as two hinges, "
            f"'{joint.name}_1' and '{joint.name}_2'",
            joint.span, element=f"joint[{joint.name}]", severity=Severity.INFO,
            data={"reason": "two hinges", "joints": [f"{joint.name}_1", f"{joint.name}_2"]},
        ))

    def _planar(self, body: etree._Element, joint: Joint) -> None:
        axis = unit_axis(joint)
        e1, e2 = planar_directions(axis)
        dyn = self._dynamics(joint)
        for suffix, kind, direction in (
            ("x", "slide", e1),
            ("y", "slide", e2),
            ("rot", "hinge", np.array(axis)),
        ):
            name = f"{joint.name}_{suffix}"
            etree.SubElement(body, "joint", {"name": name, "type": kind, "axis": vec(direction), **dyn})
            self.result.joints.append(MjJoint(name, kind, joint.name, (0.0,)))

    @staticmethod
    def _dynamics(joint: Joint) -> dict[str, str]:
        out: dict[str, str] = {}
        if joint.dynamics is not None:
            if joint.dynamics.damping > 0:
                out["damping"] = num(joint.dynamics.damping)
            if joint.dynamics.friction > 0:
                out["frictionloss"] = num(joint.dynamics.friction)
            if joint.dynamics.spring_stiffness > 0:  # SDF's joint spring, in the same units
                out["stiffness"] = num(joint.dynamics.spring_stiffness)
                if joint.dynamics.spring_reference != 0:
                    out["springref"] = num(joint.dynamics.spring_reference)
        return out

    def _unsupported(self, joint: Joint, reason: str) -> None:
        self.result.diagnostics.append(ConversionDropped.diagnostic(
            f"joint '{joint.name}': {reason}", joint.span, element=f"joint[{joint.name}]",
            severity=Severity.ERROR, data={"element": f"joint[{joint.name}]", "reason": reason}))

    def _drop(self, link: Link, where: str, reason: str) -> None:
        span = link.inertial.span if link.inertial else link.span
        self.result.diagnostics.append(ConversionDropped.diagnostic(
            f"{where}: {reason}", span, element=where, data={"element": where, "reason": reason}))


def _free_home(joint: Joint) -> tuple[float, ...]:
    w, x, y, z = joint.origin.quaternion if any(joint.origin.rpy) else (1.0, 0.0, 0.0, 0.0)
    return (*joint.origin.xyz, w, x, y, z)
