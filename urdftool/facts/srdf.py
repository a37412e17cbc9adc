"""The MoveIt SRDF read beside the robot, and what its groups contain.

The pipeline reads the SRDF (``check --srdf FILE``, or the one found beside the
model; see :mod:`urdftool.pipeline.srdf`) and hands it to the rules through
the run's options under :data:`OPTION`. The group contents here follow
MoveIt's ``JointModelGroup``: a joint brings its child link, a link its parent
joint, a chain every joint from base to tip, a subgroup its own contents.
"""

from __future__ import annotations

from dataclasses import field

from urdftool.facts.context import SRDF_OPTION, CheckContext
from urdftool.model import JointType
from urdftool.parse.srdf import Group, Srdf
from urdftool.records import record

#: The free-flyer joint Pinocchio adds when it loads a floating-base robot; example-robot-data's
#: SRDFs give it a value in their reference configurations.
PINOCCHIO_ROOT_JOINT = "root_joint"

#: Key of the run's options that holds the :class:`~urdftool.parse.srdf.Srdf`.
OPTION = SRDF_OPTION


def srdf(ctx: CheckContext) -> Srdf | None:
    value = ctx.options.get(OPTION)
    return value if isinstance(value, Srdf) else None


@record(frozen=False)
class GroupContents:
    """Joint and link names a group holds, its own and its subgroups'."""

    joints: set[str] = field(default_factory=set)
    links: set[str] = field(default_factory=set)


def virtual_joint_names(ctx: CheckContext) -> set[str]:
    found = srdf(ctx)
    return {v.name for v in found.virtual_joints} if found else set()


def chain_joints(ctx: CheckContext, base: str, tip: str) -> list[str] | None:
    """Joints from *base* down to *tip*, or ``None`` when *tip* does not hang below *base*."""
    out: list[str] = []
    current = tip
    seen: set[str] = set()
    while current != base:
        joint = ctx.tree.parent_joint.get(current)
        if joint is None or current in seen:
            return None
        seen.add(current)
        out.append(joint.name)
        current = joint.parent
    return out[::-1]


def contents(ctx: CheckContext, group: Group, _stack: tuple[str, ...] = ()) -> GroupContents:
    """What *group* holds (subgroup cycles are cut; :mod:`urdftool.rules.srdf` reports them)."""
    cache = ctx.cache.setdefault(("srdf-groups",), {})
    if group.name in cache:
        return cache[group.name]  # type: ignore[no-any-return]
    found = srdf(ctx)
    joints = {j.name: j for j in ctx.robot.joints}
    virtual = {v.name: v for v in found.virtual_joints} if found else {}
    out = GroupContents()
    for ref in group.joints:
        out.joints.add(ref.name)
        if ref.name in joints:
            out.links.add(joints[ref.name].child)
        elif ref.name in virtual:
            out.links.add(virtual[ref.name].child_link.name)
    for ref in group.links:
        out.links.add(ref.name)
        parent = ctx.tree.parent_joint.get(ref.name)
        if parent is not None:
            out.joints.add(parent.name)
    for chain in group.chains:
        names = chain_joints(ctx, chain.base.name, chain.tip.name) or []
        out.joints.update(names)
        out.links.update(joints[n].child for n in names if n in joints)
    for ref in group.subgroups:
        sub = found.group(ref.name) if found else None
        if sub is not None and sub.name not in _stack and sub.name != group.name:
            inner = contents(ctx, sub, (*_stack, group.name))
            out.joints |= inner.joints
            out.links |= inner.links
    if not _stack:
        cache[group.name] = out
    return out


def variable_count(ctx: CheckContext, joint_name: str) -> int | None:
    """How many values a state gives *joint_name*: 1, 3 (planar), 7 (floating), 0 (fixed)."""
    joint = next((j for j in ctx.robot.joints if j.name == joint_name), None)
    if joint is not None:
        return {JointType.FIXED: 0, JointType.PLANAR: 3, JointType.FLOATING: 7}.get(joint.type, 1)
    found = srdf(ctx)
    virtual = next((v for v in found.virtual_joints if v.name == joint_name), None) if found else None
    if virtual is not None:
        return {"fixed": 0, "planar": 3, "floating": 7}.get(virtual.type)
    return None
