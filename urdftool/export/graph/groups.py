"""Which link node draws which links: one each, or fixed-joint chains merged.

With ``collapse_fixed``, a link hanging from its parent by a fixed joint is drawn
inside its parent's node, as MuJoCo and Pinocchio fuse such bodies. The group is
named after its top link; joints leaving the group start from that node, and
their origins are composed through the fixed joints so that they stay true in
the top link's frame.
"""

from __future__ import annotations

from dataclasses import field

from urdftool.model import IDENTITY, Joint, JointType, KinematicTree, Pose
from urdftool.records import record


@record(frozen=False)
class LinkGroups:
    """Link name -> the top link of its group, and each top link's members in tree order."""

    top: dict[str, str] = field(default_factory=dict)
    members: dict[str, list[str]] = field(default_factory=dict)
    #: each member's frame in its top link's frame
    offset: dict[str, Pose] = field(default_factory=dict)
    #: ``id()`` of the fixed joints drawn inside a group rather than as nodes
    #: (by identity: a repeated joint name must not hide another joint)
    merged_joints: set[int] = field(default_factory=set)

    @classmethod
    def of(cls, tree: KinematicTree, collapse_fixed: bool) -> LinkGroups:
        groups = cls()
        for _, link, joint in tree.walk():
            merge = collapse_fixed and joint is not None and joint.type is JointType.FIXED
            if merge:
                assert joint is not None
                top = groups.top[joint.parent]
                groups.offset[link.name] = groups.offset[joint.parent].compose(joint.origin)
                groups.merged_joints.add(id(joint))
            else:
                top = link.name
                groups.offset[link.name] = IDENTITY
            groups.top[link.name] = top
            groups.members.setdefault(top, []).append(link.name)
        return groups

    def is_merged(self, joint: Joint) -> bool:
        return id(joint) in self.merged_joints

    def in_top_frame(self, link: str, pose: Pose) -> Pose:
        """*pose*, given in *link*'s frame, expressed in the frame of *link*'s group top link."""
        offset = self.offset.get(link, IDENTITY)
        return pose if offset.is_identity else offset.compose(pose)
