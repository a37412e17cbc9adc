"""Masses and inertia for MJCF: validated, never silently changed, repaired on request.

A link's ``<inertial>`` is exported as written when it is physically valid
(:func:`urdftool.physics.inertia.assess`) and MuJoCo can integrate it. Otherwise
the export fails with ``inertia-not-exportable`` at the ``<inertial>`` line,
unless the caller asked for a repair, which applies the minimal change below
and reports it as ``inertia-repaired`` with the numbers before and after:

* negative mass: the absolute value;
* mass 0 with non-zero inertia: the inertia is removed (a massless frame);
* a tensor that is not positive definite or breaks A + B >= C: principal axes
  are kept; moments below ``MOMENT_FLOOR`` × trace are raised to it (all of
  them to a ``REPAIR_RADIUS`` solid sphere of the link's mass when even the
  largest is below ``MOMENT_FLOOR`` times that sphere's), then
  the triangle inequality is restored by moving the moments the least distance
  (Euclidean) onto A + B = C;
* a moving body (a link with a joint of its own plus the links fixed to it)
  with less than MuJoCo's minimum mass or inertia (1e-15): the moving link gets
  ``REPAIR_MASS`` and at least the inertia of a ``REPAIR_RADIUS`` solid sphere.

Links without ``<inertial>`` and links with mass 0 and a zero tensor are
massless frames, and a positive mass with a zero tensor is a point mass: both
are fine when fixed to a body that carries mass and inertia, and refused (or
repaired) when they would be a moving body of their own.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from urdftool.catalogue.conversion import ConversionDropped, InertiaNotExportable, InertiaRepaired
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.model import Inertial, Link, Robot
from urdftool.model.pose import Matrix
from urdftool.physics.inertia import assess, principal_moments, shift_to_point

#: MuJoCo's mjMINVAL: the least mass (kg) and principal moment (kg·m²) of a moving body.
MJ_MINVAL = 1e-15
#: Mass (kg) given to a moving link that carries none.
REPAIR_MASS = 1e-3
#: Radius (m) of the solid sphere whose inertia a repaired massless moving link gets.
REPAIR_RADIUS = 0.01
#: Smallest principal moment after a repair, relative to the trace.
MOMENT_FLOOR = 1e-5


def sphere_moment(mass: float, radius: float = REPAIR_RADIUS) -> float:
    """Principal moment (kg·m²) of a solid sphere."""
    return 0.4 * mass * radius * radius


def is_massless(inertial: Inertial | None) -> bool:
    """No ``<inertial>``, or mass 0 with an all-zero tensor: a frame without mass."""
    return inertial is None or (inertial.mass == 0.0 and not np.any(inertial.inertia_matrix))


def _where(link: Link) -> str:
    return f"link[{link.name}]/inertial" if link.inertial else f"link[{link.name}]"


def _span(link: Link):  # type: ignore[no-untyped-def]
    return link.inertial.span if link.inertial and link.inertial.span else link.span


def _moments_text(values: Iterable[float]) -> str:
    return ", ".join(f"{v:.6g}" for v in values)


def _tensor_problem(inertial: Inertial, engine: str = "MuJoCo") -> str | None:
    """Why *engine* or physics refuse this tensor (mass > 0), or ``None``."""
    tensor = inertial.inertia_matrix
    verdict = assess(tensor)
    a, b, c = verdict.moments
    if not verdict.positive_definite:
        return f"inertia is not positive definite (principal moments {_moments_text(verdict.moments)} kg·m²)"
    if verdict.triangle_violation is not None:
        return (f"principal moments {_moments_text(verdict.moments)} kg·m² break the triangle "
                f"inequality A + B >= C")
    exact = sorted(np.diag(tensor)) if _is_diagonal(tensor) else [a, b, c]
    if exact[0] + exact[1] < exact[2] * (1 - 4 * np.finfo(float).eps):
        return (f"principal moments {_moments_text(exact)} kg·m² break A + B >= C by "
                f"{exact[2] - exact[0] - exact[1]:.3g} (within the rounding of the written digits, "
                f"but {engine} refuses it)")
    return None


def _is_diagonal(tensor: Matrix) -> bool:
    return not np.any(tensor - np.diag(np.diag(tensor)))


def repaired_tensor(tensor: Matrix, mass: float) -> Matrix:
    """The nearest valid tensor with the same principal axes (see the module docstring)."""
    values, vectors = principal_moments(tensor)
    moments = np.array(values, dtype=float)
    if moments[2] <= MOMENT_FLOOR * sphere_moment(mass):
        # Nothing but rounding noise: the tensor of a point, given a 1 cm sphere's.
        moments = np.full(3, sphere_moment(mass))
    floor = MOMENT_FLOOR * float(np.sum(np.abs(moments)))
    moments = np.maximum(moments, floor)
    order = np.argsort(moments)
    a, b, c = moments[order]
    if a + b < c:
        # Least-distance move onto A + B = C is along (1, 1, -1); a tiny margin
        # keeps MuJoCo's exact check satisfied after its own eigen-decomposition.
        delta = (c - a - b) / 3.0 * (1.0 + 1e-9)
        a, b, c = a + delta, b + delta, c - delta
    moments[order] = (a, b, c)
    out: Matrix = vectors @ np.diag(moments) @ vectors.T
    symmetric: Matrix = 0.5 * (out + out.T)
    return symmetric


def _with_tensor(inertial: Inertial, tensor: Matrix) -> Inertial:
    t = tensor
    rounded = Inertial.tensor(float(t[0, 0]), float(t[0, 1]), float(t[0, 2]),
                              float(t[1, 1]), float(t[1, 2]), float(t[2, 2]))
    return dataclasses.replace(inertial, inertia=rounded)


def _describe(inertial: Inertial | None) -> dict[str, object]:
    if inertial is None:
        return {"mass": 0.0, "inertia": None}
    return {"mass": inertial.mass, "inertia": [list(row) for row in inertial.inertia]}


class InertiaPlan:
    """The inertial each link is exported with, and what was found on the way."""

    def __init__(self, robot: Robot, repair: bool, engine: str = "MuJoCo"):
        self.robot = robot
        self.repair = repair
        #: the engine named in messages (the checks are the same for MuJoCo and PyBullet)
        self.engine = engine
        self.inertials: dict[str, Inertial | None] = {}
        self.diagnostics: list[Diagnostic] = []

    def _refuse(self, link: Link, problem: str, fix: str) -> None:
        self.diagnostics.append(InertiaNotExportable.diagnostic(
            f"link '{link.name}': {problem}", _span(link), element=_where(link),
            help=f"{fix}; or export with --repair-inertia (each change is reported)",
            data={"link": link.name, **_describe(link.inertial)}))

    def _repaired(self, link: Link, before: Inertial | None, after: Inertial | None, what: str) -> None:
        self.diagnostics.append(InertiaRepaired.diagnostic(
            f"link '{link.name}': {what}", _span(link), element=_where(link),
            data={"link": link.name, "before": _describe(before), "after": _describe(after)}))

    def check_link(self, link: Link) -> None:
        """Validate (and with repair, fix) one link's own inertial."""
        inertial = link.inertial
        if inertial is None or is_massless(inertial):
            self.inertials[link.name] = None
            return
        if inertial.mass < 0:
            if not self.repair:
                self._refuse(link, f"negative mass {inertial.mass:g} kg", "write the link's real mass")
                self.inertials[link.name] = inertial
                return
            fixed = dataclasses.replace(inertial, mass=-inertial.mass)
            self._repaired(link, inertial, fixed, f"mass {inertial.mass:g} kg made {fixed.mass:g} kg")
            inertial = fixed
        if inertial.mass == 0.0:
            if not self.repair:
                self._refuse(link, "mass 0 kg with a non-zero inertia tensor",
                             "write the link's mass, or remove the tensor for a massless frame")
                self.inertials[link.name] = inertial
                return
            self._repaired(link, inertial, None, "inertia of a massless link removed (massless frame)")
            self.inertials[link.name] = None
            return
        if not np.any(inertial.inertia_matrix):
            # A point mass: a valid idealisation that MuJoCo and Pinocchio both add to
            # the body it is fixed to; a moving point mass is caught by the body check.
            self.inertials[link.name] = inertial
            return
        problem = _tensor_problem(inertial, self.engine)
        if problem is None:
            self.inertials[link.name] = inertial
            return
        if not self.repair:
            self._refuse(link, problem, "write a tensor from the link's shape and mass")
            self.inertials[link.name] = inertial
            return
        fixed = _with_tensor(inertial, repaired_tensor(inertial.inertia_matrix, inertial.mass))
        before = assess(inertial.inertia_matrix).moments
        after = assess(fixed.inertia_matrix).moments
        self._repaired(link, inertial, fixed,
                       f"{problem}; principal moments repaired to {_moments_text(after)} kg·m² "
                       f"(were {_moments_text(before)})")
        self.inertials[link.name] = fixed

    def static_root(self, link: Link) -> None:
        """A root welded to the world: its mass and inertia never move, so mass 0 with a tensor
        (PyBullet's convention for a static base) is carried as a massless frame, reported."""
        inertial = link.inertial
        if inertial is None or inertial.mass != 0.0 or is_massless(inertial):
            self.check_link(link)
            return
        self.inertials[link.name] = None
        self.diagnostics.append(ConversionDropped.diagnostic(
            f"link '{link.name}': the inertia tensor of a static base with mass 0 is not carried "
            "(it has no effect on a body welded to the world)", _span(link), element=_where(link),
            severity=Severity.INFO, data={"element": _where(link), "reason": "static base"}))

    def check_moving_body(self, moving: Link, group: Sequence[Link], frames: Mapping[str, Matrix]) -> None:
        """MuJoCo's minimum for a moving body: *moving* plus the links fixed to it (*group*).

        *frames* gives each group link's pose (4×4) in *moving*'s frame.
        """
        mass, inertia = self.composite(group, frames)
        low_inertia = float(np.min(np.linalg.eigvalsh(inertia))) if mass > 0 else 0.0
        if mass >= MJ_MINVAL and low_inertia >= MJ_MINVAL:
            return
        names = ", ".join(f"'{link.name}'" for link in group)
        if mass < MJ_MINVAL:
            problem = (f"moving link carries no mass ({mass:.3g} kg over {names}); {self.engine} needs more "
                       f"than {MJ_MINVAL:g} kg on every moving body")
        else:
            problem = (f"moving link has no rotational inertia about some axis (smallest principal "
                       f"moment {low_inertia:.3g} kg·m² over {names})")
        if not self.repair:
            self._refuse(moving, problem, "give the link its real mass and inertia")
            return
        before = self.inertials.get(moving.name)
        mass_own = before.mass if before is not None and before.mass > 0 else REPAIR_MASS
        floor = sphere_moment(mass_own)
        tensor = np.zeros((3, 3)) if before is None else before.inertia_matrix
        values, vectors = principal_moments(tensor)
        raised = vectors @ np.diag(np.maximum(values, floor)) @ vectors.T
        template = before or Inertial(mass=mass_own, inertia=Inertial.tensor(0, 0, 0, 0, 0, 0),
                                      span=None)
        after = _with_tensor(dataclasses.replace(template, mass=mass_own), 0.5 * (raised + raised.T))
        self.inertials[moving.name] = after
        self._repaired(moving, before, after,
                       f"{problem}; given mass {mass_own:g} kg and principal moments of at least "
                       f"{floor:.3g} kg·m²")

    def composite(self, group: Sequence[Link], frames: Mapping[str, Matrix]) -> tuple[float, Matrix]:
        """Total mass (kg) and inertia (kg·m², about the group's centre of mass) of *group*."""
        parts = []
        for link in group:
            inertial = self.inertials.get(link.name)
            if inertial is None or inertial.mass <= 0:
                continue
            pose = frames[link.name] @ inertial.origin.matrix
            rot = pose[:3, :3]
            parts.append((inertial.mass, pose[:3, 3], rot @ inertial.inertia_matrix @ rot.T))
        mass = float(sum(p[0] for p in parts))
        if mass <= 0:
            return 0.0, np.zeros((3, 3))
        com = sum(p[0] * p[1] for p in parts) / mass
        total = np.zeros((3, 3))
        for m, c, tensor in parts:
            total += shift_to_point(tensor, m, c - com)
        return mass, total
