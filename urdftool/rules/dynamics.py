"""Dynamics (D): rigid-body checks with Pinocchio (mass matrix, gravity torques).

The numbers come from :mod:`urdftool.dynamics` (computed once per robot and
shared by the rules through the check cache). The pass runs in ``check`` by
default when Pinocchio is installed and is skipped with ``--no-dynamics``.
Thresholds were calibrated on example-robot-data and pybullet_data; the
numbers are in ``docs/dynamics.md``.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from urdftool.budgets import budget, how_to_raise
from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts.context import CheckContext
from urdftool.facts.dynamics.analysis import GRAVITY, Conditioning, DynamicsAnalysis, GravityLoad
from urdftool.facts.dynamics.configurations import rounded
from urdftool.facts.dynamics.run import Skipped, dynamics_of
from urdftool.model import JointType
from urdftool.physics.describe import fmt
from urdftool.source import Span

#: A mass matrix whose smallest eigenvalue is at most this fraction of its largest
#: (condition number 1e12 and up) is singular in double precision.
SINGULAR_RATIO = 1e-12
#: mass-matrix-ill-conditioned fires above this condition number. Every model of
#: both corpora with valid inertia stays below it (largest: 5.3e7, human.urdf near the
#: alignment of its three-joint shoulder; then 8.8e6, cassie_simple.sdf).
CONDITION_LIMIT = 1e8
#: Relative margin before a gravity torque counts as above the effort limit (rounding).
EFFORT_MARGIN = 1e-6


class _Dynamics(Rule):
    family = Family.DYNAMICS


def analysis(ctx: CheckContext) -> Any:
    """The dynamics pass's result for this robot, computed once per check run."""
    if "dynamics" not in ctx.cache:
        ctx.cache["dynamics"] = dynamics_of(ctx.robot, ctx.tree, ctx.options)
    return ctx.cache["dynamics"]


def _conditioning(ctx: CheckContext) -> Conditioning | None:
    result = analysis(ctx)
    return result.conditioning if isinstance(result, DynamicsAnalysis) else None


def _is_singular(c: Conditioning) -> bool:
    return c.smallest <= SINGULAR_RATIO * c.largest


def _where_joint(ctx: CheckContext, name: str) -> tuple[Span | None, str]:
    """Span and element path of a joint, or of the root link for the floating base."""
    joint = ctx.robot.joint(name)
    if joint is not None:
        return joint.span, f"joint[{name}]"
    root = ctx.robot.link(ctx.tree.root or "")
    return (root.span if root else ctx.robot.span), f"link[{ctx.tree.root}]"


def _pose_text(sample: int) -> str:
    return "at the zero configuration" if sample == 0 else f"at sampled configuration {sample}"


def _conditioning_data(c: Conditioning) -> dict[str, Any]:
    return {"condition_number": c.condition, "smallest_eigenvalue": c.smallest,
            "largest_eigenvalue": c.largest, "light_joint": c.light_joint, "heavy_joint": c.heavy_joint,
            "sample": c.sample, "configuration": rounded(c.configuration)}


def _joint_label(name: str) -> str:
    return name if name == "the floating base" else f"joint '{name}'"


@register
class MassMatrixSingular(_Dynamics):
    """Some motion of the robot moves no mass: the joint-space mass matrix is singular.

    ## What it does
    Builds the robot in Pinocchio (a free-flyer base for robots with wheels or
    legs), computes the mass matrix M(q) at the zero configuration and at
    seeded random configurations within the joint limits, and reports the
    first one whose smallest eigenvalue is at most 1e-12 of its largest. The
    finding names the joint that moves most along that eigenvector.

    ## Why it matters
    Forward dynamics solves M(q) q̈ = τ. A singular M has no solution: a joint
    that moves nothing accelerates without bound under the smallest torque,
    MuJoCo refuses or explodes, Gazebo and PyBullet produce NaN. The usual
    causes are a massless link on a moving joint, or a chain of massless links
    between joints whose axes can line up.

    ## Example
    ```xml
    <joint name="finger" type="revolute">
      <parent link="hand"/><child link="fingertip"/>
      <axis xyz="0 0 1"/><limit lower="0" upper="1" effort="1" velocity="1"/>
    </joint>
    <link name="fingertip"/>
    ```

    ## Fix
    Give every link that moves its real mass and inertia (see
    `missing-inertial` and `zero-mass`). For massless intermediate links
    (three revolute joints that form a ball joint), give them a small inertia
    or use one spherical joint.
    """

    code = "D001"
    name = "mass-matrix-singular"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        c = _conditioning(ctx)
        if c is None or not _is_singular(c):
            return
        span, element = _where_joint(ctx, c.light_joint)
        yield self.diagnostic(
            f"the mass matrix is singular {_pose_text(c.sample)}: smallest eigenvalue {fmt(c.smallest)} "
            f"of largest {fmt(c.largest)}, along a motion mostly of {_joint_label(c.light_joint)} "
            "(it moves no mass)",
            span, element=element,
            help="give the links this joint moves their mass and inertia",
            data=_conditioning_data(c))


