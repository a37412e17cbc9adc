"""Self-collision: which link pairs overlap at home, and MoveIt's collision matrix.

The geometry is the robot's ``<collision>`` elements placed on the Pinocchio
model (:mod:`urdftool.backends.collision`; meshes as their convex hulls). Two
questions are answered here:

* :func:`home_overlaps` (the ``self-collision-at-home`` rule): link pairs whose
  geometries overlap at the home configuration, deeper than
  :data:`DEPTH_TOLERANCE`, leaving out adjacent pairs (see :func:`adjacent`),
  links welded to each other by fixed joints, the pairs the SRDF disables and,
  in an SDF model, the pairs ``<self_collide>`` leaves off
  (:func:`urdftool.physics.sdf_defaults.sdf_self_colliding`);
* :func:`matrix` (``urdftool collisions``): every pair of links with geometry
  classified as MoveIt Setup Assistant does: ``Adjacent``, ``Default`` (in
  contact at MoveIt's default state), ``Always`` (in contact in at least
  :data:`ALWAYS_FRACTION` of the sampled configurations) or ``Never`` (in
  contact in none of them); pairs that collide sometimes stay enabled.

Models with more than :data:`MAX_GEOMETRIES` collision geometries are not
checked at home (the pair count grows as its square); the rule says so.
"""

from __future__ import annotations

import importlib.util
import math
from collections.abc import Callable
from dataclasses import field
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
else:
    from urdftool.lazy import numpy as np

from urdftool.backends.collision import CollisionScene, build_scene, count_geometries, sample_counts
from urdftool.facts.context import CheckContext
from urdftool.facts.meshes import existing_file, mesh_uses
from urdftool.facts.srdf import srdf
from urdftool.model import Joint, JointType, Robot
from urdftool.physics.sdf_defaults import sdf_self_colliding
from urdftool.records import record

#: Collision geometries above which the home check is skipped (with a note).
MAX_GEOMETRIES = 200
#: Penetration (m) below which two geometries count as touching, not overlapping:
#: meshes exported flush against each other meet within a fraction of a millimetre.
DEPTH_TOLERANCE = 1e-3
#: MoveIt Setup Assistant's default: pairs in contact in this share of samples are ``Always``.
ALWAYS_FRACTION = 0.95
#: Rule option that turns the check off (it shares ``--no-dynamics`` with the Pinocchio pass).
OPTION = "dynamics"

Pair = tuple[str, str]


@record
class NotChecked:
    reason: str


@record
class Overlap:
    link1: str
    link2: str
    #: deepest penetration between the two links' geometries (m)
    depth: float


@record(frozen=False)
class Matrix:
    """A collision matrix: reason per disabled pair (names sorted in each pair)."""

    links: list[str]
    reasons: dict[Pair, str] = field(default_factory=dict)
    samples: int = 0
    seed: int = 0
    #: pairs seen in contact in some but not all samples: left enabled
    sometimes: dict[Pair, float] = field(default_factory=dict)


def pair(a: str, b: str) -> Pair:
    return (a, b) if a <= b else (b, a)


def available(ctx: CheckContext) -> bool:
    if not ctx.options.get(OPTION, True):
        return False
    return importlib.util.find_spec("pinocchio") is not None and (
        importlib.util.find_spec("coal") is not None or importlib.util.find_spec("hppfcl") is not None)


def scene_of(ctx: CheckContext, limit: int = MAX_GEOMETRIES) -> CollisionScene | NotChecked | None:
    """The robot's collision scene, why it was not built, or ``None`` (nothing to check).

    Models with more than *limit* collision geometries are not built."""
    key = ("collision-scene", limit)
    if key in ctx.cache:
        return ctx.cache[key]  # type: ignore[no-any-return]
    result: CollisionScene | NotChecked | None
    count = count_geometries(ctx.robot)
    if not available(ctx) or count < 2:
        result = None
    elif count > limit:
        result = NotChecked(f"{count} collision geometries, over the {limit} the home check handles")
    else:
        paths = {id(use.mesh): existing_file(use) for use in mesh_uses(ctx) if use.role == "collision"}
        try:
            result = build_scene(ctx.robot, paths)
        except ValueError as exc:  # joint types Pinocchio has no model for here
            result = NotChecked(str(exc))
        except RuntimeError as exc:  # Pinocchio refuses the model (a non-positive inertia)
            result = NotChecked(f"Pinocchio refused the model: {exc}")
    ctx.cache[key] = result
    return result


