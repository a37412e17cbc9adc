"""How deep a joint's child link sinks into its parent over the joint's range (the N305 sweep).

For every limited revolute joint whose child and parent both carry collision
geometry, the joint is swept from its lower to its upper limit (every other
joint at home, see :func:`urdftool.facts.collisions.home_configuration`; mimic
followers follow) and the deepest penetration between the child's rigid body
and the parent's is recorded at each sampled position (:func:`range_sweeps`),
with the geometry of :mod:`urdftool.facts.collisions`: primitives as they
are, meshes as their convex hulls (so a mesh's depth is an upper bound),
links welded by fixed joints counted with the link they are welded to.

The share of the child's collision volume inside the parent's
(:func:`share_at`) costs more and is computed only at the angles a rule asks
about; there meshes are their own closed triangle meshes
(:mod:`urdftool.backends.collision_volume`), because a hull fills the clevis
the next link turns in; a parent whose collision is a single mesh that is
itself convex is such a hull, and its share is left unknown.

This module only measures; judging when a depth means "passes through the
parent" is the rule's job (``urdftool.rules.intent_sweep``). Prismatic joints
are not swept: a telescoping stage lies inside its parent over its whole
travel by design. Mimic followers are not swept on their own (they only move
with their leader) and closed chains not at all (their home is not the tree's).

Cost: one distance query per sampled position and geometry pair. The samples
of all joints together are kept under :data:`BUDGET` pair queries by widening
the step; models with more than
:data:`~urdftool.facts.collisions.MAX_GEOMETRIES` collision geometries are not
swept (``self-collision-not-checked`` says so).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
else:
    from urdftool.lazy import numpy as np

from urdftool.backends.collision import CollisionScene
from urdftool.backends.collision_volume import Solid, solid
from urdftool.facts.collisions import (
    NotChecked,
    apply_mimics,
    home_configuration,
    mimic_followers,
    scene_of,
)
from urdftool.facts.context import CheckContext
from urdftool.model import Joint, JointType
from urdftool.records import record

#: Default sampling step (rad): two degrees.
STEP = math.radians(2.0)
#: Points filling a child link's collision geometry (about: the grid is clipped to the shapes).
POINTS = 400
#: Pair distance queries one model may cost (about a second of coal's GJK/EPA); the step widens to fit.
BUDGET = 200_000


@record
class Sweep:
    """One revolute joint swept over its limits.

    ``angles`` (rad) run from the lower to the upper limit; ``depths`` (m) is
    the deepest penetration between the child's and the parent's collision
    geometry at each (convex hulls for meshes; 0 when apart). ``home`` is the
    joint's position at the home configuration and ``home_depth`` the
    penetration there: the overlap the joint region always has.
    """

    joint: str
    parent: str
    child: str
    lower: float
    upper: float
    home: float
    home_depth: float
    angles: tuple[float, ...]
    depths: tuple[float, ...]
    step: float
    #: the child and the parent are primitives only: the depths are exact, not those of convex
    #: hulls (an upper bound of a mesh's)
    exact: bool


def range_sweeps(ctx: CheckContext, step: float = STEP,
                 budget: int = BUDGET) -> list[Sweep] | NotChecked | None:
    """Every sweepable joint's depth profile, why none was made, or ``None`` (nothing to sweep)."""
    key = ("range-sweeps", step, budget)
    if key in ctx.cache:
        return ctx.cache[key]  # type: ignore[no-any-return]
    scene = scene_of(ctx) if not ctx.robot.loop_closures else None
    result: list[Sweep] | NotChecked | None = scene if not isinstance(scene, CollisionScene) else None
    if isinstance(scene, CollisionScene):
        result = _sweeps(ctx, scene, step, budget)
    ctx.cache[key] = result
    return result


def share_at(ctx: CheckContext, sweep: Sweep, angle: float) -> float | None:
    """The share (0..1) of the child's collision volume inside the parent's with the joint of
    *sweep* at *angle* (rad): the share of points filling the child's geometries (about
    :data:`POINTS`, on a regular grid) that lie inside a geometry of the parent. Meshes count as
    their own triangles; ``None`` when a mesh of either link does not close a volume, or when the
    parent's collision is one convex mesh (an envelope, see :mod:`urdftool.backends.collision_volume`)."""
    key = ("range-sweep-share", sweep.joint, angle)
    if key not in ctx.cache:
        scene, joint, pairs = _placed(ctx, sweep, angle)
        if scene is None or joint is None:
            return None
        volume_key = ("range-sweep-volume", sweep.joint)
        if volume_key not in ctx.cache:
            ctx.cache[volume_key] = _Volume(scene, pairs)
        ctx.cache[key] = ctx.cache[volume_key].share()
    found: float | None = ctx.cache[key]
    return found


def _placed(ctx: CheckContext, sweep: Sweep, angle: float
            ) -> tuple[CollisionScene | None, Joint | None, list[tuple[int, int]]]:
    """The scene checking *sweep*'s pairs, placed with its joint at *angle* (rad)."""
    scene = scene_of(ctx)
    joint = ctx.robot.joint(sweep.joint)
    if not isinstance(scene, CollisionScene) or joint is None:
        return None, None, []
    pairs = _pairs(scene, joint)
    if scene.pairs != pairs:
        scene.use_pairs(pairs)
    scene.distances(_poser(ctx, scene, joint)(angle))
    return scene, joint, pairs