@register
class MassMatrixIllConditioned(_Dynamics):
    """The joint-space mass matrix is ill-conditioned in some sampled pose.

    ## What it does
    Computes the condition number (largest over smallest eigenvalue) of the
    mass matrix M(q) at the zero configuration and seeded random
    configurations within the joint limits, and reports the worst when it is
    above 1e8 (and the matrix is not singular). The finding names the joint
    that moves most along the lightest direction, and gives the pose in `data`.

    ## Why it matters
    A condition number of 1e8 means one direction of motion is a hundred
    million times lighter than another. Simulators with a fixed timestep then
    need tiny steps or jitter: the light joint is thrown about by the
    contact and coupling forces of the heavy ones. The cause is nearly always
    a placeholder inertia (1e-9 kg·m² on a real part) or a massless chain.

    ## Example
    ```xml
    <link name="hand">
      <inertial><mass value="1e-6"/>
        <inertia ixx="1e-12" ixy="0" ixz="0" iyy="1e-12" iyz="0" izz="1e-12"/></inertial>
    </link>
    ```

    ## Fix
    Use the link's real mass and inertia (CAD, or the formula of its shape);
    `inertia-geometry-mismatch` gives the tensor of its geometry.
    """

    code = "D002"
    name = "mass-matrix-ill-conditioned"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        c = _conditioning(ctx)
        if c is None or _is_singular(c) or c.condition <= CONDITION_LIMIT:
            return
        span, element = _where_joint(ctx, c.light_joint)
        yield self.diagnostic(
            f"the mass matrix is ill-conditioned {_pose_text(c.sample)}: condition number "
            f"{c.condition:.2g} (limit {CONDITION_LIMIT:.0e}); the lightest motion is mostly of "
            f"{_joint_label(c.light_joint)} (eigenvalue {fmt(c.smallest)}), the heaviest of "
            f"{_joint_label(c.heavy_joint)} ({fmt(c.largest)})",
            span, element=element,
            help="check the inertia of the links this joint moves: a placeholder tensor is the usual cause",
            data={**_conditioning_data(c), "limit": CONDITION_LIMIT})


