"""A joint's dynamics (J011): damping, friction and spring stiffness that cannot be negative."""

from __future__ import annotations

from collections.abc import Iterator

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts.context import CheckContext
from urdftool.model import JointType


@register
class NegativeJointDynamics(Rule):
    """A joint's damping, friction or spring stiffness is negative.

    ## What it does
    Reports a joint (URDF `<dynamics damping friction>`, SDF
    `<axis><dynamics>` with `damping`, `friction` and `spring_stiffness`,
    cut joints of closed chains included) whose coefficient is below zero.

    ## Why it matters
    Neither urdfdom nor libsdformat checks the sign, and no engine does
    either. Negative viscous damping puts energy into the joint every step,
    so it speeds up without bound and the simulation blows up; a negative
    spring pushes the joint away from its reference instead of back;
    negative Coulomb friction has no meaning. urdftool's MJCF and PyBullet
    exports write only positive values, so the exported model differs from
    the file. Zero is the "off" value.

    ## Example
    ```xml
    <axis><xyz>1 0 0</xyz><dynamics><damping>-0.5</damping></dynamics></axis>
    ```

    ## Fix
    Write the magnitude: `<damping>0.5</damping>` (N·m·s/rad for a hinge,
    N·s/m for a slider).
    """

    family = Family.JOINTS
    code = "J011"
    name = "negative-joint-dynamics"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        joints = [*ctx.robot.joints, *(closure.joint for closure in ctx.robot.loop_closures)]
        for joint in joints:
            dynamics = joint.dynamics
            if dynamics is None:
                continue
            linear = joint.type is JointType.PRISMATIC
            units = {
                "damping": "N·s/m" if linear else "N·m·s/rad",
                "friction": "N" if linear else "N·m",
                "spring_stiffness": "N/m" if linear else "N·m/rad",
            }
            for field, unit in units.items():
                value = getattr(dynamics, field)
                if value < 0:
                    yield self.diagnostic(
                        f"joint '{joint.name}': {field} {value:g} {unit} is negative; a joint with it "
                        + ("gains energy and runs away" if field == "damping"
                           else "is pushed away from its reference" if field == "spring_stiffness"
                           else "has a friction no engine can apply"),
                        dynamics.span or joint.span,
                        element=f"joint[{joint.name}]/dynamics",
                        help=f"write the magnitude ({-value:g}), or 0 for none",
                        data={"field": field, "value": value},
                    )