def adjacent(robot: Robot, with_geometry: set[str]) -> set[Pair]:
    """Link pairs joined by a joint, as MoveIt's Setup Assistant counts them: parent and child,
    and across a link without collision geometry (its neighbours are adjacent to each other)."""
    graph: dict[str, set[str]] = {}
    for joint in robot.joints:
        graph.setdefault(joint.parent, set()).add(joint.child)
        graph.setdefault(joint.child, set()).add(joint.parent)
    for link, neighbours in list(graph.items()):
        if link not in with_geometry:
            for a in neighbours:
                for b in neighbours:
                    if a != b:
                        graph[a].add(b)
    return {pair(a, b) for a, ns in graph.items() for b in ns if a != b}


def disabled_by_srdf(ctx: CheckContext) -> set[Pair]:
    found = srdf(ctx)
    if found is None:
        return set()
    off = {pair(c.link1.name, c.link2.name) for c in found.collisions if not c.enable}
    on = {pair(c.link1.name, c.link2.name) for c in found.collisions if c.enable}
    alone = {n.name for n in found.default_disabled}
    links = [link.name for link in ctx.robot.links]
    off |= {pair(a, b) for a in alone for b in links if a != b}
    return off - on


def home_configuration(ctx: CheckContext, scene: CollisionScene) -> Any:
    """Zeros clamped into the limits; the SRDF's first group state's values when there is one."""
    values = {j.name: _clamp(j, 0.0) for j in ctx.robot.joints}
    found = srdf(ctx)
    if found is not None and found.group_states:
        for value in found.group_states[0].joints:
            joint = ctx.robot.joint(value.name)
            if joint is not None and len(value.values) == 1:
                values[value.name] = _clamp(joint, value.values[0])
    return _configuration(ctx.robot, scene, values)


def default_configuration(robot: Robot, scene: CollisionScene) -> Any:
    """MoveIt's default state: 0, or the middle of the limits when 0 is outside them."""
    values: dict[str, float] = {}
    for joint in robot.joints:
        lo, hi = _bounds(joint)
        values[joint.name] = 0.0 if lo <= 0.0 <= hi else (lo + hi) / 2.0
    return _configuration(robot, scene, values)


def _bounds(joint: Joint) -> tuple[float, float]:
    limit = joint.limit
    if joint.type is JointType.CONTINUOUS or limit is None or limit.lower is None or limit.upper is None \
            or limit.lower > limit.upper or (limit.lower == 0.0 and limit.upper == 0.0):
        return (-math.pi, math.pi) if joint.type is not JointType.PRISMATIC else (0.0, 0.0)
    return float(limit.lower), float(limit.upper)


def _clamp(joint: Joint, value: float) -> float:
    lo, hi = _bounds(joint)
    return min(max(value, lo), hi)


_ONE_DOF = (JointType.REVOLUTE, JointType.CONTINUOUS, JointType.PRISMATIC)


def _one_dof(robot: Robot, scene: CollisionScene) -> list[tuple[Joint, int]]:
    out = []
    for joint in robot.joints:
        if joint.type in _ONE_DOF and joint.name in scene.pin.joints:
            out.append((joint, scene.pin.idx_q(joint.name)))
    return out


def _configuration(robot: Robot, scene: CollisionScene, values: dict[str, float]) -> Any:
    q = scene.neutral()
    for joint, idx in _one_dof(robot, scene):
        q[idx] = values.get(joint.name, 0.0)
    apply_mimics(robot, scene, q)
    return q


#: A mimic follower in the configuration vector: its index, its leader's, multiplier, offset.
Follower = tuple[int, int, float, float]


def mimic_followers(robot: Robot, scene: CollisionScene) -> list[Follower]:
    """Every 1-DOF mimic follower whose leader is in the model, in joint order."""
    out = []
    for joint in robot.joints:
        mimic = joint.mimic
        if mimic is None or joint.type not in _ONE_DOF or joint.name not in scene.pin.joints \
                or mimic.joint not in scene.pin.joints:
            continue
        leader = scene.pin.idx_q(mimic.joint)
        out.append((scene.pin.idx_q(joint.name), leader, mimic.multiplier, mimic.offset))
    return out


def apply_mimics(
    robot: Robot, scene: CollisionScene, q: Any, followers: list[Follower] | None = None
) -> None:
    """Set every mimic follower of *q* (one configuration or a stack of them) from its leader.

    *followers*: :func:`mimic_followers`, when a caller sets many configurations of one scene (a
    range sweep's samples).
    """
    for idx, leader, multiplier, offset in mimic_followers(robot, scene) if followers is None else followers:
        q[..., idx] = offset + multiplier * q[..., leader]


def _bodies_adjacent(scene: CollisionScene, adjacent_links: set[Pair]) -> set[tuple[int, int]]:
    """Rigid bodies (Pinocchio joints) joined by an adjacent link pair; every link counts, with or
    without geometry, so a link welded to a geometry-less one inherits its neighbours."""
    frames = scene.pin.model.frames
    body = {link: int(frames[fid].parentJoint) for link, fid in scene.pin.link_frames.items()}
    return {(min(body[a], body[b]), max(body[a], body[b])) for a, b in adjacent_links
            if a in body and b in body}


