"""Choosing a spanning tree when an SDF model's joint graph has closed chains.

The rule (documented in docs/sdf.md):

1. Roots are the links that are nobody's child, the canonical link's root first,
   then the others in file order. When links are left over (a chain that only
   closes on itself), the first of them in file order becomes a root as well.
2. Links are reached breadth-first, following each joint from parent to child,
   so every kept joint lies on a shortest path from a root.
3. When several joints reach the same link at the same depth, the one most
   likely driven is kept: single-DOF joints with an effort limit, then other
   single-DOF and fixed joints, then ball/universal/revolute2, then gearbox
   couplings; ties go to the joint written first.
4. A prismatic joint left out by points 2 and 3 takes the place of the fixed,
   hinge or ball joint that reaches the same link, when that joint is no more
   likely driven and the slider's parent does not hang below the link: MJCF
   closes a cut fixed joint with a ``weld`` and a hinge or ball with
   ``connect`` constraints, a cut slider with nothing it has.
5. Every other joint between known links is a loop closure. Joints that name
   an unknown link or the same link twice stay in the joint list for the
   structural rules to report.
"""

from __future__ import annotations

from collections.abc import Sequence

from urdftool.model import Joint, JointType

_PASSIVE_MULTI = {JointType.SPHERICAL, JointType.UNIVERSAL, JointType.REVOLUTE2}
#: Joints whose cut MJCF closes completely (``weld``; ``connect``, two for a hinge), unlike a slider.
_CLOSABLE = {JointType.FIXED, JointType.REVOLUTE, JointType.CONTINUOUS, JointType.SPHERICAL}


def keep_rank(joint: Joint) -> int:
    """Lower ranks are kept in the tree first (see the module docstring, point 3)."""
    if joint.type is JointType.GEARBOX:
        return 3
    if joint.type in _PASSIVE_MULTI:
        return 2
    limit = joint.limit
    if joint.type.dof == 1 and limit is not None and limit.effort is not None and limit.effort > 0:
        return 0
    return 1


def spanning_tree(
    links: Sequence[str], joints: Sequence[Joint], canonical: str | None = None
) -> tuple[list[Joint], list[Joint]]:
    """Split *joints* into ``(tree joints, loop-closing joints)``, both in file order."""
    names = set(links)
    usable = [j for j in joints if j.parent in names and j.child in names and j.parent != j.child]
    children = {j.child for j in usable}
    roots = [name for name in links if name not in children]
    if canonical in names:
        roots.sort(key=lambda r: r != _root_of(canonical, usable))
    order = {id(j): i for i, j in enumerate(joints)}
    kept: dict[str, Joint] = {}
    reached: set[str] = set()
    pending = list(links)
    frontier = list(roots)
    while True:
        reached.update(frontier)
        while frontier:
            frontier = _next_level(frontier, usable, reached, kept, order)
            reached.update(frontier)
        rest = [name for name in pending if name not in reached]
        if not rest:
            break
        frontier = [rest[0]]
    _keep_sliders(usable, kept)
    tree_ids = {id(j) for j in kept.values()}
    usable_ids = {id(j) for j in usable}
    tree = [j for j in joints if id(j) in tree_ids or id(j) not in usable_ids]
    cut = [j for j in usable if id(j) not in tree_ids]
    return tree, cut


def _next_level(
    frontier: list[str], joints: list[Joint], reached: set[str], kept: dict[str, Joint], order: dict[int, int]
) -> list[str]:
    level = set(frontier)
    best: dict[str, Joint] = {}
    for joint in joints:
        if joint.parent not in level or joint.child in reached:
            continue
        current = best.get(joint.child)
        key = (keep_rank(joint), order[id(joint)])
        if current is None or key < (keep_rank(current), order[id(current)]):
            best[joint.child] = joint
    kept.update(best)
    return sorted(best, key=lambda name: order[id(best[name])])


def _keep_sliders(joints: list[Joint], kept: dict[str, Joint]) -> None:
    """Point 4 of the module docstring: swap each cut prismatic joint (in file order) into the
    tree for the fixed, hinge or ball joint that reaches its child, when that is allowed.

    Both joints name the same child, so no joint is reversed and the child's subtree moves
    with it; the tree stays a tree as long as the slider's parent is not in that subtree."""
    for joint in joints:
        current = kept.get(joint.child)
        if (joint.type is not JointType.PRISMATIC or current is None or current is joint
                or current.type not in _CLOSABLE or keep_rank(current) < keep_rank(joint)
                or _below(joint.parent, joint.child, kept)):
            continue
        kept[joint.child] = joint


def _below(link: str, ancestor: str, kept: dict[str, Joint]) -> bool:
    """Whether *link* is *ancestor* or hangs below it in the tree *kept* (child -> joint)."""
    seen: set[str] = set()
    while link not in seen:
        if link == ancestor:
            return True
        seen.add(link)
        joint = kept.get(link)
        if joint is None:
            return False
        link = joint.parent
    return False


def _root_of(link: str, joints: list[Joint]) -> str:
    """Follow the first parent joint of each link upwards (cycle-safe)."""
    parents: dict[str, str] = {}
    for joint in joints:
        parents.setdefault(joint.child, joint.parent)
    seen = {link}
    while link in parents and parents[link] not in seen:
        link = parents[link]
        seen.add(link)
    return link
