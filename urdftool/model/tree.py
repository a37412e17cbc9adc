"""The kinematic tree view of a robot: roots, parents, children, order, DOF, FK.

Built defensively: it never assumes the joint graph is a tree. A link with two
parent joints keeps the first one written; joints that would close a cycle are
left out of the tree (and listed in :attr:`KinematicTree.cycle_joints`), so every
traversal terminates, even on self-loops.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from dataclasses import field
from functools import cached_property

from urdftool.model.pose import Matrix, axis_angle_matrix, homogeneous, quaternion_to_matrix, vector_norm
from urdftool.model.robot import Joint, JointType, Link, Robot
from urdftool.records import record


class _Forest:
    """Disjoint sets of links, each set one tree, remembering the tree's top link.

    Union by size with path halving: building a tree of n joints takes near-linear
    time, where walking to the root for every joint took quadratic time on chains.
    """

    def __init__(self) -> None:
        self._up: dict[str, str] = {}
        self._size: dict[str, int] = {}
        self._top: dict[str, str] = {}

    def _find(self, link: str) -> str:
        up = self._up
        if link not in up:
            up[link] = link
            self._size[link] = 1
            self._top[link] = link
            return link
        while up[link] != link:
            up[link] = up[up[link]]
            link = up[link]
        return link

    def attach(self, child: str, parent: str) -> bool:
        """Hang the tree whose top is *child* below *parent*; false, leaving the trees as they
        are, when *parent* hangs somewhere below *child* (the joint would close a cycle)."""
        a = self._find(parent)
        top = self._top[a]
        if top == child:
            return False
        b = self._find(child)
        if a == b:
            return True
        if self._size[a] < self._size[b]:
            a, b = b, a
        self._up[b] = a
        self._size[a] += self._size[b]
        self._top[a] = top
        return True


@record(frozen=False)
class KinematicTree:
    """Parent/child maps over link and joint names."""

    robot: Robot
    #: child link -> the joint that carries it (first one written wins)
    parent_joint: dict[str, Joint] = field(default_factory=dict)
    #: parent link -> joints hanging from it, in file order
    child_joints: dict[str, list[Joint]] = field(default_factory=dict)
    #: joints left out of the tree: a second parent, a self-loop, or closing a cycle
    cycle_joints: list[Joint] = field(default_factory=list)

    @classmethod
    def of(cls, robot: Robot) -> KinematicTree:
        tree = cls(robot)
        link_names = {link.name for link in robot.links}
        forest = _Forest()
        for joint in robot.joints:
            if joint.parent not in link_names or joint.child not in link_names:
                continue
            if joint.parent == joint.child or joint.child in tree.parent_joint:
                tree.cycle_joints.append(joint)
                continue
            # The child has no parent yet, so it is the top of its own tree: the joint
            # closes a cycle exactly when the parent hangs somewhere below the child.
            if not forest.attach(joint.child, joint.parent):
                tree.cycle_joints.append(joint)
                continue
            tree.parent_joint[joint.child] = joint
            tree.child_joints.setdefault(joint.parent, []).append(joint)
        return tree

    def _is_ancestor(self, candidate: str, link: str) -> bool:
        """True when *candidate* is *link* or lies on its path to a root (constant time)."""
        if candidate == link:
            return True
        spans = self._subtree_spans
        inside, outer = spans.get(link), spans.get(candidate)
        if inside is None or outer is None:
            return False
        return outer[0] <= inside[0] < outer[1]

    def lineal(self, a: str, b: str) -> bool:
        """True when one of the links *a*, *b* lies on the other's path to the root (or they
        are the same link): a serial chain, never two sides of a robot."""
        return self._is_ancestor(a, b) or self._is_ancestor(b, a)

    @cached_property
    def _subtree_spans(self) -> dict[str, tuple[int, int]]:
        """link -> (its depth-first index, one past its last descendant's index)."""
        spans: dict[str, tuple[int, int]] = {}
        open_links: list[tuple[str, int]] = []
        count = 0
        for index, (depth, link, _) in enumerate(self.walk()):
            count = index + 1
            while open_links and open_links[-1][1] >= depth:
                name, _ = open_links.pop()
                spans[name] = (spans[name][0], index)
            spans[link.name] = (index, index + 1)
            open_links.append((link.name, depth))
        for name, _ in open_links:
            spans[name] = (spans[name][0], count)
        return spans

    @cached_property
    def roots(self) -> list[str]:
        """Links with no parent joint, in file order."""
        return [link.name for link in self.robot.links if link.name not in self.parent_joint]

    @property
    def root(self) -> str | None:
        roots = self.roots
        return roots[0] if roots else None

    def children(self, link: str) -> list[str]:
        return [joint.child for joint in self.child_joints.get(link, [])]

    def parent(self, link: str) -> str | None:
        joint = self.parent_joint.get(link)
        return joint.parent if joint else None

    def walk(self, start: str | None = None) -> Iterator[tuple[int, Link, Joint | None]]:
        """Depth-first ``(depth, link, joint from parent)`` from each root, in file order."""
        starts = [start] if start is not None else self.roots
        links = {link.name: link for link in self.robot.links}
        seen: set[str] = set()
        for root in starts:
            stack: list[tuple[int, str]] = [(0, root)]
            while stack:
                depth, name = stack.pop()
                if name in seen or name not in links:
                    continue
                seen.add(name)
                yield depth, links[name], (self.parent_joint.get(name) if depth else None)
                for joint in reversed(self.child_joints.get(name, [])):
                    stack.append((depth + 1, joint.child))

    @cached_property
    def order(self) -> list[str]:
        """Links in depth-first order from the roots."""
        return [link.name for _, link, _ in self.walk()]

    @cached_property
    def joints_in_order(self) -> list[Joint]:
        """Tree joints, each after its parent's joint."""
        return [self.parent_joint[name] for name in self.order if name in self.parent_joint]

    @property
    def dof(self) -> int:
        """Degrees of freedom of the tree, not counting mimic joints (they follow another)."""
        return sum(j.dof for j in self.joints_in_order if j.mimic is None)

    def path_to_root(self, link: str) -> list[Joint]:
        """Joints from *link* up to its root, nearest first."""
        out: list[Joint] = []
        seen: set[str] = set()
        current = link
        while current in self.parent_joint and current not in seen:
            seen.add(current)
            joint = self.parent_joint[current]
            out.append(joint)
            current = joint.parent
        return out

    def forward_kinematics(
        self,
        q: Mapping[str, float | Sequence[float]] | None = None,
        base: Matrix | None = None,
    ) -> dict[str, Matrix]:
        """World pose (4×4) of every link frame reachable from a root.

        *q* maps joint names to positions: a float for 1-DOF joints (rad or m);
        for ``floating`` ``[x, y, z, qw, qx, qy, qz]``; for ``planar`` ``[x, y, θ]``
        in the joint frame whose normal is ``axis``; for ``spherical``
        ``[qw, qx, qy, qz]``. Missing joints sit at 0; mimic joints follow their
        target. Roots sit at *base* (identity by default).
        """
        import numpy as np

        q = dict(q or {})
        poses: dict[str, Matrix] = {}
        start = np.eye(4) if base is None else base
        for depth, link, joint in self.walk():
            if depth == 0 or joint is None:
                poses[link.name] = start
                continue
            parent_pose = poses[joint.parent]
            poses[link.name] = parent_pose @ joint.origin.matrix @ joint_motion(joint, q, self.robot)
        return poses


def mimic_value(joint: Joint, q: Mapping[str, float | Sequence[float]], robot: Robot) -> float:
    """Position of a mimic joint, following chains of mimics; a cycle falls back to q (or 0)."""
    assert joint.mimic is not None
    chain = [joint]
    seen = {joint.name}
    current = joint
    while current.mimic is not None:
        target = robot.joint(current.mimic.joint)
        if target is None or target.name in seen:
            # A missing target or a mimic cycle (both reported by the joint rules).
            return float(_scalar(q.get(joint.name, 0.0)))
        seen.add(target.name)
        chain.append(target)
        current = target
    value = float(_scalar(q.get(current.name, 0.0)))
    for follower in reversed(chain[:-1]):
        assert follower.mimic is not None
        value = follower.mimic.multiplier * value + follower.mimic.offset
    return value


def _scalar(value: float | Sequence[float]) -> float:
    return 0.0 if isinstance(value, Sequence) else float(value)


def joint_motion(joint: Joint, q: Mapping[str, float | Sequence[float]], robot: Robot) -> Matrix:
    """The 4×4 motion of *joint* at position ``q[joint.name]``, in the joint frame."""
    import numpy as np

    if joint.type is JointType.FIXED:
        return np.eye(4)
    value: float | Sequence[float]
    if joint.mimic is not None and joint.type.dof == 1:
        value = mimic_value(joint, q, robot)
    else:
        value = q.get(joint.name, 0.0)
    axis = np.asarray(joint.axis, dtype=float)
    norm = vector_norm(axis)
    unit = axis / norm if norm > 0 else np.array([1.0, 0.0, 0.0])
    if joint.type in (JointType.REVOLUTE, JointType.CONTINUOUS):
        return homogeneous(axis_angle_matrix(tuple(unit.tolist()), float(value)), (0.0, 0.0, 0.0))  # type: ignore[arg-type]
    if joint.type is JointType.PRISMATIC:
        return homogeneous(np.eye(3), unit * float(value))  # type: ignore[arg-type]
    if joint.type in (JointType.UNIVERSAL, JointType.REVOLUTE2) and joint.axis2 is not None:
        pair = isinstance(value, Sequence) and len(value) == 2
        first, second = (value[0], value[1]) if pair else (0.0, 0.0)  # type: ignore[index]
        axis2 = np.asarray(joint.axis2, dtype=float)
        axis2 = axis2 / (vector_norm(axis2) or 1.0)
        turn_first = axis_angle_matrix(tuple(unit), float(first))
        rotation = turn_first @ axis_angle_matrix(tuple(axis2), float(second))
        return homogeneous(rotation, (0.0, 0.0, 0.0))
    if joint.type is JointType.FLOATING and isinstance(value, Sequence) and len(value) == 7:
        x, y, z, qw, qx, qy, qz = (float(v) for v in value)
        return homogeneous(quaternion_to_matrix((qw, qx, qy, qz)), (x, y, z))
    if joint.type is JointType.SPHERICAL and isinstance(value, Sequence) and len(value) == 4:
        return homogeneous(quaternion_to_matrix(tuple(float(v) for v in value)), (0.0, 0.0, 0.0))  # type: ignore[arg-type]
    if joint.type is JointType.PLANAR and isinstance(value, Sequence) and len(value) == 3:
        # Planar motion in the plane normal to the axis: translate along two
        # in-plane directions, then rotate about the normal.
        helper = np.array([1.0, 0.0, 0.0]) if abs(unit[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        e1 = np.cross(unit, helper)
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(unit, e1)
        x, y, theta = (float(v) for v in value)
        return homogeneous(axis_angle_matrix(tuple(unit), theta), e1 * x + e2 * y)
    return np.eye(4)
