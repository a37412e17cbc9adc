"""Mimic joints (J008, J009): a `<mimic>` that names no joint, and mimic chains that close on
themselves. Decisions are in ``docs/joints.md``."""

from __future__ import annotations

from collections.abc import Iterator

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.catalogue.suggest import suggester
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts.context import CheckContext
from urdftool.model import Joint


def _where(joint: Joint) -> str:
    return f"joint[{joint.name}]/mimic"


@register
class MimicTargetMissing(Rule):
    """A `<mimic>` names a joint that does not exist.

    ## What it does
    Reports mimic elements whose `joint` attribute names no joint of the
    robot.

    ## Why it matters
    The mimicking joint has nothing to follow: urdfdom-based tools leave it
    free, MuJoCo's importer drops the coupling, and a gripper's second finger
    hangs loose.

    ## Example
    ```xml
    <mimic joint="finger_joint_1" multiplier="1"/>   <!-- the joint is 'finger_1_joint' -->
    ```

    ## Fix
    Name an existing joint, e.g. `<mimic joint="finger_1_joint"/>`.
    """

    family = Family.JOINTS
    code = "J008"
    name = "mimic-target-missing"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        names = {joint.name for joint in ctx.robot.joints}
        suggest = suggester(names)  # both hands of a robot may mimic the same missing joint
        for joint in ctx.robot.joints:
            mimic = joint.mimic
            if mimic is None or mimic.joint in names:
                continue
            yield self.diagnostic(
                f"joint '{joint.name}' mimics '{mimic.joint}', which is not a joint of this robot"
                + suggest(mimic.joint),
                mimic.span or joint.span, element=_where(joint),
                data={"target": mimic.joint},
            )


@register
class MimicCycle(Rule):
    """Mimic joints follow each other in a cycle.

    ## What it does
    Follows each joint's `<mimic>` target, then that joint's target, and so
    on, and reports a chain that comes back to a joint already on it
    (including a joint that mimics itself). Each cycle is reported once, at
    the first of its joints in the file.

    ## Why it matters
    A cycle has no driving joint: every position depends on another in the
    loop. Tools that resolve mimic chains recurse forever or give up, and the
    coupled joints are left free or frozen.

    ## Example
    ```xml
    <joint name="left_finger"> … <mimic joint="right_finger"/></joint>
    <joint name="right_finger"> … <mimic joint="left_finger"/></joint>
    ```

    ## Fix
    Remove the `<mimic>` from the joint that is actuated, so the chain ends
    there.
    """

    family = Family.JOINTS
    code = "J009"
    name = "mimic-cycle"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        joints = {joint.name: joint for joint in ctx.robot.joints}
        order = {joint.name: index for index, joint in enumerate(ctx.robot.joints)}
        for cycle in mimic_cycles(joints):
            first = joints[min(cycle, key=order.__getitem__)]
            start = cycle.index(first.name)
            ordered = cycle[start:] + cycle[:start]
            chain = " → ".join(f"'{name}'" for name in [*ordered, ordered[0]])
            yield self.diagnostic(
                f"mimic joints follow each other in a cycle: {chain}",
                first.mimic.span if first.mimic and first.mimic.span else first.span,
                element=_where(first),
                help=f"remove the <mimic> of the actuated joint of the loop (e.g. '{first.name}')",
                data={"cycle": ordered},
            )


def mimic_cycles(joints: dict[str, Joint]) -> list[list[str]]:
    """Every cycle of mimic targets, each once, in the order it is first reached.

    Each joint is walked at most once (linear time): a walk stops at a joint an
    earlier walk has finished, and reports a cycle when it meets itself.
    """
    finished: set[str] = set()
    cycles: list[list[str]] = []
    for start in joints:
        path: list[str] = []
        on_path: dict[str, int] = {}
        current: str | None = start
        while current is not None and current in joints and current not in finished:
            if current in on_path:
                cycles.append(path[on_path[current] :])
                break
            on_path[current] = len(path)
            path.append(current)
            mimic = joints[current].mimic
            current = mimic.joint if mimic is not None else None
        finished.update(path)
    return cycles