def home_overlaps(ctx: CheckContext) -> list[Overlap] | NotChecked | None:
    """Link pairs overlapping at home (deepest first), why they were not checked, or ``None``."""
    if "collision-home" in ctx.cache:
        return ctx.cache["collision-home"]  # type: ignore[no-any-return]
    # A closed chain's home is not its tree's zero configuration: not checked.
    scene = scene_of(ctx) if not ctx.robot.loop_closures else None
    result: list[Overlap] | NotChecked | None = scene if not isinstance(scene, CollisionScene) else None
    if isinstance(scene, CollisionScene):
        result = _overlaps(ctx, scene)
    ctx.cache["collision-home"] = result
    return result


def _overlaps(ctx: CheckContext, scene: CollisionScene) -> list[Overlap]:
    links = set(scene.links())
    near = adjacent(ctx.robot, links)
    near_bodies = _bodies_adjacent(scene, near)
    off = disabled_by_srdf(ctx)
    colliding = sdf_self_colliding(ctx.robot)
    todo = []
    for i, a in enumerate(scene.pieces):
        for j in range(i + 1, len(scene.pieces)):
            b = scene.pieces[j]
            if a.link == b.link or a.body == b.body or pair(a.link, b.link) in near | off:
                continue
            if colliding is not None and a.link not in colliding and b.link not in colliding:
                continue  # an SDF pair its simulator never collides
            if (min(a.body, b.body), max(a.body, b.body)) in near_bodies:
                continue
            todo.append((i, j))
    if not todo:
        return []
    scene.use_pairs(todo)
    deepest: dict[Pair, float] = {}
    order: dict[Pair, tuple[str, str]] = {}
    for (i, j), distance in zip(todo, scene.distances(home_configuration(ctx, scene)), strict=True):
        if -distance > DEPTH_TOLERANCE and scene.surfaces_meet(i, j):
            key = pair(scene.pieces[i].link, scene.pieces[j].link)
            order.setdefault(key, (scene.pieces[i].link, scene.pieces[j].link))
            deepest[key] = max(deepest.get(key, 0.0), -distance)
    return [Overlap(*order[k], depth=d) for k, d in deepest.items()]


def sample_configurations(robot: Robot, scene: CollisionScene, samples: int, seed: int) -> Any:
    """*samples* configurations drawn uniformly within the joint limits (seeded)."""
    rng = np.random.default_rng(seed)
    base = scene.neutral()
    qs = np.tile(base, (samples, 1))
    for joint, idx in _one_dof(robot, scene):
        lo, hi = _bounds(joint)
        qs[:, idx] = rng.uniform(lo, hi, size=samples) if hi > lo else lo
    apply_mimics(robot, scene, qs)
    return qs


def matrix(robot: Robot, scene: CollisionScene, samples: int = 10_000, seed: int = 0,
           progress: Callable[[int], None] | None = None) -> Matrix:
    """MoveIt Setup Assistant's classification of every pair of links with geometry."""
    links = scene.links()
    out = Matrix(links, samples=samples, seed=seed)
    for a, b in sorted(adjacent(robot, set(links))):
        if a in links and b in links:
            out.reasons[(a, b)] = "Adjacent"
    todo = [(i, j) for i in range(len(scene.pieces)) for j in range(i + 1, len(scene.pieces))
            if scene.pieces[i].link != scene.pieces[j].link
            and pair(scene.pieces[i].link, scene.pieces[j].link) not in out.reasons]
    scene.use_pairs(todo)
    link_pairs = [pair(scene.pieces[i].link, scene.pieces[j].link) for i, j in todo]
    for k in scene.colliding(default_configuration(robot, scene)):
        out.reasons.setdefault(link_pairs[k], "Default")
    keys = sorted(set(link_pairs))
    group = {key: g for g, key in enumerate(keys)}
    counts, done = sample_counts(scene, sample_configurations(robot, scene, samples, seed),
                                 [group[key] for key in link_pairs], progress)
    hits = dict(zip(keys, counts, strict=True))
    for key in sorted(hits):
        if key in out.reasons:
            continue
        fraction = hits[key] / done if done else 0.0
        if done and fraction >= ALWAYS_FRACTION:
            out.reasons[key] = "Always"
        elif hits[key] == 0:
            out.reasons[key] = "Never"
        else:
            out.sometimes[key] = fraction
    for i, a in enumerate(links):
        for b in links[i + 1:]:
            key = pair(a, b)
            if key not in out.reasons and key not in hits and key not in out.sometimes:
                out.reasons[key] = "Never"
    return out
