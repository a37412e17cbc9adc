"""Joint types that contradict the limb they are in (N304).

A limb is the chain of moving joints from a branch point (a link that carries
two or more moving chains, or the root) to a leaf. Legs and arms whose joints
are all limited do not have one joint that turns without end in their middle:
that joint was typed ``continuous`` by mistake (a copied wheel joint, an
exporter's default), and a position controller or a planner can then wind it
past where the hardware stops.
"""

from __future__ import annotations

import re
from collections.abc import Iterator

from urdftool.catalogue.registry import register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts.context import CheckContext
from urdftool.model import Joint, JointType, KinematicTree
from urdftool.rules.intent_common import IntentRule, where_joint

#: Limited revolute joints a limb must have besides the continuous one for the contrast to count.
LIMITED_MIN = 2
#: Limbs longer than this are arms, whose last joint (a wrist or tool roll) may spin on purpose.
SHORT_LIMB = 4
#: Children that turn without end by design.
_SPINNING = re.compile(r"wheel|roller|caster|castor|rotor|prop|spin|lidar|laser|fan|drum|track",
                       re.IGNORECASE)


def limbs(tree: KinematicTree) -> list[list[Joint]]:
    """Every limb's moving joints, from its branch point (or root) to its leaf."""
    moving_below: dict[str, bool] = {}
    branches: set[str] = set()
    order = tree.order
    for name in reversed(order):  # children before their parents
        # the child joints that move, or lead to one that does
        chains = 0
        for below in tree.child_joints.get(name, ()):
            if below.type is not JointType.FIXED or moving_below.get(below.child, False):
                chains += 1
        moving_below[name] = chains > 0
        if chains >= 2:
            branches.add(name)
    out: list[list[Joint]] = []
    for name in order:
        if moving_below.get(name, False):
            continue  # not the end of a limb
        chain: list[Joint] = []
        link = name
        while True:
            joint = tree.parent_joint.get(link)
            if joint is None:
                break
            if joint.type.is_moving:
                chain.append(joint)
            if joint.parent in branches:
                break
            link = joint.parent
        if chain:
            out.append(list(reversed(chain)))
    return out


@register
class ContinuousInLimitedLimb(IntentRule):
    """One joint of a limb turns without end while the limb's other joints are all limited.

    ## What it does
    Splits the robot into limbs (the chains of moving joints between branch
    points and leaves) and reports a `continuous` joint when its limb has at
    least two limited `revolute` joints and no other continuous joint, the
    joint is not the last of a limb longer than four joints (an arm's wrist
    or tool roll may spin), and its name or its child's does not say it
    spins (wheel, roller, caster, rotor, propeller, lidar, fan, drum, track).

    ## Why it matters
    `continuous` has no limits: MoveIt plans through any angle, ros2_control
    and Gazebo never stop it, and `check` cannot judge its range. In a leg or
    an arm whose other joints are limited, it is almost always a copied wheel
    joint or an exporter's default: the knee winds through the thigh.

    ## Example
    ```xml
    <joint name="FL_knee" type="continuous">   <!-- hip and thigh are revolute, limited -->
    ```

    ## Fix
    Make it `revolute` with the hardware's `lower`/`upper`. To silence it for
    a joint that does spin: `<!-- urdftool: ignore[N304] -->` before the joint.
    """

    code = "N304"
    name = "continuous-in-limited-limb"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        if all(joint.type is not JointType.CONTINUOUS for joint in ctx.robot.joints):
            return  # most arms: no limb can have its one continuous joint
        for limb in limbs(ctx.tree):
            continuous = [j for j in limb if j.type is JointType.CONTINUOUS]
            if len(continuous) != 1:
                continue
            limited = [j for j in limb if j.type is JointType.REVOLUTE and j.limit is not None
                       and j.limit.lower is not None and j.limit.upper is not None]
            if len(continuous) != 1 or len(limited) < LIMITED_MIN:
                continue
            joint = continuous[0]
            end_roll = joint is limb[-1] and len(limb) > SHORT_LIMB
            if end_roll or _SPINNING.search(joint.child) or _SPINNING.search(joint.name):
                continue
            others = ", ".join(f"'{j.name}'" for j in limited[:4]) + (" …" if len(limited) > 4 else "")
            yield self.diagnostic(
                f"joint '{joint.name}' is continuous (no limits) while every other joint of its "
                f"limb is limited ({others})",
                joint.span,
                element=where_joint(joint, "type"),
                help="make it revolute with the hardware's lower and upper limits",
                data={"joint": joint.name, "limb": [j.name for j in limb]},
            )