def sweepable(joint: Joint) -> bool:
    limit = joint.limit
    return (joint.type is JointType.REVOLUTE and joint.mimic is None and limit is not None
            and limit.lower is not None and limit.upper is not None
            and math.isfinite(limit.lower) and math.isfinite(limit.upper) and limit.lower < limit.upper)


def _body(scene: CollisionScene, link: str) -> int | None:
    frame = scene.pin.link_frames.get(link)
    return None if frame is None else int(scene.pin.model.frames[frame].parentJoint)


def _pairs(scene: CollisionScene, joint: Joint) -> list[tuple[int, int]]:
    """(child piece, parent piece) index pairs of *joint*: the pieces of the two rigid bodies."""
    child, parent = _body(scene, joint.child), _body(scene, joint.parent)
    if child is None or parent is None or child == parent:
        return []
    mine = [k for k, p in enumerate(scene.pieces) if p.body == child]
    theirs = [k for k, p in enumerate(scene.pieces) if p.body == parent]
    return [(i, j) for i in mine for j in theirs]


def _poser(
    ctx: CheckContext, scene: CollisionScene, joint: Joint, home: Any = None
) -> Callable[[float], Any]:
    """The configurations of a sweep of *joint*: the home configuration (*home*, when already
    computed) with *joint* at an angle (rad) and its mimic followers after it. The joint's place in
    the configuration and the followers are looked up once for all the sweep's samples."""
    start = home if home is not None else home_configuration(ctx, scene)
    index = scene.pin.idx_q(joint.name)
    followers = mimic_followers(ctx.robot, scene)

    def at(angle: float) -> Any:
        q = start.copy()
        q[index] = angle
        apply_mimics(ctx.robot, scene, q, followers)
        return q

    return at


def _sweeps(ctx: CheckContext, scene: CollisionScene, step: float, budget: int) -> list[Sweep]:
    todo: list[tuple[Joint, list[tuple[int, int]]]] = []
    for joint in ctx.robot.joints:
        if sweepable(joint) and joint.name in scene.pin.joints:
            pairs = _pairs(scene, joint)
            if pairs:
                todo.append((joint, pairs))
    cost = sum(len(pairs) * _samples(joint, step) for joint, pairs in todo)
    if cost > budget:
        step *= cost / budget
    home = home_configuration(ctx, scene)
    out = []
    for joint, pairs in todo:
        assert joint.limit is not None and joint.limit.lower is not None and joint.limit.upper is not None
        lower, upper = float(joint.limit.lower), float(joint.limit.upper)
        n = _samples(joint, step)
        angles = [lower + (upper - lower) * k / (n - 1) for k in range(n)]
        scene.use_pairs(pairs)
        home_depth = _depth(scene, home)
        at = _poser(ctx, scene, joint, home)
        depths = [_depth(scene, at(angle)) for angle in angles]
        exact = not any(k in scene.meshes for pair in pairs for k in pair)
        out.append(Sweep(joint.name, joint.parent, joint.child, lower, upper,
                         float(home[scene.pin.idx_q(joint.name)]), home_depth,
                         tuple(angles), tuple(depths), (upper - lower) / (n - 1), exact))
    return out


class _Volume:
    """The child's collision volume as points, and the share of them inside the parent's geometry.

    ``solids`` is ``None`` when a mesh of either link does not close a volume, or when the parent's
    collision is a single mesh that is its own convex hull (an envelope): the share is then
    unknown."""

    def __init__(self, scene: CollisionScene, pairs: list[tuple[int, int]]) -> None:
        self.scene = scene
        self.mine = sorted({i for i, _ in pairs})
        self.theirs = sorted({j for _, j in pairs})
        found = {k: solid(scene, k) for k in [*self.mine, *self.theirs]}
        closed = {k: v for k, v in found.items() if v is not None}
        # a parent that is one convex mesh is an envelope (a hull of the part, notches filled):
        # the child turning into the notch would count as inside it, so the share is unknown
        envelope = len(self.theirs) == 1 and self.theirs[0] in closed and closed[self.theirs[0]].envelope
        self.solids: dict[int, Solid] | None = closed if len(closed) == len(found) and not envelope else None
        self.points: dict[int, Any] = {}
        if self.solids is not None:
            volume = sum(self.solids[i].box_volume for i in self.mine)
            spacing = (volume / POINTS) ** (1 / 3) if volume > 0 else 1e-3
            self.points = {i: self.solids[i].fill(spacing) for i in self.mine}
        self.total = sum(len(p) for p in self.points.values())

    def share(self) -> float | None:
        """Share of the child's points inside any parent geometry, at the scene's last placements."""
        if self.solids is None or not self.total:
            return None
        count = 0
        for i in self.mine:
            rotation, position = self.scene.placement(i)
            world = self.points[i] @ rotation.T + position
            hit = np.zeros(len(world), dtype=bool)
            for j in self.theirs:
                rot, pos = self.scene.placement(j)
                hit |= self.solids[j].contains((world - pos) @ rot)
            count += int(hit.sum())
        return count / self.total


def _samples(joint: Joint, step: float) -> int:
    assert joint.limit is not None and joint.limit.lower is not None and joint.limit.upper is not None
    return max(2, math.ceil((joint.limit.upper - joint.limit.lower) / step) + 1)


def _depth(scene: CollisionScene, q: Any) -> float:
    """The deepest penetration (m) among the scene's pairs at *q*, which also places the pieces there."""
    return max(0.0, *(-d for d in scene.distances(q)))
