"""Runtime (R): verdicts of the bundled smoke simulation.

These rules read the simulation fact (:func:`urdftool.facts.simulation.simulation`,
computed once per robot by the simulator the pipeline installs). They run only
when the simulation is asked for: ``urdftool sim``, ``check --sim``, or the
``simulate`` function of the Python API. Each finding names its engine; the
engine's summary is in ``data["summary"]``. Thresholds and the reasons for them
are in ``docs/sim.md``.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts.context import CheckContext
from urdftool.facts.simulation import display_name, simulation
from urdftool.model import Joint, JointType, Robot
from urdftool.physics.describe import fmt
from urdftool.source import Span

if TYPE_CHECKING:
    from urdftool.facts.simulation.record import EngineRun, LimitViolation

#: A joint faster than this (rad/s, or m/s for prismatic joints) has blown up.
JOINT_SPEED_LIMIT = 100.0
#: A base faster than this (m/s) has blown up: more than 2.5 s of free fall.
BASE_SPEED_LIMIT = 25.0
#: Energy may not rise above its start by more than this fraction of m·g·size.
ENERGY_GROWTH_LIMIT = 0.5
#: A mobile robot still moving faster than this (m/s, mean over the last 10 % of the run) …
DRIFT_SPEED = 0.01
#: … or travelling further than this (m) over the second half has not settled.
DRIFT_DISTANCE = 0.02
#: With --hold, a joint still moving faster than this (rad/s or m/s) at the end has not settled.
HOLD_DRIFT_SPEED = 0.05
#: How far (rad, or m for prismatic joints) beyond a limit counts as a violation: MuJoCo's
#: soft limits and PyBullet's limit constraints both let a loaded joint sink a little.
LIMIT_TOLERANCE = {JointType.REVOLUTE: 0.1, JointType.PRISMATIC: 0.01}


class _Runtime(Rule):
    family = Family.RUNTIME


def _runs(ctx: CheckContext) -> Iterator[EngineRun]:
    result = simulation(ctx)
    if result is not None:
        yield from (run for run in result.runs if run.ran)


def _root_span(ctx: CheckContext) -> tuple[Span | None, str | None]:
    root = ctx.robot.link(ctx.tree.root or "")
    return (root.span, f"link[{root.name}]") if root else (ctx.robot.span, None)


def _joint_span(ctx: CheckContext, name: str | None) -> tuple[Span | None, str | None]:
    joint = ctx.robot.joint(name) if name else None
    return (joint.span, f"joint[{joint.name}]") if joint else _root_span(ctx)


def unstable_because(run: EngineRun) -> str | None:
    """Why the run blew up, in words, or ``None``."""
    if run.diverged_at is not None:
        return f"the state became NaN/infinite at t = {run.diverged_at:.3f} s"
    if run.max_joint_speed > JOINT_SPEED_LIMIT:
        return (f"joint '{run.fastest_joint}' reached {fmt(run.max_joint_speed)} rad/s "
                f"(bound {JOINT_SPEED_LIMIT:g})")
    if run.max_base_speed > BASE_SPEED_LIMIT:
        return f"the base reached {fmt(run.max_base_speed)} m/s (bound {BASE_SPEED_LIMIT:g})"
    if run.energy_growth > ENERGY_GROWTH_LIMIT:
        return (f"the energy grew by {fmt(run.energy_max - run.energy_initial)} J, "
                f"{fmt(run.energy_growth)} × m·g·size (bound {ENERGY_GROWTH_LIMIT:g})")
    return None


def drift_because(run: EngineRun, floating: bool, hold: bool) -> str | None:
    """Why the robot has not come to rest, in words, or ``None``."""
    if unstable_because(run) is not None:
        return None
    if floating and (run.base_late_speed > DRIFT_SPEED or run.base_late_distance > DRIFT_DISTANCE):
        return (f"the base still moves at {fmt(run.base_late_speed)} m/s at the end and travelled "
                f"{fmt(run.base_late_distance)} m in the second half of the run")
    if not floating and hold and run.late_joint_speed > HOLD_DRIFT_SPEED:
        return (f"joint '{run.late_fastest_joint}' still moves at {fmt(run.late_joint_speed)} rad/s "
                "at the end, held at its start pose")
    return None


def beyond_limits(robot: Robot, run: EngineRun) -> list[tuple[Joint, LimitViolation]]:
    """The joints that went past a limit by more than the tolerance, with how far."""
    out = []
    for violation in run.limit_violations:
        joint = robot.joint(violation.joint)
        if joint is not None and violation.amount > LIMIT_TOLERANCE.get(joint.type, 0.1):
            out.append((joint, violation))
    return out


def _summary(run: EngineRun) -> dict[str, Any]:
    return {"engine": run.engine, "summary": run.summary()}


@register
class SimUnstable(_Runtime):
    """The robot blows up in simulation: NaN, runaway speeds, or energy from nowhere.

    ## What it does
    Simulates the robot for a few seconds (default 2 s) in MuJoCo and PyBullet
    from urdftool's own exports, with zero commands (joints held by their
    damping only), and reports a run whose state becomes NaN or infinite, a
    joint faster than 100 rad/s, a base faster than 25 m/s, or a total energy
    that rises above its start by more than half of m·g·size (the energy it
    takes to lift the robot by its own size).

    ## Why it matters
    A passive robot can only lose energy. A model that gains it, or whose
    joints spin up without a command, has a defect the engine cannot
    integrate: a link far too light for its neighbours, a tiny inertia on a
    fast joint, geometry that starts deep inside other geometry.

    ## Example
    A 1e-6 kg gripper finger on a 20 kg arm, or two links created overlapping.

    ## Fix
    Look at the joint the finding names and the links it moves: give them
    their real masses and inertias (see the `I` and `D` rules), remove
    overlaps (`sim-initial-penetration`).
    """

    code = "R001"
    name = "sim-unstable"
    severity = Severity.ERROR

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for run in _runs(ctx):
            why = unstable_because(run)
            if why is None:
                continue
            span, element = _joint_span(ctx, run.fastest_joint if "joint" in why else None)
            yield self.diagnostic(f"{display_name(run.engine)}: unstable: {why}", span, element=element,
                                  data=_summary(run))


@register
class SimInitialPenetration(_Runtime):
    """Links of the robot overlap in its start pose.

    ## What it does
    At the first step of the smoke simulation (home or zero pose), lists the
    pairs of links whose collision geometry overlaps by more than 1 mm, as
    each engine sees it (MuJoCo's contacts, PyBullet's closest points). Links
    that touch by construction are left out: links welded together by fixed
    joints, and links joined by a joint. An overlap the run does not simulate
    (PyBullet's, measured with self-collision on while the run keeps
    PyBullet's default, self-collision off) is reported as `info` and does not
    fail the verdict.

    ## Why it matters
    Overlapping geometry is pushed apart by the contact solver on the first
    step: the robot jumps, jitters, or explodes. MuJoCo collides every pair of
    bodies that are not parent and child, so this happens there as soon as
    the file is loaded; in PyBullet as soon as self-collision is turned on
    (`URDF_USE_SELF_COLLISION`), which a plain `loadURDF` does not do.

    ## Example
    A lidar cylinder placed 2 cm into the chassis box it sits on, mounted on
    a fixed joint to a mast rather than to the chassis.

    ## Fix
    Move or shrink the collision geometry so the links do not overlap at the
    start pose; simplify convex hulls that bulge into neighbours.
    """

    code = "R002"
    name = "sim-initial-penetration"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for run in _runs(ctx):
            if not run.penetrations:
                continue
            worst = run.penetrations[0]
            # Point at the link further down the tree: its placement is the likelier mistake.
            order = {name: i for i, name in enumerate(ctx.tree.order)}
            deeper = max((worst.link_a, worst.link_b), key=lambda name: order.get(name, -1))
            link = ctx.robot.link(deeper)
            collision = link.collisions[0] if link and link.collisions else None
            span = collision.span if collision and collision.span else (link.span if link else None)
            more = f" and {len(run.penetrations) - 1} more pair(s)" if len(run.penetrations) > 1 else ""
            # PyBullet runs without self-collision: a contact no run sees is information, not a defect
            unseen = "" if run.self_collision else (
                f"; not simulated: {display_name(run.engine)} loads without self-collision, and with "
                "URDF_USE_SELF_COLLISION its solver would push them apart")
            yield self.diagnostic(
                f"{display_name(run.engine)}: links '{worst.link_a}' and '{worst.link_b}' overlap by "
                f"{worst.depth * 1000:.1f} mm at the start{more}{unseen}",
                span, element=f"link[{deeper}]/collision",
                severity=None if run.self_collision else Severity.INFO,
                data={**_summary(run), "pairs": [[p.link_a, p.link_b, p.depth] for p in run.penetrations]})


@register
class SimDrift(_Runtime):
    """The robot keeps moving or sliding after it should have come to rest.

    ## What it does
    For a mobile robot dropped onto the ground, reports a base still moving
    faster than 1 cm/s over the last tenth of the run, or travelling more than
    2 cm over its second half. With `--hold` (PD at the start pose), also
    reports a fixed-base robot whose joints still move faster than 0.05 rad/s
    at the end. Base speed and distance are in `data`.

    ## Why it matters
    A robot standing still with no command should stay where it is. One that
    creeps ("slowly slips to its left") has wheels or casters whose contact,
    friction or mass distribution is wrong, and every localisation and
    control test built on it inherits the drift.

    ## Example
    A differential-drive robot whose caster is a sphere on a fixed joint
    touching the ground ahead of the wheels' axle, with friction 1 on one side.

    ## Fix
    Check the wheel and caster geometry and joints (a caster is a free
    spherical or two revolute joints, or frictionless), that the centre of
    mass lies between the contacts, and that wheels have damping.
    """

    code = "R003"
    name = "sim-drift"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        result = simulation(ctx)
        if result is None:
            return
        hold = bool(ctx.options.get("sim_hold"))
        for run in _runs(ctx):
            why = drift_because(run, result.scene.floating, hold)
            if why is None:
                continue
            span, element = (
                _root_span(ctx) if result.scene.floating else _joint_span(ctx, run.late_fastest_joint)
            )
            note = "" if hold else " (expected without actuators)"
            yield self.diagnostic(
                f"{display_name(run.engine)}: has not settled: {why}{note}", span, element=element,
                severity=None if hold else Severity.INFO,
                data={**_summary(run), "base_speed": run.base_late_speed,
                      "base_distance": run.base_late_distance, "joint_speed": run.late_joint_speed})


@register
class SimJointLimitViolation(_Runtime):
    """A joint goes beyond its limits in simulation.

    ## What it does
    Records every limited revolute and prismatic joint at every step of the
    smoke simulation and reports the furthest each one went past its lower
    or upper limit, when that is more than 0.1 rad (0.01 m for prismatic
    joints), with the time and position in `data`.

    ## Why it matters
    Engines enforce limits with soft constraints; a joint that passes them
    by degrees carries more load than its limit stiffness can take (a heavy
    link on a light joint), or starts outside its range. Controllers and
    collision checks that trust the limits will be wrong.

    ## Example
    A 5 kg arm resting on the lower limit of a joint whose child link has an
    inertia of 1e-6 kg·m².

    ## Fix
    Check the limits (radians, not degrees), the start pose, and the masses
    the joint carries.
    """

    code = "R004"
    name = "sim-joint-limit-violation"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        hold = bool(ctx.options.get("sim_hold"))
        for run in _runs(ctx):
            for joint, violation in beyond_limits(ctx.robot, run):
                unit = "m" if joint.type is JointType.PRISMATIC else "rad"
                side = "upper" if violation.position > violation.bound else "lower"
                note = "" if hold else "; nothing held it (no actuators)"
                yield self.diagnostic(
                    f"{display_name(run.engine)}: joint '{joint.name}' went {fmt(violation.amount)} {unit} "
                    f"past its {side} limit {fmt(violation.bound)} (at t = {violation.time:.2f} s){note}",
                    joint.span, element=f"joint[{joint.name}]",
                    severity=None if hold else Severity.INFO,
                    data={**_summary(run), "joint": joint.name, "amount": violation.amount,
                          "position": violation.position, "limit": violation.bound, "time": violation.time})


@register
class SimSummary(_Runtime):
    """The verdict and the numbers of each engine's smoke simulation.

    ## What it does
    Reports once per engine and robot what the smoke simulation measured:
    max joint speed, energy drift, final base displacement, initial
    penetration depth, the largest gap of a closed loop over the run (SDF
    loop closures in MuJoCo) and wall time (in `data["summary"]`), and the
    verdict in words. The verdict is "failed" for a defect only: a blow-up,
    overlap at the start that the run simulates, a loop that opens by more than 1 mm, or, with
    `--hold`, a robot that does not settle or passes a limit. When an
    exporter refuses the model (physically invalid inertia, a closed chain
    PyBullet cannot hold) or the engine is not installed, it says so, and
    the exporter's own findings are reported beside it.

    ## Why it matters
    A verdict that says "passed" with its numbers is evidence a CI log can
    keep; a silent pass is not. Tools read the summary from the JSON report.

    ## Example
    `urdftool sim arm.urdf --format json`.

    ## Fix
    Nothing to fix: this is information. Fix the other `R` findings it lists.
    """

    code = "R005"
    name = "sim-summary"
    severity = Severity.INFO

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        result = simulation(ctx)
        if result is None:
            return
        hold = bool(ctx.options.get("sim_hold"))
        for run in result.runs:
            name = display_name(run.engine)
            if run.unavailable:
                yield self.diagnostic(f"{name}: not simulated: {run.unavailable}", ctx.robot.span,
                                      data={**_summary(run), "verdict": "not simulated"})
                continue
            if run.refused:
                codes = ", ".join(sorted({d.code for d in run.refused}))
                yield self.diagnostic(f"{name}: not simulated: the export was refused ({codes})",
                                      ctx.robot.span, data={**_summary(run), "verdict": "not simulated"})
                yield from run.refused
                continue
            verdict = _verdict(ctx.robot, run, result.scene.floating, hold, result.scene.base_reason)
            yield self.diagnostic(f"{name}: {verdict}", ctx.robot.span,
                                  data={**_summary(run), "verdict": verdict.split(" ", 1)[0].rstrip(":")})


#: The largest gap (m) a closed loop may open during the smoke run before the verdict fails.
LOOP_TOLERANCE = 0.001


def _verdict(robot: Robot, run: EngineRun, floating: bool, hold: bool, base_reason: str = "") -> str:
    """"passed" or "failed (...)" with the numbers. Failed is for defects only: blow-ups and NaN,
    links overlapping at the start where the run simulates their contact, a closed loop that
    opens by more than LOOP_TOLERANCE, and, with actuators holding (``--hold``), not settling or
    going past a limit. Without actuators a fixed arm sags, a legged robot collapses and
    free wheels roll: that motion is expected and named after the verdict, never failed."""
    drift = drift_because(run, floating, hold)
    limits = beyond_limits(robot, run)
    loops_open = run.loop_gap is not None and run.loop_gap > LOOP_TOLERANCE
    problems = [name for name, found in (
        ("unstable", unstable_because(run)),
        ("penetrating at start", run.penetrations if run.self_collision else None),
        ("loops open", loops_open),
        ("not settled", drift if hold else None),
        ("past joint limits", limits if hold else None)) if found]
    expected = expected_motion(run, floating, hold, base_reason)
    unseen = " (self-collision off: not simulated)" if run.penetrations and not run.self_collision else ""
    numbers = (f"{run.steps} steps of {run.timestep * 1000:.3g} ms; max joint speed "
               f"{fmt(run.max_joint_speed)}, energy drift {fmt(run.energy_growth)}, base moved "
               f"{fmt(run.base_displacement)} m, penetration {run.penetration_depth * 1000:.1f} mm{unseen}"
               + (f", loop gap {run.loop_gap * 1000:.2f} mm" if run.loop_gap is not None else ""))
    head = "passed" if not problems else "failed (" + ", ".join(problems) + ")"
    if expected and not problems:
        head += f" ({expected})"
    return f"{head}: {numbers}"


def expected_motion(run: EngineRun, floating: bool, hold: bool, base_reason: str = "") -> str | None:
    """The motion a robot without actuators is expected to show, in words, when it showed it.

    *base_reason* is why the base is free (the MJCF export's decision: ``"auto: wheels"``,
    ``"auto: 4 legs"``, ...): legs fold, free wheels turn and roll, anything else settles."""
    if hold or unstable_because(run) is not None:
        return None
    moved = drift_because(run, floating, hold) is not None or bool(run.limit_violations) or (
        run.max_joint_speed > 0.05)
    if not moved:
        return None
    if not floating:
        return "expected without actuators: the arm sags under gravity"
    if "legs" in base_reason:
        return "expected without actuators: the free robot collapses"
    if "wheels" in base_reason:
        return "expected without actuators: the unpowered wheels turn as it settles"
    return "expected without actuators: the free robot settles under gravity"
