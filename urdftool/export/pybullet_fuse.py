"""Fixed joints fused for PyBullet: each link on a fixed joint merged into the link that carries it.

PyBullet keeps every fixed-joint link as a link of its own and cannot report
the state of a body with more than :data:`~urdftool.export.pybullet.MAX_JOINTS`
joints. Fusing (``--fuse-fixed``, and automatically for such bodies) writes
each chain of fixed joints as one link, the *kept* link (the one whose parent
joint moves, or the root):

* inertia: the masses summed exactly; the centre of mass and the tensor about
  it by the parallel-axis theorem, in the kept link's frame;
* visuals and collisions re-posed into the kept link's frame;
* joints hanging from a fused link re-parented to the kept link, their origin
  composed with the fused frame's pose;
* the fused frames kept: one line per frame in a comment of the written file
  (:func:`frames_comment`, read back by :func:`read_fused_frames`), with the
  frame's pose in the kept link's frame, and named in the export's finding.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Mapping
from typing import TYPE_CHECKING
from urllib.parse import unquote

if TYPE_CHECKING:
    import numpy as np
else:
    from urdftool.lazy import numpy as np

from urdftool.export.numbers import vec
from urdftool.model import Collision, Inertial, JointType, KinematicTree, Link, Robot, Visual
from urdftool.model.pose import Matrix, Pose
from urdftool.physics.inertia import shift_to_point
from urdftool.records import record

#: First line of the comment that lists the fused frames.
FRAMES_TITLE = "urdftool fused frames"
_LINE = re.compile(r'fused "([^"]+)" into "([^"]+)" xyz="([^"]*)" rpy="([^"]*)"')


@record
class FusedFrame:
    """A link merged into *into*: its frame's pose in *into*'s frame, and the fixed joint removed."""

    link: str
    into: str
    pose: Pose
    joint: str


@record
class Fusion:
    """The robot with its fixed joints fused, and every fused frame."""

    robot: Robot
    frames: tuple[FusedFrame, ...] = ()


def fuse_fixed(robot: Robot, anchor: str | None = None) -> Fusion:
    """*robot* with every link on a fixed joint merged into its nearest non-fixed ancestor.

    Nothing is merged into *anchor*: a massless root that holds a fixed robot to the world
    (PyBullet fixes a base of mass 0) must stay massless, so its fixed children stay links.
    """
    tree = KinematicTree.of(robot)
    if tree.cycle_joints:
        return Fusion(robot)  # a closed chain is refused by the exporter; nothing to fuse
    placed: dict[str, tuple[str, Matrix]] = {}
    frames: list[FusedFrame] = []
    for _depth, link, joint in tree.walk():
        fusable = joint is not None and joint.type is JointType.FIXED and joint.parent in placed
        if fusable and joint is not None and placed[joint.parent][0] != anchor:
            kept, above = placed[joint.parent]
            transform = above @ joint.origin.matrix
            placed[link.name] = (kept, transform)
            frames.append(FusedFrame(link.name, kept, Pose.from_matrix(transform), joint.name))
        else:
            placed[link.name] = (link.name, np.eye(4))
    if not frames:
        return Fusion(robot)
    members: dict[str, list[tuple[Link, Matrix]]] = {}
    for link in robot.links:
        if link.name in placed:
            kept, transform = placed[link.name]
            members.setdefault(kept, []).append((link, transform))
    fused = {frame.link for frame in frames}
    removed = {frame.joint for frame in frames}
    links = tuple(_merged(link, members[link.name]) for link in robot.links
                  if link.name not in fused and link.name in members)
    joints = []
    for joint in robot.joints:
        if joint.name in removed and joint.child in fused:
            continue
        if joint.parent in fused:
            kept, transform = placed[joint.parent]
            joint = dataclasses.replace(joint, parent=kept,
                                        origin=Pose.from_matrix(transform @ joint.origin.matrix))
        joints.append(joint)
    return Fusion(dataclasses.replace(robot, links=links, joints=tuple(joints)), tuple(frames))


def _merged(kept: Link, members: list[tuple[Link, Matrix]]) -> Link:
    """*kept* carrying the inertia, visuals and collisions of every member (itself first)."""
    if len(members) == 1:
        return kept
    visuals: list[Visual] = []
    collisions: list[Collision] = []
    for link, transform in members:
        visuals += [dataclasses.replace(v, origin=_moved(transform, v.origin)) for v in link.visuals]
        collisions += [dataclasses.replace(c, origin=_moved(transform, c.origin)) for c in link.collisions]
    return dataclasses.replace(kept, inertial=composite_inertial(kept, members),
                               visuals=tuple(visuals), collisions=tuple(collisions))


def _moved(transform: Matrix, origin: Pose) -> Pose:
    return Pose.from_matrix(transform @ origin.matrix)


def composite_inertial(kept: Link, members: list[tuple[Link, Matrix]]) -> Inertial | None:
    """The members' inertials as one, in *kept*'s frame: masses summed, centre of mass and tensor
    by the parallel-axis theorem. *kept*'s own inertial, unchanged, when no other member has mass."""
    parts: list[tuple[float, Matrix, Matrix]] = []
    for link, transform in members:
        inertial = link.inertial
        if inertial is None or inertial.mass <= 0:
            continue
        rotation = transform[:3, :3]
        com = rotation @ np.asarray(inertial.origin.xyz, dtype=float) + transform[:3, 3]
        parts.append((inertial.mass, com, rotation @ inertial.inertia_in_link_frame @ rotation.T))
    others = [link for link, _ in members[1:] if link.inertial is not None and link.inertial.mass > 0]
    if not others:
        return kept.inertial
    mass = float(sum(m for m, _, _ in parts))
    centre = sum((m * c for m, c, _ in parts), np.zeros(3)) / mass
    tensor = sum((shift_to_point(t, m, c - centre) for m, c, t in parts), np.zeros((3, 3)))
    tensor = (tensor + tensor.T) / 2.0
    span = kept.inertial.span if kept.inertial is not None else others[0].inertial.span  # type: ignore[union-attr]
    return Inertial(
        mass=mass,
        inertia=Inertial.tensor(tensor[0, 0], tensor[0, 1], tensor[0, 2], tensor[1, 1], tensor[1, 2],
                                tensor[2, 2]),
        origin=Pose((float(centre[0]), float(centre[1]), float(centre[2]))),
        span=span,
    )


