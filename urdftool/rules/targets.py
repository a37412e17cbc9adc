"""Consumers (T): what each program asked for with ``check --target`` will do with this file.

Each rule reads the consumer tables of :mod:`urdftool.targets` for the targets
of the run (``ctx.options["targets"]``, a tuple of names); without targets
these rules report nothing. Every finding names the consumer and the effect on
this file, and carries ``data["target"]``. Mesh contents come from the mesh
survey facts (:mod:`urdftool.facts.meshes`, :mod:`urdftool.facts.mesh_shape`).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping

from urdftool.catalogue.registry import Family, Rule, register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts.companions import srdf_files
from urdftool.facts.context import CheckContext
from urdftool.model import Box, Joint, JointType, Link, Mesh, Sphere
from urdftool.physics.inertia import principal_moments
from urdftool.physics.massprops import geometry_properties
from urdftool.targets import TARGETS, Target

#: A hull the mesh fills less than this is reported (info); below HULL_WARN, a warning.
HULL_NOTE = 0.75
HULL_WARN = 0.5
#: PyBullet's inertia from the collision shapes is reported when a principal moment differs
#: from the file's by more than this factor.
INERTIA_FACTOR = 2.0


def targets(ctx: CheckContext) -> list[Target]:
    """The targets of this run, in the order given."""
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


def _descendants(ctx: CheckContext, link: str) -> list[str]:
    out: list[str] = []
    todo = list(ctx.tree.children(link))
    while todo:
        name = todo.pop()
        if name in out:
            continue
        out.append(name)
        todo.extend(ctx.tree.children(name))
    return out


def _lumped_mass(ctx: CheckContext, link: str) -> float:
    """The mass of *link* with every link hanging from it by fixed joints (Gazebo's lumping)."""
    links = {lk.name: lk for lk in ctx.robot.links}
    total, todo, seen = 0.0, [link], set()
    while todo:
        name = todo.pop()
        if name in seen or name not in links:
            continue
        seen.add(name)
        inertial = links[name].inertial
        total += inertial.mass if inertial is not None and inertial.mass > 0 else 0.0
        todo.extend(j.child for j in ctx.robot.joints if j.parent == name and j.type is JointType.FIXED)
    return total


def _collision_volume(link: Link) -> float | None:
    """The summed volume (m³) of the link's collision shapes, ``None`` when one is unknown."""
    total = 0.0
    for item in link.collisions:
        solid = geometry_properties(item.geometry)
        if solid is None:
            return None
        total += solid.volume
    return total


def _open_collision_mesh(link: Link) -> str | None:
    """The file name of the first collision mesh of *link* that is not a closed surface (its
    volume was measured by its convex hull), else ``None``."""
    for item in link.collisions:
        if isinstance(item.geometry, Mesh):
            solid = geometry_properties(item.geometry)
            if solid is not None and solid.approximate:
                return item.geometry.filename
    return None


def _link_at(link: Link) -> tuple[object, str]:
    return link.span, f"link[{link.name}]"


@register
class TargetDefaultMass(_Targets):
    """A consumer fills in the mass of a link that has none.

    ## What it does
    For each target of `--target`, reports links without `<inertial>` (or
    with zero mass) and what the consumer gives them: PyBullet 1 kg; MuJoCo
    and Isaac Sim the mass of the collision geometry at 1000 kg/m³ (when a
    collision mesh is not closed, no number: the volume of an open mesh is not
    the part's; MuJoCo gives a lidless 2 kg box 1.61 kg); Pinocchio,
    KDL and Drake zero; Gazebo (classic and gz-sim) leaves the link out, with
    every link below it, when the link is not attached by a fixed joint.
    Drake also floats a root link that is not welded to the world, and stops
    a simulation whose mass matrix a massless link leaves singular: a warning
    when the link is not welded to its parent and nothing on fixed joints
    below it carries mass.

    ## Why it matters
    The same file then weighs different amounts in each program: a sensor
    mount that weighs nothing in RViz weighs 1 kg in PyBullet, in Gazebo
    the arm below a massless link simply disappears, and in Drake the first
    simulation step stops with "mass matrix ... is not positive-definite".

    ## Example
    ```xml
    <link name="arm"><collision>…</collision></link>  <!-- no <inertial> -->
    ```

    ## Fix
    Give every link that moves an `<inertial>` with its real mass and inertia
    (`urdftool check` rule `missing-inertial` suggests one from the geometry).
    """

    code = "T001"
    name = "target-default-mass"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        for target in targets(ctx):
            if target.missing_inertial is None:
                continue
            for link in ctx.robot.links:
                if link.name == "world":
                    continue
                massless = link.inertial is None or link.inertial.mass == 0
                if not massless:
                    continue
                found = self._effect(ctx, target, link)
                if found is not None:
                    yield found

    def _zero(
        self, ctx: CheckContext, target: Target, link: Link, what: str, data: Mapping[str, object]
    ) -> Diagnostic:
        """Zero mass and inertia; for Drake, a simulation that stops when nothing below carries mass."""
        floats = target.floating_root and link.name == ctx.tree.root
        parent = _parent_joint(ctx, link.name)
        joined = floats or (parent is not None and parent.type is not JointType.FIXED)  # not welded
        stops = target.massless_stops and joined and _lumped_mass(ctx, link.name) == 0
        message = f"{target.label} will give link '{link.name}' zero mass and inertia (it {what})"
        if floats:
            message += " and make it a free body unless it is welded to the world"
        if stops:
            message += "; a simulation stops at its first step (a mass matrix that is not positive-definite)"
            if ctx.tree.children(link.name):
                message += " unless the links below it carry inertia about each way it moves"
        return self.diagnostic(
            message, link.span, element=f"link[{link.name}]",
            severity=Severity.WARNING if stops else Severity.INFO,
            help="give the link an <inertial> if it carries any mass"
            + (" (or weld it to the world: plant.WeldFrames)" if floats else ""),
            data={**data, "mass": 0.0, "floats": floats, "stops": stops},
        )

    def _effect(self, ctx: CheckContext, target: Target, link: Link) -> Diagnostic | None:
        kind = target.missing_inertial
        what = "has no <inertial>" if link.inertial is None else "has zero mass"
        data = {"target": target.name, "link": link.name, "effect": kind}
        if kind == "dropped":
            parent = _parent_joint(ctx, link.name)
            if parent is not None and parent.type is JointType.FIXED:
                return None  # lumped into its parent, not dropped
            if _lumped_mass(ctx, link.name) > 0:
                return None  # links on fixed joints below it are lumped in first and give it mass
            below = _descendants(ctx, link.name)
            tail = f", with the {len(below)} link(s) below it" if below else ""
            return self.diagnostic(
                f"{target.label} will leave link '{link.name}' out of the model{tail} "
                f"(it {what}; the URDF-to-SDF conversion drops such links)",
                link.span, element=f"link[{link.name}]", severity=Severity.ERROR,
                help="give the link an <inertial> with a positive mass",
                data={**data, "dropped": [link.name, *below]},
            )
        if kind == "one-kg":
            if link.inertial is not None:  # PyBullet keeps an explicit zero (a static base)
                return None
            return self.diagnostic(
                f"{target.label} will give link '{link.name}' mass 1 kg (it {what}), "
                "with an inertia computed from its collision shapes",
                link.span, element=f"link[{link.name}]", help="give the link an <inertial>",
                data={**data, "mass": 1.0},
            )
        if not _moving(ctx, link.name, target):
            return None
        if kind == "zero":
            return self._zero(ctx, target, link, what, data)
        open_mesh = _open_collision_mesh(link)
        if open_mesh is not None:
            return self.diagnostic(
                f"{target.label} will give link '{link.name}' a mass computed from its collision "
                f"mesh '{open_mesh}', which is not closed: the volume of an open mesh is not the "
                f"part's, so neither is the mass (it {what})",
                link.span, element=f"link[{link.name}]",
                help="give the link an <inertial>, or close the mesh",
                data={**data, "mass": None, "open_mesh": open_mesh},
            )
        volume = _collision_volume(link)
        if volume is None or volume <= 0:
            return None
        mass = 1000.0 * volume
        return self.diagnostic(
            f"{target.label} will give link '{link.name}' the mass of its collision geometry at "
            f"1000 kg/m³: {mass:.3g} kg (it {what})",
            link.span, element=f"link[{link.name}]", help="give the link an <inertial>",
            data={**data, "mass": mass, "volume": volume},
        )


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


@register
class TargetInertiaFromCollision(_Targets):
    """PyBullet replaces a link's inertia by one computed from its collision shapes.

    ## What it does
    With `--target pybullet`, predicts the inertia PyBullet's `loadURDF`
    uses without the `URDF_USE_INERTIA_FROM_FILE` flag (that of the link's
    collision box or sphere at the link's mass, and nearly zero for a link
    without collision shapes) and reports links where a principal moment
    differs from the file's by more than a factor of 2.

    ## Why it matters
    A link's rotational dynamics in PyBullet are then not those written in
    the file: a sensor head without collision shapes spins freely, a
    long link with a small collision box swings too fast.

    ## Example
    A camera link with an `<inertial>` and no `<collision>`.

    ## Fix
    Load with `p.loadURDF(path, flags=p.URDF_USE_INERTIA_FROM_FILE)`.
    """

    code = "T010"
    name = "target-inertia-from-collision"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        if not any(t.inertia_from_collision for t in targets(ctx)):
            return
        for link in ctx.robot.links:
            inertial = link.inertial
            if inertial is None or inertial.mass <= 0:
                continue
            predicted = _bullet_inertia(link, inertial.mass)
            if predicted is None:
                continue
            moments, _ = principal_moments(inertial.inertia_matrix)
            written = sorted(abs(float(v)) for v in moments)
            if min(written) <= 0:
                continue
            ratios = [max(p, 1e-300) / w for p, w in zip(sorted(predicted), written, strict=True)]
            if all(1 / INERTIA_FACTOR <= r <= INERTIA_FACTOR for r in ratios):
                continue
            shown = ", ".join(f"{v:.3g}" for v in predicted)
            yield self.diagnostic(
                f"PyBullet will give link '{link.name}' the inertia of its collision shapes "
                f"(diagonal {shown} kg·m²) instead of the file's, unless loaded with "
                "URDF_USE_INERTIA_FROM_FILE",
                link.span, element=f"link[{link.name}]",
                help="load it with flags=p.URDF_USE_INERTIA_FROM_FILE",
                data={"target": "pybullet", "link": link.name, "predicted": list(predicted)},
            )


def _bullet_inertia(link: Link, mass: float) -> tuple[float, float, float] | None:
    """Bullet's local inertia for the link's collision shape, where it can be predicted exactly."""
    if not link.collisions:
        return (0.0, 0.0, 0.0)  # an empty compound: Bullet's near-zero inertia
    if len(link.collisions) != 1:
        return None
    geometry = link.collisions[0].geometry
    if isinstance(geometry, Sphere):
        value = 0.4 * mass * geometry.radius**2
        return (value, value, value)
    if isinstance(geometry, Box):
        x, y, z = geometry.size
        return (mass * (y * y + z * z) / 12, mass * (x * x + z * z) / 12, mass * (x * x + y * y) / 12)
    return None
