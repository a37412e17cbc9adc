"""Masses and inertia for PyBullet: every link explicit, invalid tensors refused or repaired.

PyBullet's URDF loader gives a link without ``<inertial>`` a mass of 1 kg and
unit inertia, and zeroes a tensor that is negative or breaks A + B >= C (each
with a ``b3Warning``). So the PyBullet URDF writes an ``<inertial>`` for every
link: the source's, or mass 0 with a zero tensor where the source has none
(URDF's meaning of a missing ``<inertial>``: no mass).

Validity and repair are the MJCF exporter's (:class:`~urdftool.export.mjcf_inertia.InertiaPlan`):
each tensor is judged on its own, then every moving rigid body (a link on a
moving joint plus the links fixed to it, which PyBullet keeps as separate
links on fixed joints) must carry mass and inertia; with ``--repair-inertia``
each change is made and reported as ``inertia-repaired``.

The base: PyBullet fixes a base of mass 0 to the world and lets any other
float unless ``loadURDF(..., useFixedBase=True)``. A massless root therefore
gives a fixed robot, as in the source's own terms (nothing there could move
it); ``--floating-base free`` with a massless root is refused.
"""

from __future__ import annotations

from dataclasses import field

from urdftool.catalogue.conversion import InertiaNotExportable
from urdftool.diagnostics import Diagnostic
from urdftool.export.mjcf_inertia import InertiaPlan
from urdftool.model import Inertial, KinematicTree, Robot
from urdftool.physics.bodies import rigid_bodies
from urdftool.records import record

#: What a massless link is written with: an explicit zero, so PyBullet does not invent 1 kg.
MASSLESS = Inertial(mass=0.0, inertia=Inertial.tensor(0.0, 0.0, 0.0, 0.0, 0.0, 0.0))


@record(frozen=False)
class PyBulletInertia:
    """Each link's written ``<inertial>``, the base's kind, and the findings."""

    inertials: dict[str, Inertial] = field(default_factory=dict)
    #: "floating" (PyBullet's default for a base with mass) or "fixed" (a massless base)
    base: str = "fixed"
    diagnostics: list[Diagnostic] = field(default_factory=list)


def plan_inertia(
    robot: Robot, tree: KinematicTree, repair: bool, floating_base: str
) -> PyBulletInertia:
    """Check (and with *repair*, fix) every link's inertial and every moving body's minimum."""
    plan = InertiaPlan(robot, repair, engine="PyBullet")
    for link in robot.links:
        plan.check_link(link)
    root = tree.root
    root_mass = plan.inertials.get(root) if root else None
    floats = root_mass is not None and root_mass.mass > 0
    links = {link.name: link for link in robot.links}
    for body in rigid_bodies(tree):
        if body.moves or (body.joint is None and floats):
            frames = {link.name: pose.matrix for link, pose in body.links}
            plan.check_moving_body(links[body.head], [link for link, _ in body.links], frames)
    result = PyBulletInertia(
        base="floating" if floats else "fixed", diagnostics=list(plan.diagnostics)
    )
    if floating_base == "free" and not floats and root is not None:
        result.diagnostics.append(_massless_free_base(robot, root))
    for link in robot.links:
        result.inertials[link.name] = plan.inertials.get(link.name) or MASSLESS
    return result


def _massless_free_base(robot: Robot, root: str) -> Diagnostic:
    link = robot.link(root)
    span = (
        link.inertial.span
        if link is not None and link.inertial is not None
        else (link.span if link else None)
    )
    return InertiaNotExportable.diagnostic(
        f"link '{root}': the base of a floating robot carries no mass; PyBullet fixes a massless "
        "base to the world",
        span,
        element=f"link[{root}]",
        help="give the root link its mass and inertia, or make the robot's root a link that has them",
        data={"link": root, "mass": 0.0},
    )