def frames_comment(frames: tuple[FusedFrame, ...]) -> str:
    """The comment text listing every fused frame (numbers exact: they parse back to the same floats)."""
    lines = [f" {FRAMES_TITLE} (pose of each frame in the frame of the link it was fused into):"]
    lines += [f'     fused "{_quoted(f.link)}" into "{_quoted(f.into)}" xyz="{vec(f.pose.xyz)}" '
              f'rpy="{vec(f.pose.rpy)}"' for f in frames]
    return "\n".join(lines) + "\n"


def _quoted(name: str) -> str:
    """*name* as a comment can hold it: no ``"``, no ``--`` (percent-encoded, read back by unquote)."""
    return name.replace("%", "%25").replace('"', "%22").replace("--", "-%2D")


def read_fused_frames(text: str) -> dict[str, tuple[str, Pose]]:
    """Fused link -> (link it was fused into, its pose there), from a written file's comment."""
    out: dict[str, tuple[str, Pose]] = {}
    start = text.find(FRAMES_TITLE)
    if start < 0:
        return out
    end = text.find("-->", start)
    for match in _LINE.finditer(text[start:end if end >= 0 else None]):
        xyz = tuple(float(v) for v in match.group(3).split())
        rpy = tuple(float(v) for v in match.group(4).split())
        out[unquote(match.group(1))] = (unquote(match.group(2)), Pose(xyz, rpy))  # type: ignore[arg-type]
    return out


def frame_matrices(frames: Mapping[str, tuple[str, Pose]]) -> dict[str, tuple[str, Matrix]]:
    """:func:`read_fused_frames` with each pose as a 4×4 transform."""
    return {name: (into, pose.matrix) for name, (into, pose) in frames.items()}
