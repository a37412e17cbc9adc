"""Closed chains (L): loops in SDF models and links with several parents in URDF."""

from __future__ import annotations

from collections.abc import Iterator

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts.context import CheckContext
from urdftool.model import KinematicTree, LoopClosure


class _Loops(Rule):
    family = Family.LOOPS


def loop_cycle(tree: KinematicTree, closure: LoopClosure) -> tuple[list[str], list[str]]:
    """The links and joints around the loop a cut joint closes, starting at its parent link.

    Walks from both ends of the cut joint up the tree to their nearest common
    ancestor; returns ``(links, joints)`` in order around the loop, the cut
    joint last.
    """
    joint = closure.joint
    up_parent = _chain(tree, joint.parent)
    up_child = _chain(tree, joint.child)
    on_child_side = {link for link, _ in up_child}
    meet = next((link for link, _ in up_parent if link in on_child_side), None)
    links: list[str] = []
    joints: list[str] = []
    for link, via in up_parent:
        links.append(link)
        if link == meet or via is None:
            break
        joints.append(via)
    down: list[tuple[str, str | None]] = []
    for link, via in up_child:
        if link == meet:
            break
        down.append((link, via))
    for link, via in reversed(down):
        if via is not None:
            joints.append(via)
        links.append(link)
    joints.append(joint.name)
    return links, joints


def _chain(tree: KinematicTree, link: str) -> list[tuple[str, str | None]]:
    """``(link, joint to its parent)`` from *link* up to its root."""
    out: list[tuple[str, str | None]] = []
    seen: set[str] = set()
    current: str | None = link
    while current is not None and current not in seen:
        seen.add(current)
        joint = tree.parent_joint.get(current)
        out.append((current, joint.name if joint else None))
        current = joint.parent if joint else None
    return out


@register
class ClosedChain(_Loops):
    """The model has a closed kinematic chain; lists each loop with its links and joints.

    ## What it does
    For every joint that urdftool cut to turn the model's joint graph into a
    tree (see docs/sdf.md for how the cut is chosen), reports the loop it
    closes: the links and joints around it, the cut joint's type, and the
    anchor of the cut joint in each of its two links.

    ## Why it matters
    Tree-based tools (URDF, KDL, most IK solvers, PyBullet's URDF loader)
    cannot hold a loop: they drop the cut joint, so the linkage falls apart
    or moves as an open chain. Simulators that support loops need the cut
    joint as a constraint (an MJCF equality, an SDF joint).

    ## Example
    ```xml
    <joint name="coupler_to_rocker" type="revolute">
      <parent>coupler</parent> <child>rocker</child>
    </joint>  <!-- rocker already hangs from ground through another joint -->
    ```

    ## Fix
    Nothing to fix when the loop is intended: keep the model in SDF, or export
    it to MJCF, which keeps the loop as an equality constraint. Break the loop
    only when the extra joint is a mistake.
    """

    code = "L001"
    name = "closed-chain"
    severity = Severity.INFO

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for closure in ctx.robot.loop_closures:
            links, joints = loop_cycle(ctx.tree, closure)
            joint = closure.joint
            yield self.diagnostic(
                f"joint '{joint.name}' ({joint.type.value}) closes a loop of {len(links)} links: "
                + " → ".join(f"'{link}'" for link in links),
                joint.span,
                element=f"joint[{joint.name}]",
                help="kept as a loop-closure constraint; URDF cannot hold it, MJCF keeps it as an equality",
                data={
                    "links": links,
                    "joints": joints,
                    "cut_joint": joint.name,
                    "type": joint.type.value,
                    "parent_anchor": {
                        "xyz": list(closure.parent_anchor.xyz),
                        "rpy": list(closure.parent_anchor.rpy),
                    },
                    "child_anchor": {
                        "xyz": list(closure.child_anchor.xyz),
                        "rpy": list(closure.child_anchor.rpy),
                    },
                },
            )


@register
class LinkMultipleParents(_Loops):
    """A URDF link is the child of more than one joint.

    ## What it does
    Reports every joint after the first that names an already-parented link
    as its child, unless that joint also closes a directed cycle (reported by
    `kinematic-loop`).

    ## Why it matters
    URDF is a tree: every link has exactly one parent joint. urdfdom refuses
    the file, and permissive loaders keep one of the joints and silently drop
    the other, so the linkage the author drew is not the one simulated.

    ## Example
    ```xml
    <joint name="crank_to_coupler" type="revolute"><parent link="crank"/><child link="coupler"/></joint>
    <joint name="rocker_to_coupler" type="revolute"><parent link="rocker"/><child link="coupler"/></joint>
    ```

    ## Fix
    Remove the second joint to keep an open chain; to keep the closed chain,
    describe the model in SDF (which allows loops) or export it to MJCF with
    the extra joint as an equality constraint.
    """

    code = "L002"
    name = "link-multiple-parents"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        if ctx.robot.format == "sdf":
            return
        tree = ctx.tree
        for joint in tree.cycle_joints:
            first = tree.parent_joint.get(joint.child)
            if first is None or first is joint or joint.parent == joint.child:
                continue
            if tree._is_ancestor(joint.child, joint.parent):
                continue  # closes a directed cycle: kinematic-loop reports it
            yield self.diagnostic(
                f"link '{joint.child}' is the child of joint '{first.name}'"
                f" and again of joint '{joint.name}'",
                joint.span,
                element=f"joint[{joint.name}]",
                help="URDF links have one parent; keep the closed chain in SDF, or as an MJCF equality "
                "constraint, and remove this joint from the URDF",
                data={"link": joint.child, "joints": [first.name, joint.name]},
            )
