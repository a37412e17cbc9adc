"""PyBullet-ready URDF: the source robot as PyBullet's loader needs it to be the same robot.

Built on the plain URDF writer (:mod:`urdftool.export.urdf`), after preparing
the model:

* meshes: paths relative to OUT, DAE and other formats converted to OBJ,
  colours of converted meshes kept (:mod:`urdftool.export.pybullet_meshes`);
* inertia: an explicit ``<inertial>`` on every link, invalid tensors refused
  or repaired on request (:mod:`urdftool.export.pybullet_inertia`);
* joint axes written as unit vectors (PyBullet uses the vector as written, so
  a prismatic joint with axis ``0 0 2`` would move twice as far);
* the base: a robot that moves about (wheels, legs; ``--floating-base``, see
  :mod:`urdftool.physics.mobility`) whose root link is massless
  (``base_footprint``) is rooted at its heaviest fixed child instead, the old
  root kept as a massless fixed child, because PyBullet welds a base of mass 0
  to the world (:func:`plan_base`; reported as ``conversion-dropped`` info);
* fixed joints fused (``--fuse-fixed``, and automatically for a body with
  more joints than PyBullet can report): exact composite inertia, the fused
  frames listed in a comment (:mod:`urdftool.export.pybullet_fuse`);
* floating joints refused (PyBullet silently makes them fixed);
* mimic joints kept in the file but reported: PyBullet ignores ``<mimic>``;
  ``help`` gives the gear-constraint recipe that holds them (as ``sim`` applies
  it: :func:`urdftool.backends.pybullet.couple_mimics`).

A comment at the top of OUT records the source and how to load the file.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from lxml import etree

from urdftool.catalogue.conversion import ConversionDropped
from urdftool.catalogue.syntax import EmptyRobot
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.export import ExportOptions, ExportResult
from urdftool.export.assets import relative_reference
from urdftool.export.pybullet_fuse import Fusion, frames_comment, fuse_fixed
from urdftool.export.pybullet_inertia import PyBulletInertia, plan_inertia
from urdftool.export.pybullet_meshes import MeshPlan, mesh_key
from urdftool.export.urdf import URDF_JOINT_TYPES, UrdfFlavor, refusals, robot_element, to_bytes
from urdftool.model import Joint, JointType, KinematicTree, Mesh, Robot
from urdftool.physics.mobility import decide_base, reroot_massless_base
from urdftool.records import record
from urdftool.rules.syntax import MultipleRoots

#: The flag every PyBullet URDF from urdftool is meant to be loaded with.
LOAD_FLAGS = "p.URDF_USE_INERTIA_FROM_FILE"

#: The most joints of one body whose state PyBullet 3.2 can report (128 fails).
MAX_JOINTS = 127

PYBULLET_JOINT_TYPES: dict[JointType, str] = {
    t: name for t, name in URDF_JOINT_TYPES.items() if t is not JointType.FLOATING
}
PYBULLET_JOINT_TYPES[JointType.SPHERICAL] = "spherical"


@record
class PyBulletFlavor(UrdfFlavor):
    """URDF as PyBullet reads it: spherical joints and capsules, no floating joints, mesh paths planned."""

    name: str = "PyBullet"
    joint_types: dict[JointType, str] = dataclasses.field(
        default_factory=lambda: dict(PYBULLET_JOINT_TYPES)
    )
    extra_shapes: frozenset[str] = frozenset({"capsule"})
    #: mesh key (resolved path, else filename) -> filename written (relative to OUT, or an asset)
    filenames: dict[str, str] = dataclasses.field(default_factory=dict)

    def mesh_filename(self, mesh: Mesh) -> str:
        return self.filenames.get(mesh_key(mesh), mesh.filename)


@record
class BasePlan:
    """The robot as the PyBullet URDF roots it, and the finding that says so when it was re-rooted."""

    robot: Robot
    diagnostics: tuple[Diagnostic, ...] = ()


def plan_base(robot: Robot, options: ExportOptions) -> BasePlan:
    """Re-root a free robot whose root link is massless (see the module docstring).

    The exporter writes, and the verifier compares against, the robot planned here.
    """
    tree = KinematicTree.of(robot)
    if not robot.links or len(tree.roots) != 1:
        return BasePlan(robot)
    if decide_base(robot, tree, options.floating_base).kind != "free":
        return BasePlan(robot)
    rooted = reroot_massless_base(robot, tree)
    if rooted is robot:
        return BasePlan(robot)
    old, new = tree.root, rooted.links[0].name
    link = robot.link(old or "")
    note = ConversionDropped.diagnostic(
        f"link '{old}' has no mass and is the root of a robot that moves about; PyBullet welds a "
        f"massless base to the world, so the export roots the tree at '{new}' and keeps '{old}' as "
        "its fixed child (every frame and the total mass unchanged)",
        link.span if link else robot.span,
        element=f"link[{old}]",
        severity=Severity.INFO,
        help="nothing to do; give the root link mass to keep it as PyBullet's base",
        data={"reason": "re-rooted", "old_root": old, "new_root": new},
    )
    return BasePlan(rooted, (note,))


@record
class ExportPlan:
    """The robot as written (re-rooted, fixed joints fused), the re-rooted robot before fusing
    (every frame of the source), the fusion, and the findings that say so."""

    robot: Robot
    unfused: Robot
    fusion: Fusion
    diagnostics: tuple[Diagnostic, ...] = ()


def plan_export(robot: Robot, options: ExportOptions) -> ExportPlan:
    """:func:`plan_base`, then fixed joints fused when asked or when the body is too large for
    PyBullet. The exporter writes, and the verifier compares against, the robot planned here."""
    base = plan_base(robot, options)
    rooted = base.robot
    joints = len(rooted.links) - 1
    if not options.fuse_fixed and joints <= MAX_JOINTS:
        return ExportPlan(rooted, rooted, Fusion(rooted), base.diagnostics)
    fusion = fuse_fixed(rooted, _anchor(rooted, options))
    if not fusion.frames:
        return ExportPlan(rooted, rooted, fusion, base.diagnostics)
    left = len(fusion.robot.links) - 1
    fused = len(fusion.frames)
    what = (
        f"{fused} link{'s' if fused != 1 else ''} on fixed joints merged into the links that carry "
        f"them ({', '.join(f.link for f in fusion.frames[:3])}{', ...' if fused > 3 else ''}): "
        "masses summed, centre of mass and inertia composed exactly, visuals and collisions "
        "re-posed; each fused frame's pose is listed in a comment of the output"
    )
    if options.fuse_fixed:
        message, severity = f"fuse fixed joints: {what}", Severity.INFO
    else:
        message = (
            f"the robot has {joints} joints; PyBullet cannot report the state of a body with more "
            f"than {MAX_JOINTS}, so {what} ({left} joints left)"
        )
        severity = Severity.WARNING
    note = ConversionDropped.diagnostic(
        message,
        robot.span,
        element="robot",
        severity=severity,
        help="nothing to do; read the fused frames' poses from the comment at the top of the output",
        data={
            "reason": "fused",
            "fused": {f.link: f.into for f in fusion.frames},
            "joints": joints,
            "joints_left": left,
        },
    )
    return ExportPlan(fusion.robot, rooted, fusion, (*base.diagnostics, note))


def _anchor(robot: Robot, options: ExportOptions) -> str | None:
    """The root, when it is massless and the robot is not free: PyBullet fixes it to the world
    only while it has no mass, so nothing may be fused into it."""
    tree = KinematicTree.of(robot)
    root = robot.link(tree.root or "")
    if root is None or (root.inertial is not None and root.inertial.mass > 0):
        return None
    return None if decide_base(robot, tree, options.floating_base).kind == "free" else root.name


def export(robot: Robot, out: Path, options: ExportOptions) -> ExportResult:
    """The PyBullet URDF (key ``out.name``) and its assets; nothing when refused."""
    out = Path(out)
    plan = plan_export(robot, options)
    robot = plan.robot
    tree = KinematicTree.of(robot)
    diagnostics = _structure(robot, tree) or _joint_refusals(robot)
    diagnostics += list(plan.diagnostics)
    inertia = plan_inertia(robot, tree, options.repair_inertia, options.floating_base)
    diagnostics += inertia.diagnostics + _mimic_reports(robot) + _spring_reports(robot)
    if any(d.severity is Severity.ERROR for d in diagnostics):
        # Refused: converting meshes (seconds for large DAE files) would be wasted.
        return ExportResult({}, sorted(diagnostics, key=Diagnostic.sort_key))
    meshes = MeshPlan.create(out.resolve().parent, options.copy_assets, options.absolute_mesh_paths)
    prepared = meshes.carry(_prepared(robot, inertia))
    diagnostics += meshes.diagnostics
    root, dropped = robot_element(prepared, PyBulletFlavor(filenames=meshes.filenames))
    root.insert(0, etree.Comment(_header(robot, out, inertia, options)))
    if plan.fusion.frames:
        root.insert(1, etree.Comment(frames_comment(plan.fusion.frames)))
    files = {out.name: to_bytes(root), **meshes.files.files}
    return ExportResult(
        dict(sorted(files.items())), sorted(diagnostics + dropped, key=Diagnostic.sort_key)
    )


def _spring_reports(robot: Robot) -> list[Diagnostic]:
    """SDF joint springs: the file keeps them for Gazebo (``springStiffness``), PyBullet reads none."""
    found = []
    for joint in robot.joints:
        dynamics = joint.dynamics
        if dynamics is None or dynamics.spring_stiffness <= 0:
            continue
        where = f"joint[{joint.name}]/axis/dynamics/spring_stiffness"
        unit = "N/m" if joint.type is JointType.PRISMATIC else "N·m/rad"
        found.append(ConversionDropped.diagnostic(
            f"joint '{joint.name}': PyBullet has no joint spring; its {dynamics.spring_stiffness:g} {unit} "
            "spring is kept for Gazebo only (apply it as a force in your control loop)",
            dynamics.span or joint.span, element=where,
            data={"element": where, "reason": "PyBullet reads no joint spring"}))
    return found


def _prepared(robot: Robot, inertia: PyBulletInertia) -> Robot:
    """*robot* with the planned inertials and unit joint axes."""
    links = tuple(
        dataclasses.replace(link, inertial=inertia.inertials[link.name]) for link in robot.links
    )
    joints = tuple(_unit_axis(joint) for joint in robot.joints)
    return dataclasses.replace(robot, links=links, joints=joints)


def _unit_axis(joint: Joint) -> Joint:
    x, y, z = joint.axis
    norm = (x * x + y * y + z * z) ** 0.5
    if norm == 0.0 or norm == 1.0:
        return joint
    return dataclasses.replace(joint, axis=(x / norm, y / norm, z / norm))


def _structure(robot: Robot, tree: KinematicTree) -> list[Diagnostic]:
    """A robot PyBullet cannot load at all: no links, or more than one root."""
    if not robot.links:
        return [
            EmptyRobot.diagnostic("the robot has no links; PyBullet cannot load it", robot.span)
        ]
    if len(tree.roots) > 1:
        return [
            MultipleRoots.diagnostic(
                f"the robot has {len(tree.roots)} roots ({', '.join(tree.roots[:5])});"
                " PyBullet loads one tree",
                robot.span,
            )
        ]
    if len(robot.links) - 1 > MAX_JOINTS:
        return [
            ConversionDropped.diagnostic(
                f"the robot has {len(robot.links) - 1} joints with its fixed joints fused; PyBullet "
                "loads it but cannot report the "
                f"state of a body with more than {MAX_JOINTS} (getLinkState and "
                "getBasePositionAndOrientation fail); not converted",
                robot.span,
                element="robot",
                severity=Severity.ERROR,
                help="split the robot into bodies (PyBullet loads each with its own loadURDF)",
                data={"reason": "size", "joints": len(robot.links) - 1, "limit": MAX_JOINTS},
            )
        ]
    return []


def _joint_refusals(robot: Robot) -> list[Diagnostic]:
    """Closed chains and joint types PyBullet cannot hold; floating joints with PyBullet's reason."""
    found = [d for d in refusals(robot, PyBulletFlavor()) if d.data.get("type") != "floating"]
    for joint in robot.joints:
        if joint.type is JointType.FLOATING:
            found.append(
                ConversionDropped.diagnostic(
                    f"joint '{joint.name}' is floating; PyBullet turns floating joints into fixed ones; "
                    "not converted",
                    joint.span,
                    element=f"joint[{joint.name}]",
                    severity=Severity.ERROR,
                    help=f"make '{joint.child}' the root (remove the joint and '{joint.parent}'): a "
                    "PyBullet base floats unless loaded with useFixedBase=True",
                    data={"reason": "joint type", "joint": joint.name, "type": "floating"},
                )
            )
    return found


