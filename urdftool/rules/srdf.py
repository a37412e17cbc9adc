"""MoveIt SRDF (P): the semantic description checked against the robot it describes.

The SRDF is read by :mod:`urdftool.parse.srdf` and handed over by the pipeline
(:mod:`urdftool.facts.srdf`); without one these rules report nothing. Every
finding is located in the ``.srdf`` file. What MoveIt does with each defect
(from srdfdom and moveit_core's ``RobotModel``) decides the severity: a name
MoveIt drops with an error log is an error, since the group, state or
collision exclusion the author wrote is silently gone. Decisions: docs/srdf.md.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.catalogue.suggest import did_you_mean, suggester
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts import srdf as facts
from urdftool.facts.context import CheckContext
from urdftool.model import JointType
from urdftool.parse.srdf import JointValue, Named

#: Values within this of a limit are inside it (SRDFs round to 6 digits).
_TOLERANCE = 1e-6
_ACTIVE = (JointType.REVOLUTE, JointType.PRISMATIC, JointType.CONTINUOUS, JointType.PLANAR,
           JointType.FLOATING)


class _Srdf(Rule):
    family = Family.SRDF
    kind = "model"
    since = "0.2.0"


@register
class SrdfRobotMismatch(_Srdf):
    """The SRDF is written for a robot of another name.

    ## What it does
    Compares the SRDF's `<robot name>` with the URDF's.

    ## Why it matters
    MoveIt logs "Semantic description is not specified for the same robot as
    the URDF" and goes on; a different name usually means the SRDF of another
    robot (or of another variant of this one) was picked up.

    ## Example
    ```xml
    <robot name="panda_arm">   <!-- the URDF says <robot name="panda"> -->
    ```

    ## Fix
    Give the SRDF the URDF's robot name, or point `--srdf` at the right file.
    """

    code = "P001"
    name = "srdf-robot-mismatch"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        found = facts.srdf(ctx)
        if found is None or not found.robot_name or not ctx.robot.name or found.robot_name == ctx.robot.name:
            return
        yield self.diagnostic(
            f"the SRDF describes robot '{found.robot_name}', the model is '{ctx.robot.name}'",
            found.span,
            element=f"robot[{found.robot_name}]",
            help=f"write <robot name=\"{ctx.robot.name}\"> in the SRDF, or check that it is the right SRDF",
        )


@register
class SrdfUnknownLink(_Srdf):
    """The SRDF names a link the robot does not have.

    ## What it does
    Checks the links named by groups (`<link>`, `<chain base_link tip_link>`),
    end effectors (`parent_link`), virtual joints (`child_link`) and the
    collision matrix (`<disable_collisions link1 link2>`,
    `<disable_default_collisions link>`).

    ## Why it matters
    MoveIt drops the name with an error in its log: a group loses a link (or
    is empty and dropped), an end effector disappears, and a misspelt
    `disable_collisions` pair is checked after all, so a gripper in contact
    with its own wrist makes every start state "in collision".

    ## Example
    ```xml
    <disable_collisions link1="panda_link1" link2="panda_lnk2" reason="Adjacent"/>
    ```

    ## Fix
    Use the link's exact name from the URDF; regenerate the collision matrix
    after renaming links.
    """

    code = "P002"
    name = "srdf-unknown-link"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        found = facts.srdf(ctx)
        if found is None:
            return
        links = {link.name for link in ctx.robot.links}
        refs: list[tuple[Named, str]] = []
        for group in found.groups:
            refs += [(ref, f"group '{group.name}'") for ref in group.links]
            for chain in group.chains:
                refs += [(chain.base, f"the chain of group '{group.name}'"),
                         (chain.tip, f"the chain of group '{group.name}'")]
        refs += [(e.parent_link, f"end effector '{e.name}'") for e in found.end_effectors]
        refs += [(v.child_link, f"virtual joint '{v.name}'") for v in found.virtual_joints]
        # The collision matrix is most of an SRDF: its names are tested first, and its pairs (with
        # their spans) are built only when one names a link the robot does not have.
        if not links.issuperset(name for pair in found.collision_names for name in pair[:2]):
            for pair in found.collisions:
                refs += [(pair.link1, "a collision pair"), (pair.link2, "a collision pair")]
        refs += [(ref, "disable_default_collisions") for ref in found.default_disabled]
        suggest = suggester(links)
        for ref, owner in refs:
            if ref.name not in links:
                yield self.diagnostic(
                    f"{owner} names link '{ref.name}', which the robot does not have"
                    + suggest(ref.name),
                    ref.span,
                    element=f"link[{ref.name}]",
                    help="use the exact name of one of the URDF's links",
                    data={"link": ref.name},
                )


@register
class SrdfUnknownJoint(_Srdf):
    """The SRDF names a joint the robot does not have.

    ## What it does
    Checks the joints named by groups, group states and `<passive_joint>`s
    against the URDF's joints and the SRDF's virtual joints.

    ## Why it matters
    MoveIt drops the joint: a group loses it (the arm plans with one joint
    fewer), a named state leaves it at its default, a passive joint is
    planned for as if it had a motor.

    ## Example
    ```xml
    <group name="arm"><joint name="panda_joint8"/></group>   <!-- no such joint -->
    ```

    ## Fix
    Use the joint's exact name from the URDF, or add the virtual joint the
    group means.
    """

    code = "P003"
    name = "srdf-unknown-joint"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        found = facts.srdf(ctx)
        if found is None:
            return
        joints = {joint.name for joint in ctx.robot.joints} | facts.virtual_joint_names(ctx)
        # (the name with its span, who names it, the owner's name): the owner is written out
        # only for a finding, not for every joint of every group state.
        refs: list[tuple[Named | JointValue, str, str | None]] = []
        for group in found.groups:
            refs += [(ref, "group", group.name) for ref in group.joints]
        for state in found.group_states:
            refs += [(value, "group state", state.name) for value in state.joints
                     if value.name != facts.PINOCCHIO_ROOT_JOINT]
        refs += [(ref, "a passive joint", None) for ref in found.passive_joints]
        suggest = suggester(joints)
        for ref, kind, owner in refs:
            if ref.name not in joints:
                yield self.diagnostic(
                    (kind if owner is None else f"{kind} '{owner}'") + f" names joint '{ref.name}', "
                    "which the robot does not have" + suggest(ref.name),
                    ref.span,
                    element=f"joint[{ref.name}]",
                    help="use the exact name of one of the URDF's joints or the SRDF's virtual joints",
                    data={"joint": ref.name},
                )


@register
class SrdfChainBroken(_Srdf):
    """A group's `<chain>` tip does not hang below its base.

    ## What it does
    Follows the tree up from `tip_link`; reports the chain when `base_link`
    is not on the way (tip and base swapped, or on different branches).

    ## Why it matters
    srdfdom builds a chain by walking up from the tip to the base; when the
    base is not above the tip the chain holds other joints than meant, or is
    dropped ("do not form a chain"), and the group plans for the wrong joints.

    ## Example
    ```xml
    <chain base_link="panda_hand" tip_link="panda_link0"/>   <!-- swapped -->
    ```

    ## Fix
    Write the link nearer the root as `base_link` and a link below it as `tip_link`.
    """

    code = "P004"
    name = "srdf-chain-broken"
    # srdfdom builds chains from the tip up; whether a path through a common ancestor
    # is accepted has changed between releases, so this is not an error.
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        found = facts.srdf(ctx)
        if found is None:
            return
        links = {link.name for link in ctx.robot.links}
        for group in found.groups:
            for chain in group.chains:
                base, tip = chain.base.name, chain.tip.name
                if base not in links or tip not in links:
                    continue  # srdf-unknown-link
                if facts.chain_joints(ctx, base, tip) is None:
                    swapped = facts.chain_joints(ctx, tip, base) is not None
                    yield self.diagnostic(
                        f"group '{group.name}': chain tip '{tip}' does not hang below base '{base}'"
                        + (" (base and tip are swapped)" if swapped else ""),
                        chain.span,
                        element=f"group[{group.name}]/chain",
                        help="swap base_link and tip_link" if swapped
                        else "pick a base_link on the path from the tip to the root",
                        data={"group": group.name, "base": base, "tip": tip},
                    )


@register
class SrdfUnknownGroup(_Srdf):
    """The SRDF names a group it does not define.

    ## What it does
    Checks the groups named by `<group><group name>` (subgroups), by group
    states (`group`) and by end effectors (`group`, `parent_group`).

    ## Why it matters
    MoveIt drops the subgroup, the named state or the end effector with an
    error in its log; `move_group` then has no "home" pose, or no gripper.

    ## Example
    ```xml
    <group_state name="ready" group="panda_arm">   <!-- the group is "arm" -->
    ```

    ## Fix
    Use the exact name of a `<group>` of this SRDF.
    """

    code = "P005"
    name = "srdf-unknown-group"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        found = facts.srdf(ctx)
        if found is None:
            return
        groups = {group.name for group in found.groups}
        refs: list[tuple[Named, str]] = []
        for group in found.groups:
            refs += [(ref, f"group '{group.name}'") for ref in group.subgroups]
        refs += [(s.group, f"group state '{s.name}'") for s in found.group_states if s.group is not None]
        for effector in found.end_effectors:
            refs.append((effector.group, f"end effector '{effector.name}'"))
            if effector.parent_group is not None:
                refs.append((effector.parent_group, f"end effector '{effector.name}' (parent_group)"))
        for ref, owner in refs:
            if ref.name not in groups:
                yield self.diagnostic(
                    f"{owner} names group '{ref.name}', which the SRDF does not define"
                    + did_you_mean(ref.name, groups),
                    ref.span,
                    element=f"group[{ref.name}]",
                    help="use the exact name of one of the SRDF's groups",
                    data={"group": ref.name},
                )


@register
class SrdfGroupCycle(_Srdf):
    """Groups include each other in a cycle.

    ## What it does
    Follows `<group><group name>` subgroup references and reports a group
    that includes itself, directly or through others.

    ## Why it matters
    MoveIt cannot build the groups of the cycle and drops them all.

    ## Example
    ```xml
    <group name="a"><group name="b"/></group>
    <group name="b"><group name="a"/></group>
    ```

    ## Fix
    Make the inclusion go one way: the larger group lists the smaller.
    """

    code = "P006"
    name = "srdf-group-cycle"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        found = facts.srdf(ctx)
        if found is None:
            return
        edges = {g.name: [r.name for r in g.subgroups] for g in found.groups}
        reported: set[frozenset[str]] = set()
        for group in found.groups:
            cycle = _cycle_from(group.name, edges)
            if cycle is None or frozenset(cycle) in reported:
                continue
            reported.add(frozenset(cycle))
            yield self.diagnostic(
                "groups include each other: " + " → ".join([*cycle, cycle[0]]),
                group.span,
                element=f"group[{group.name}]",
                help="remove one of the subgroup references",
                data={"cycle": cycle},
            )


def _cycle_from(start: str, edges: dict[str, list[str]]) -> list[str] | None:
    """The cycle through *start*, if any (depth first)."""
    stack: list[tuple[str, list[str]]] = [(start, [start])]
    seen: set[str] = set()
    while stack:
        node, path = stack.pop()
        for nxt in edges.get(node, []):
            if nxt == start:
                return path
            if nxt not in seen and nxt in edges:
                seen.add(nxt)
                stack.append((nxt, [*path, nxt]))
    return None


@register
class SrdfStateIncomplete(_Srdf):
    """A named state leaves out joints of its group, or sets joints outside it.

    ## What it does
    Compares the joints a `<group_state>` sets with the moving joints of its
    group (its joints, links, chains and subgroups, as MoveIt builds them).
    Mimic and passive joints and fixed joints need no value; a state without
    a `group` (Pinocchio's reference configurations) is not checked.

    ## Why it matters
    MoveIt warns and leaves a missing joint at its default, so "home" is not
    the pose the author meant; a value for a joint outside the group is
    dropped with an error.

    ## Example
    ```xml
    <group_state name="ready" group="arm">
      <joint name="panda_joint1" value="0"/>   <!-- panda_joint2…7 missing -->
    </group_state>
    ```

    ## Fix
    Give every moving joint of the group a value; move values of other joints
    into a state of a group that holds them.
    """

    code = "P007"
    name = "srdf-state-incomplete"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        found = facts.srdf(ctx)
        if found is None:
            return
        joints = {j.name: j for j in ctx.robot.joints}
        virtual = facts.virtual_joint_names(ctx)
        passive = {p.name for p in found.passive_joints}
        for state in found.group_states:
            group = found.group(state.group.name) if state.group is not None else None
            if group is None:
                continue
            held = facts.contents(ctx, group).joints
            if not held:
                continue  # an empty group: MoveIt drops it, Pinocchio reads it as "the whole robot"
            given = {value.name for value in state.joints}
            for value in state.joints:
                if value.name not in held and (value.name in joints or value.name in virtual):
                    yield self.diagnostic(
                        f"group state '{state.name}' sets joint '{value.name}', which is not in group "
                        f"'{group.name}'; MoveIt drops the value",
                        value.span,
                        element=f"group_state[{state.name}]/joint[{value.name}]",
                        help=f"remove it, or use a group that holds '{value.name}'",
                        data={"state": state.name, "joint": value.name},
                    )
            needed = sorted(
                name for name in held
                if name in joints and joints[name].type in _ACTIVE and joints[name].mimic is None
                and name not in passive and name not in given
            )
            if needed:
                yield self.diagnostic(
                    f"group state '{state.name}' gives no value for {len(needed)} joint(s) of group "
                    f"'{group.name}': {', '.join(needed[:6])}{' …' if len(needed) > 6 else ''}",
                    state.span,
                    element=f"group_state[{state.name}]",
                    help="add a <joint name value> for each",
                    data={"state": state.name, "missing": needed},
                )


@register
class SrdfStateOutsideLimits(_Srdf):
    """A named state puts a joint outside its limits, or gives it the wrong number of values.

    ## What it does
    Compares each value of a `<group_state>` with the joint's `<limit
    lower upper>` (continuous joints have none) and the number of values with
    the joint's type (1, 3 for planar, 7 for floating).

    ## Why it matters
    Planning to the named target fails ("goal not within bounds"), and a
    state with the wrong number of values is dropped by MoveIt.

    ## Example
    ```xml
    <joint name="panda_joint4" value="0.5"/>   <!-- limits are [-3.07, -0.07] -->
    ```

    ## Fix
    Write a value inside the limits (in radians or metres), or widen the
    limit if the URDF is wrong.
    """

    code = "P008"
    name = "srdf-state-outside-limits"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        found = facts.srdf(ctx)
        if found is None:
            return
        joints = {j.name: j for j in ctx.robot.joints}
        for state in found.group_states:
            for value in state.joints:
                if not value.values:
                    continue  # invalid-number
                where = f"group_state[{state.name}]/joint[{value.name}]"
                count = facts.variable_count(ctx, value.name)
                if count is not None and count != len(value.values) and count > 0:
                    yield self.diagnostic(
                        f"group state '{state.name}': joint '{value.name}' takes {count} value(s), "
                        f"{len(value.values)} given",
                        value.span, element=where, help=f"write {count} space-separated values",
                        data={"state": state.name, "joint": value.name},
                    )
                    continue
                joint = joints.get(value.name)
                if joint is None or joint.type not in (JointType.REVOLUTE, JointType.PRISMATIC):
                    continue
                limit = joint.limit
                if limit is None or limit.lower is None or limit.upper is None:
                    continue
                q = value.values[0]
                if not math.isfinite(q):
                    continue
                slack = _TOLERANCE * max(1.0, abs(limit.lower), abs(limit.upper))
                if q < limit.lower - slack or q > limit.upper + slack:
                    yield self.diagnostic(
                        f"group state '{state.name}': joint '{value.name}' = {q:g} is outside its limits "
                        f"[{limit.lower:g}, {limit.upper:g}]",
                        value.span, element=where,
                        help="write a value inside the joint's <limit>",
                        data={"state": state.name, "joint": value.name, "value": q,
                              "lower": limit.lower, "upper": limit.upper},
                    )
