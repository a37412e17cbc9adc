"""What each link's declared inertia and its geometry say, measured once per check.

The inertia rules (I004–I008), the units rules (N004) and their help texts all
ask the same questions of every link: the principal moments of the declared
tensor, and the uniform solid of its collision and visual geometry. Each is a
pure function of the link (:mod:`urdftool.physics.inertia`,
:mod:`urdftool.physics.linkmass`); here they are kept in ``ctx.cache`` so that a
check decomposes each tensor and places each shape once, and reads each mesh's
facts once per file and scale however many links use it.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
else:
    # NumPy is imported on first use: a structural check must not pay for it.
    from urdftool.lazy import numpy as np

from urdftool.facts.context import CheckContext
from urdftool.facts.meshes import status
from urdftool.model import Geometry, Inertial, Link, Mesh
from urdftool.model.robot import Inertia3
from urdftool.physics import linkmass
from urdftool.physics.inertia import (
    RELATIVE_TOLERANCE,
    InertiaVerdict,
    clearly_valid,
    judge_moments,
    principal_moments,
    principal_moments_many,
)
from urdftool.physics.linkmass import InertiaComparison, Moments
from urdftool.physics.massprops import SolidProperties, geometry_properties, mesh_properties
from urdftool.physics.vec3 import Tensor3


def declared_valid(ctx: CheckContext, inertial: Inertial, abs_tol: float = 0.0) -> bool:
    """Whether the tensor as written is valid (:func:`declared_verdict`'s ``valid``): four rules
    ask it of every link, and most tensors answer without their eigenvalues
    (:func:`~urdftool.physics.inertia.clearly_valid`)."""
    found = _judged(ctx, abs_tol).get(id(inertial))
    if found is not None and found[0] is inertial:
        return found[1] is None or found[1].valid
    return declared_verdict(ctx, inertial, abs_tol).valid


def declared_verdict(ctx: CheckContext, inertial: Inertial, abs_tol: float = 0.0) -> InertiaVerdict:
    """:func:`~urdftool.physics.inertia.assess` of the tensor as written (inertial frame, kg·m²)
    at ``abs_tol`` (:data:`~urdftool.physics.inertia.MIN_MOMENT` for the validity rules, 0 for
    the fit rules)."""
    found = _judged(ctx, abs_tol).get(id(inertial))
    if found is not None and found[0] is inertial and found[1] is not None:
        return found[1]
    return judge_moments(declared_moments(ctx, inertial), RELATIVE_TOLERANCE, abs_tol)


#: Link tensors judged at one tolerance, by the element's identity (see :func:`_judged`).
Judged = dict[int, tuple[Inertial, InertiaVerdict | None]]


def _judged(ctx: CheckContext, abs_tol: float) -> Judged:
    """Every link's tensor judged at ``abs_tol``, by the element's identity: ``None`` for a tensor
    clearly valid, else its verdict.

    Kept by identity, which costs less to look up than six numbers; the robot holds its elements
    for the whole check, and the element kept beside each answer makes sure it is the one asked
    about.
    """
    by_tolerance: dict[float, Judged] | None = ctx.cache.get("declared-verdicts")
    if by_tolerance is None:
        by_tolerance = ctx.cache["declared-verdicts"] = {}
    judged = by_tolerance.get(abs_tol)
    if judged is None:
        judged = by_tolerance[abs_tol] = _judge_all(ctx, abs_tol, by_tolerance)
    return judged


def _judge_all(ctx: CheckContext, abs_tol: float, by_tolerance: dict[float, Judged]) -> Judged:
    """:func:`_judged` at ``abs_tol``, from what the other tolerances found: a tensor clearly valid
    at a larger one is clearly valid at this one, and a tensor decomposed for another is judged
    from the same moments. The rest are decomposed in one call
    (:func:`~urdftool.physics.inertia.principal_moments_many`)."""
    stricter = [found for tolerance, found in by_tolerance.items() if tolerance >= abs_tol]
    judged: Judged = {}
    unclear: list[Inertial] = []
    for link in ctx.robot.links:
        inertial = link.inertial
        if inertial is None:
            continue
        key = id(inertial)
        clear = stricter and _clear_in(stricter, key)
        if clear or clearly_valid(inertial.inertia, RELATIVE_TOLERANCE, abs_tol):
            judged[key] = (inertial, None)
            continue
        decomposed = _verdict_in(by_tolerance, key)
        if decomposed is not None:
            judged[key] = (inertial, judge_moments(decomposed.moments, RELATIVE_TOLERANCE, abs_tol))
        else:
            unclear.append(inertial)
    try:
        moments = principal_moments_many([inertial.inertia for inertial in unclear])
    except np.linalg.LinAlgError:
        # One tensor that LAPACK cannot decompose fails the whole stack; decomposed one at a
        # time, it fails only the rule that asks for it, as it always did.
        return judged
    for inertial, found in zip(unclear, moments, strict=True):
        judged[id(inertial)] = (inertial, judge_moments(found, RELATIVE_TOLERANCE, abs_tol))
    return judged


def _clear_in(judged: list[Judged], key: int) -> bool:
    """Whether one of *judged* found the tensor of element *key* clearly valid."""
    return any(key in found and found[key][1] is None for found in judged)


def _verdict_in(by_tolerance: dict[float, Judged], key: int) -> InertiaVerdict | None:
    """A verdict on the tensor of element *key* at another tolerance (its moments are known)."""
    for found in by_tolerance.values():
        answer = found.get(key)
        if answer is not None and answer[1] is not None:
            return answer[1]
    return None


def declared_moments(ctx: CheckContext, inertial: Inertial) -> Moments:
    """Principal moments (kg·m², ascending) of the tensor as written, once per distinct tensor."""
    moments: dict[Any, Moments] = ctx.cache.setdefault("declared-moments", {})
    found = moments.get(inertial.inertia)
    if found is None:
        values, _ = principal_moments(inertial.inertia_matrix)
        found = moments[inertial.inertia] = (float(values[0]), float(values[1]), float(values[2]))
    return found


def geometry_sources(ctx: CheckContext, link: Link) -> Iterator[tuple[str, SolidProperties]]:
    """:func:`urdftool.physics.linkmass.geometry_sources` of *link*, each solid measured once.

    Still lazy: the visual solid is measured only when a rule reads past the
    collision one, and then kept for the next rule.
    """
    memo: dict[str, _Sources] | None = ctx.cache.get("link-solids")
    if memo is None:
        memo = ctx.cache["link-solids"] = {}
    sources = memo.get(link.name)
    if sources is None or sources.link is not link:  # a robot may repeat a link's name
        sources = memo[link.name] = _Sources(link, _measurer(ctx))
    return sources.read()


def comparison(ctx: CheckContext, link: Link) -> InertiaComparison | None:
    """:func:`urdftool.physics.linkmass.compare_with_geometry` of *link*, from the measured solids."""
    return linkmass.compare_with_geometry(link, geometry_sources(ctx, link))


def moment_factors(compared: Sequence[tuple[Link, InertiaComparison]]) -> list[float | None]:
    """:func:`~urdftool.physics.linkmass.moment_factor` of each link's declared tensor against
    its comparison's computed one, with the tensors of all of them decomposed in one call
    (:func:`~urdftool.physics.inertia.principal_moments_many`) instead of two per link.

    ``None`` for a link whose tensors cannot be decomposed: LAPACK does not converge on a tensor
    of subnormal numbers (a box 4.9e-324 m deep, fixtures/fuzz-regressions), and such a
    geometry cannot be measured, as a missing one.
    """
    tensors = [tensor for link, found in compared for tensor in (_declared(link), found.computed)]
    try:
        moments: list[Moments | None] = list(principal_moments_many(tensors))
    except np.linalg.LinAlgError:  # one at a time, so that only that link is left unmeasured
        moments = [_moments_or_none(tensor) for tensor in tensors]
    return [
        None if declared is None or computed is None else linkmass.moment_factor(declared, computed)
        for declared, computed in zip(moments[0::2], moments[1::2], strict=True)
    ]


def _declared(link: Link) -> Inertia3:
    assert link.inertial is not None  # a comparison is made only for a link with an <inertial>
    return link.inertial.inertia


def _moments_or_none(tensor: Inertia3 | Tensor3) -> Moments | None:
    try:
        return linkmass.moments_of(tensor)
    except np.linalg.LinAlgError:
        return None


class _Sources:
    """One link's two solids, each measured when a rule first reads that far."""

    def __init__(self, link: Link, measure: linkmass.Measure) -> None:
        self.link = link
        self.measure = measure
        self.collision: SolidProperties | _Unmeasured | None = _UNMEASURED
        self.visual: SolidProperties | _Unmeasured | None = _UNMEASURED

    def read(self) -> Iterator[tuple[str, SolidProperties]]:
        """:func:`urdftool.physics.linkmass.geometry_sources`, from what is measured already.

        A solid that fails to measure raises once, to the rule that asked; the rules after it
        find no solid from there on (no visual solid either when the collision one failed).
        """
        collision = self.collision
        if isinstance(collision, _Unmeasured):
            self.collision = self.visual = None  # what the next rules find if measuring raises
            collision = self.collision = linkmass.collision_solid(self.link, self.measure)
            self.visual = _UNMEASURED
        if collision is not None:
            yield "collision", collision
        visual = self.visual
        if isinstance(visual, _Unmeasured):
            self.visual = None  # what the next rules find if measuring raises
            visual = self.visual = linkmass.visual_solid(self.link, self.measure)
        if visual is not None:
            yield "visual", visual


class _Unmeasured:
    """The mark of a solid not measured yet (``None`` is a solid that cannot be measured)."""


_UNMEASURED = _Unmeasured()


def _measurer(ctx: CheckContext) -> linkmass.Measure:
    """:func:`~urdftool.physics.massprops.geometry_properties`, with each mesh file at each scale
    measured once per check: an arm's left and right links share their meshes."""
    found: linkmass.Measure | None = ctx.cache.get("mesh-measurer")
    if found is not None:
        return found
    meshes: dict[tuple[str | None, str, tuple[float, float, float]], SolidProperties | None] = {}

    def measure(geometry: Geometry | None) -> SolidProperties | None:
        if not isinstance(geometry, Mesh):
            return geometry_properties(geometry)
        # The file name is in the key because the solid's label quotes it.
        key = (geometry.resolved, geometry.filename, geometry.scale)
        if key not in meshes:
            # the mesh survey's status of the file: one os.stat per file per check
            known = status(ctx, geometry.resolved) if geometry.resolved is not None else None
            meshes[key] = mesh_properties(geometry, known)
        return meshes[key]

    ctx.cache["mesh-measurer"] = measure
    return measure