def _mimic_reports(robot: Robot) -> list[Diagnostic]:
    """One ``conversion-dropped`` per mimic joint, with the gear constraint that replaces it."""
    found = []
    for joint in robot.joints:
        if joint.mimic is None:
            continue
        mimic = joint.mimic
        recipe = (
            "PyBullet ignores <mimic>; couple the joints with a gear constraint after loading "
            "(urdftool.backends.pybullet.couple_mimics does this): "
            f"a = index of joint '{joint.name}', b = index of joint '{mimic.joint}'; "
            "c = p.createConstraint(robot, a, robot, b, jointType=p.JOINT_GEAR, jointAxis=[0, 0, 1], "
            "parentFramePosition=[0, 0, 0], childFramePosition=[0, 0, 0]); "
            f"p.changeConstraint(c, gearRatio={-mimic.multiplier:g}, "
            f"relativePositionTarget={mimic.offset:g}, erp=1, maxForce=1e6); "
            "p.setPhysicsEngineParameter(numSolverIterations=200) (PyBullet's defaults, erp 0 and "
            "50 iterations, let followers drift by tenths of a radian)"
        )
        found.append(
            ConversionDropped.diagnostic(
                f"joint '{joint.name}' mimics '{mimic.joint}' (x{mimic.multiplier:g}"
                f"{f' + {mimic.offset:g}' if mimic.offset else ''}); PyBullet does not enforce <mimic>",
                mimic.span or joint.span,
                element=f"joint[{joint.name}]/mimic",
                help=recipe,
                data={
                    "reason": "mimic",
                    "joint": joint.name,
                    "mimics": mimic.joint,
                    "multiplier": mimic.multiplier,
                    "offset": mimic.offset,
                },
            )
        )
    return found


def _header(robot: Robot, out: Path, inertia: PyBulletInertia, options: ExportOptions) -> str:
    """The comment at the top of OUT: where it came from and how to load it."""
    folder = None if options.absolute_mesh_paths else out.resolve().parent
    source = relative_reference(robot.path, folder) if robot.path else "a robot model"
    base = (
        "base: floating (pass useFixedBase=True to fix it)"
        if inertia.base == "floating"
        else "base: fixed to the world (the root link has no mass)"
    )
    # XML comments cannot hold "--", so the options are named in words.
    flags = [
        f
        for f, on in (
            ("repair inertia", options.repair_inertia),
            ("copy assets", options.copy_assets),
            ("fuse fixed joints", options.fuse_fixed),
        )
        if on
    ]
    return (
        f" PyBullet URDF generated by urdftool from {source}"
        f"{' (options: ' + ', '.join(flags) + ')' if flags else ''}.\n"
        f'     Load with p.loadURDF("{out.name}", flags={LOAD_FLAGS}); {base}. '
    )
