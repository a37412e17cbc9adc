"""Consumers (T): what each program asked for with ``check --target`` will do with this file.

Each rule reads the consumer tables of :mod:`urdftool.targets` for the targets
of the run (``ctx.options["targets"]``, a tuple of names); without targets,
or on a model read from SDF (the tables describe URDF readers), these rules
report nothing. Every finding names the consumer and the effect on
this file, and carries ``data["target"]``. Mesh contents come from the mesh
survey facts (:mod:`urdftool.facts.meshes`, :mod:`urdftool.facts.mesh_shape`).
"""

from __future__ import annotations

from collections.abc import Iterator

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts.companions import srdf_files
from urdftool.facts.context import CheckContext
from urdftool.model import Joint, JointType
from urdftool.targets import TARGETS, Target

#: A hull the mesh fills less than this is reported (info); below HULL_WARN, a warning.
HULL_NOTE = 0.75
HULL_WARN = 0.5


def targets(ctx: CheckContext) -> list[Target]:
    """The targets of this run, in the order given; none for a model read from SDF.

    The tables describe URDF readers. An SDF file is read by SDFormat itself (gz-sim, Gazebo,
    Drake): a link without ``<inertial>`` gets SDFormat's default of 1 kg, and no URDF-to-SDF
    conversion drops it or lumps fixed joints; the URDF tables would report effects that do not
    happen (on gz-sim's example worlds, 20 false errors).
    """
    if ctx.robot.format == "sdf":
        return []
    names = ctx.options.get("targets") or ()
    return [TARGETS[n] for n in names if n in TARGETS]


class _Targets(Rule):
    family = Family.TARGETS


def _pct(value: float) -> str:
    return f"{100 * value:.0f} %"


def _moving(ctx: CheckContext, link: str, target: Target | None = None) -> bool:
    """The link moves relative to the root (a non-fixed joint between them), or floats with it."""
    if target is not None and target.floating_root and link == ctx.tree.root:
        return True
    return any(j.type is not JointType.FIXED for j in ctx.tree.path_to_root(link))


def _parent_joint(ctx: CheckContext, link: str) -> Joint | None:
    path = ctx.tree.path_to_root(link)
    return path[0] if path else None


@register
class TargetFusesFixedJoints(_Targets):
    """A consumer merges the links joined by a fixed joint.

    ## What it does
    For each target of `--target` that does it, reports each fixed joint
    whose child link will not exist as a body of its own: MuJoCo fuses it into
    its parent body, Gazebo (classic and gz-sim) lumps its inertia and shapes
    into the parent link, Pinocchio turns it into a frame of its parent body.

    ## Why it matters
    Code that looks the link up by name (a sensor, a plugin, a contact
    callback, an end-effector body) finds nothing, and the parent's mass and
    inertia change.

    ## Example
    ```xml
    <joint name="tool_mount" type="fixed"><parent link="arm"/><child link="tool"/></joint>
    ```

    ## Fix
    Nothing, when the merge is wanted. To keep the link: MuJoCo
    `<mujoco><compiler fusestatic="false"/></mujoco>`, Gazebo
    `<preserveFixedJoint>true</preserveFixedJoint>` in the joint's `<gazebo>`
    block, Pinocchio `model.getFrameId("tool")`.
    """

    code = "T002"
    name = "target-fuses-fixed-joints"
    severity = Severity.INFO

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        chosen = [t for t in targets(ctx) if t.fixed_joints is not None]
        if not chosen:
            return
        for joint in ctx.robot.joints:
            if joint.type is not JointType.FIXED or joint.parent == "world":
                continue
            for target in chosen:
                verb = {
                    "fused": f"fuse link '{joint.child}' into the body of '{joint.parent}'",
                    "lumped": f"lump link '{joint.child}' into '{joint.parent}' and drop the link",
                    "frames": f"make link '{joint.child}' a frame of '{joint.parent}', adding its "
                    "inertia to it",
                }[target.fixed_joints or ""]
                if target.name in ("gazebo", "gz-sim") and _preserved(ctx, joint):
                    continue
                yield self.diagnostic(
                    f"{target.label} will {verb} (fixed joint '{joint.name}')",
                    joint.span, element=f"joint[{joint.name}]",
                    help=f"to keep it as a body: {target.keep_fixed.replace('JOINT', joint.name)}"
                    if target.keep_fixed else None,
                    data={"target": target.name, "joint": joint.name, "child": joint.child,
                          "effect": target.fixed_joints},
                )