@register
class GravityTorqueExceedsEffort(_Dynamics):
    """A joint of a fixed-base robot cannot hold its links against gravity.

    ## What it does
    For robots fixed to the world, computes with Pinocchio the static gravity
    torque g(q) each joint needs to hold the robot still (gravity 9.81 m/s²
    along -z of the root frame), at the zero configuration and at seeded
    random configurations within the limits, and reports every joint whose
    largest torque exceeds its `<limit effort>`. The pose and torque are in
    `data`. A joint that others mimic holds their load too.

    ## Why it matters
    Simulators clamp motor torques at `effort`: a joint that needs more sags
    under its own weight, a position controller never reaches its target,
    and a gravity-compensation controller saturates. Either the effort is
    wrong (a placeholder, the wrong unit, a value per motor instead of after
    the gearbox) or the masses are.

    ## Example
    A 1 m, 5 kg horizontal link on a joint limited to 10 N·m needs
    5 kg · 9.81 m/s² · 0.5 m = 24.5 N·m:
    ```xml
    <joint name="shoulder" type="revolute">
      <axis xyz="0 1 0"/><limit lower="-1.57" upper="1.57" effort="10" velocity="2"/>
    </joint>
    ```

    ## Fix
    Write the effort the joint really has (after the gearbox), or correct the
    masses of the links it carries. Springs or counterweights that are not in
    the model are a reason to ignore this rule for that robot.
    """

    code = "D003"
    name = "gravity-torque-exceeds-effort"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        result = analysis(ctx)
        if not isinstance(result, DynamicsAnalysis):
            return
        for load in result.gravity:
            limit = load.joint.limit
            effort = limit.effort if limit is not None else None
            if effort is None or effort <= 0 or load.torque <= effort * (1 + EFFORT_MARGIN):
                continue
            yield self._finding(load, effort)

    def _finding(self, load: GravityLoad, effort: float) -> Diagnostic:
        joint = load.joint
        unit = "N" if joint.type is JointType.PRISMATIC else "N·m"
        return self.diagnostic(
            f"joint '{joint.name}' needs {load.torque:.3g} {unit} to hold against gravity "
            f"{_pose_text(load.sample)}, limit {effort:g} {unit}",
            joint.span, element=f"joint[{joint.name}]",
            help=f"raise <limit effort> to at least {load.torque:.3g} {unit} if the actuator has it, "
                 "or check the masses of the links it carries",
            data={"joint": joint.name, "torque": load.torque, "effort": effort, "unit": unit,
                  "gravity": GRAVITY, "sample": load.sample, "configuration": rounded(load.configuration)})


@register
class DynamicsNotChecked(_Dynamics):
    """The dynamics pass could not check this model, or only part of it.

    ## What it does
    Says once per model why the mass matrix and gravity checks did not run:
    physically invalid inertia (negative mass, a tensor that is not positive
    definite or breaks A + B ≥ C, already reported by the inertia rules),
    several roots, or joint types without a rigid-body model here (universal,
    revolute2, screw, gearbox). For a fixed-base robot with closed chains it
    says that gravity torques were not checked.

    ## Why it matters
    Dynamics computed from inertia that belongs to no real body are numbers
    without a robot behind them; reporting them would bury the real cause. A
    silent skip would read as "passed".

    ## Example
    ```xml
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.3"/>
    ```

    ## Fix
    Fix the findings of the inertia rules; the dynamics are checked on the
    next run.
    """

    code = "D004"
    name = "dynamics-not-checked"
    severity = Severity.INFO

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        result = analysis(ctx)
        if isinstance(result, Skipped):
            first = result.why.elements[0] if result.why.elements else None
            span, element = self._where(ctx, first)
            yield self.diagnostic(f"dynamics not checked: {result.why.reason}", span, element=element,
                                  data={"reason": result.why.reason, "elements": list(result.why.elements)})
        elif isinstance(result, DynamicsAnalysis) and not result.dense:
            done = "gravity loads checked with the linear-time pass" if result.gravity_computed else \
                "nothing else computed"
            limit = int(budget("dynamics-dof"))
            yield self.diagnostic(
                f"mass-matrix conditioning not checked: {result.dof} moving degrees of freedom, over the "
                f"{limit} the dense pass handles; {done}",
                ctx.robot.span,
                element="robot",
                help=how_to_raise("dynamics-dof") + " (the dense pass's memory grows about as DOF³)",
                data={"reason": "size", "dof": result.dof, "limit": limit},
            )
        elif isinstance(result, DynamicsAnalysis) and not result.floating and ctx.robot.loop_closures \
                and result.dof:
            closing = ctx.robot.loop_closures[0].joint
            yield self.diagnostic(
                f"gravity torques not checked: joint '{closing.name}' closes a kinematic loop, which "
                "carries part of the load",
                closing.span,
                element=f"joint[{closing.name}]",
                data={
                    "reason": "closed chain",
                    "elements": [lc.joint.name for lc in ctx.robot.loop_closures],
                },
            )

    @staticmethod
    def _where(ctx: CheckContext, name: str | None) -> tuple[Span | None, str | None]:
        link = ctx.robot.link(name) if name else None
        if link is not None:
            inertial = link.inertial
            return (inertial.span if inertial and inertial.span else link.span), f"link[{link.name}]"
        joint = ctx.robot.joint(name) if name else None
        if joint is not None:
            return joint.span, f"joint[{joint.name}]"
        return ctx.robot.span, None