def _preserved(ctx: CheckContext, joint: Joint) -> bool:
    """A ``<gazebo reference="joint">`` block keeps the joint (preserveFixedJoint)."""
    for ext in ctx.robot.extensions:
        if ext.tag != "gazebo" or ext.attributes.get("reference") != joint.name or ext.element is None:
            continue
        for child in ext.element.iter():
            if str(child.tag) in ("preserveFixedJoint", "disableFixedJointLumping") and (
                (child.text or "").strip().lower() in ("true", "1")
            ):
                return True
    return False


@register
class TargetIgnoresMimic(_Targets):
    """A consumer does not couple a `<mimic>` joint to the joint it follows.

    ## What it does
    For each target of `--target`, reports `<mimic>` elements the consumer
    ignores (PyBullet, KDL), needs a plugin for (Gazebo classic) or honours
    only when asked (Pinocchio's `mimic=True`) or only in some plants (Drake:
    a discrete plant with the SAP solver, its default, couples the joints; the
    TAMSI solver ignores the `<mimic>`, and a continuous plant stops at its
    first step).

    ## Why it matters
    The follower becomes an independent joint: a gripper's second finger
    hangs loose in simulation and inverse kinematics moves it on its own.

    ## Example
    ```xml
    <mimic joint="left_slide" multiplier="1"/>
    ```

    ## Fix
    PyBullet: `createConstraint(..., JOINT_GEAR, ...)` between the joints;
    Gazebo classic: a mimic joint plugin; Pinocchio:
    `buildModelFromUrdf(path, mimic=True)`; Drake: a discrete plant
    (`time_step > 0`) with the SAP solver (the default approximation
    `lagged`, or `sap` or `similar`).
    """

    code = "T004"
    name = "target-ignores-mimic"
    severity = Severity.WARNING

    def _discrete_only(self, target: Target, joint: Joint) -> Diagnostic:
        assert joint.mimic is not None
        return self.diagnostic(
            f"{target.label} will couple joint '{joint.name}' to '{joint.mimic.joint}' (its <mimic>) only "
            "in a discrete plant with the SAP solver (the default): the TAMSI solver ignores the <mimic> "
            "and a continuous plant (time_step 0) stops at its first step",
            joint.mimic.span or joint.span, element=f"joint[{joint.name}]/mimic", severity=Severity.INFO,
            help="simulate it in a discrete plant (time_step > 0) with the SAP solver",
            data={"target": target.name, "joint": joint.name, "leader": joint.mimic.joint,
                  "effect": target.mimic},
        )

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        chosen = [t for t in targets(ctx) if t.mimic is not None]
        for joint in ctx.robot.joints:
            if joint.mimic is None:
                continue
            for target in chosen:
                if target.mimic == "discrete-only":
                    yield self._discrete_only(target, joint)
                    continue
                unless = {
                    "ignored": "",
                    "needs-plugin": " unless a mimic joint plugin couples it",
                    "needs-option": " unless asked to honour it (mimic=True)",
                }[target.mimic or ""]
                yield self.diagnostic(
                    f"{target.label} will ignore the <mimic> of joint '{joint.name}' "
                    f"(following '{joint.mimic.joint}'){unless}: the joint moves on its own",
                    joint.mimic.span or joint.span, element=f"joint[{joint.name}]/mimic",
                    severity=Severity.INFO if target.mimic == "needs-option" else Severity.WARNING,
                    data={"target": target.name, "joint": joint.name, "effect": target.mimic},
                )


@register
class TargetJointType(_Targets):
    """A consumer welds or reinterprets a joint type.

    ## What it does
    For each target of `--target`, reports joints of a type the consumer does
    not read as URDF means it: PyBullet welds `floating` joints, KDL welds
    `floating` and `planar` joints, Pinocchio gives a `continuous` joint two
    configuration variables (cos θ, sin θ), Drake drops a `floating` joint
    and leaves its child a free body (not attached to the parent, at the
    world origin).

    ## Why it matters
    A welded joint no longer moves; a continuous joint with two configuration
    variables breaks code that indexes `q` by joint.

    ## Example
    ```xml
    <joint name="loose" type="floating">…</joint>
    ```

    ## Fix
    Use joint types the consumer supports (a floating base is the root link
    itself, not a joint); in Pinocchio, index `q` through `model.idx_qs`.
    """

    code = "T005"
    name = "target-joint-type"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for joint in ctx.robot.joints:
            for target in targets(ctx):
                effect = target.joint_types.get(joint.type.value)
                if effect is None:
                    continue
                lost = effect in ("fixed", "free")  # the joint no longer moves as written
                kind = joint.type.value
                if effect == "fixed":
                    message = f"{target.label} will weld {kind} joint '{joint.name}' (a fixed joint)"
                elif effect == "free":
                    message = (
                        f"{target.label} will drop {kind} joint '{joint.name}' and make link "
                        f"'{joint.child}' a free body, not attached to '{joint.parent}'"
                    )
                else:
                    message = f"{target.label} will give {kind} joint '{joint.name}' {effect}"
                yield self.diagnostic(
                    message, joint.span, element=f"joint[{joint.name}]",
                    severity=Severity.WARNING if lost else Severity.INFO,
                    data={"target": target.name, "joint": joint.name, "type": kind,
                          "child": joint.child, "effect": effect},
                )


@register
class TargetRootInertia(_Targets):
    """KDL drops the inertia of the root link.

    ## What it does
    With `--target kdl`, reports a root link with an `<inertial>`.

    ## Why it matters
    kdl_parser cannot give the root segment an inertia: it warns and drops
    it, so KDL's dynamics (and every controller built on KDL, as in
    ros_control's chain solvers) miss that mass.

    ## Example
    ```xml
    <link name="base_link"><inertial><mass value="4"/>…</inertial></link>  <!-- the root -->
    ```

    ## Fix
    Add a massless root link (`base_footprint` or `root`) joined to it by
    a fixed joint.
    """

    code = "T008"
    name = "target-root-inertia"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        chosen = [t for t in targets(ctx) if t.root_inertia_ignored]
        root = ctx.tree.root
        link = next((lk for lk in ctx.robot.links if lk.name == root), None)
        if not chosen or link is None or link.inertial is None or link.inertial.mass == 0:
            return
        for target in chosen:
            yield self.diagnostic(
                f"{target.label} will drop the {link.inertial.mass:g} kg inertia of root link "
                f"'{link.name}' (a root segment has no inertia)",
                link.span, element=f"link[{link.name}]",
                help="add a massless root link joined to it by a fixed joint",
                data={"target": target.name, "link": link.name, "mass": link.inertial.mass},
            )


@register
class TargetNeedsSrdf(_Targets):
    """MoveIt needs a semantic description (SRDF) beside the URDF.

    ## What it does
    With `--target moveit`, reports a robot with no `.srdf` file in its
    folder, in `../srdf/` or in `../config/` (or given with `srdf` in the
    run's options).

    ## Why it matters
    MoveIt plans for groups, end effectors and a self-collision matrix that
    only the SRDF defines; without one, every link pair is checked for
    collision and no planning group exists.

    ## Example
    `arm.urdf` alone in its folder.

    ## Fix
    Generate one with the MoveIt Setup Assistant, or start from
    `urdftool collisions arm.urdf -o arm.srdf`.
    """

    code = "T009"
    name = "target-needs-srdf"
    severity = Severity.INFO

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for target in targets(ctx):
            if target.needs_srdf and not srdf_files(ctx):
                yield self.diagnostic(
                    f"{target.label} needs an SRDF for robot '{ctx.robot.name}': none found beside the file",
                    None, help="create one with the MoveIt Setup Assistant",
                    data={"target": target.name},
                )


