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

from collections.abc import Iterable, Iterator
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
else:
    # NumPy is imported on first use: a structural check must not pay for it.
    from urdftool.lazy import numpy as np

from urdftool.facts.context import CheckContext
from urdftool.model import Geometry, Inertial, Link, Mesh
from urdftool.physics import linkmass
from urdftool.physics.inertia import (
    RELATIVE_TOLERANCE,
    InertiaVerdict,
    judge_moments,
    principal_moments,
    principal_moments_many,
)
from urdftool.physics.linkmass import InertiaComparison, Moments, Prepared
from urdftool.physics.massprops import SolidProperties, geometry_properties


def declared_verdict(ctx: CheckContext, inertial: Inertial, abs_tol: float = 0.0) -> InertiaVerdict:
    """:func:`~urdftool.physics.inertia.assess` of the tensor as written (inertial frame, kg·m²).

    Judged once per distinct tensor and tolerance (``abs_tol``:
    :data:`~urdftool.physics.inertia.MIN_MOMENT` for the validity rules, 0 for the fit rules):
    four rules ask it of every link.
    """
    verdicts: dict[tuple[Any, float], InertiaVerdict] = ctx.cache.setdefault("declared-verdicts", {})
    key = (inertial.inertia, abs_tol)
    verdict = verdicts.get(key)
    if verdict is None:
        verdict = verdicts[key] = judge_moments(declared_moments(ctx, inertial), RELATIVE_TOLERANCE, abs_tol)
    return verdict


def declared_moments(ctx: CheckContext, inertial: Inertial) -> Moments:
    """Principal moments (kg·m², ascending) of the tensor as written, once per distinct tensor.

    The first call decomposes every link's tensor at once
    (:func:`~urdftool.physics.inertia.principal_moments_many`): the validity rules judge each
    of them anyway.
    """
    moments: dict[Any, Moments] | None = ctx.cache.get("declared-moments")
    if moments is None:
        moments = ctx.cache["declared-moments"] = _all_declared_moments(ctx)
    found = moments.get(inertial.inertia)
    if found is None:
        values, _ = principal_moments(inertial.inertia_matrix)
        found = moments[inertial.inertia] = (float(values[0]), float(values[1]), float(values[2]))
    return found


def _all_declared_moments(ctx: CheckContext) -> dict[Any, Moments]:
    inertials = (link.inertial for link in ctx.robot.links if link.inertial is not None)
    tensors = list(dict.fromkeys(inertial.inertia for inertial in inertials))
    try:
        return dict(zip(tensors, principal_moments_many(tensors), strict=True))
    except np.linalg.LinAlgError:
        # One tensor that LAPACK cannot decompose fails the whole stack; decomposed one at a
        # time, it fails only the rule that asks for it, as it always did.
        return {}


def geometry_sources(ctx: CheckContext, link: Link) -> Iterator[tuple[str, SolidProperties]]:
    """:func:`urdftool.physics.linkmass.geometry_sources` of *link*, each solid measured once.

    Still lazy: the visual solid is measured only when a rule reads past the
    collision one, and then kept for the next rule.
    """
    memo: dict[str, _Sources] = ctx.cache.setdefault("link-solids", {})
    sources = memo.get(link.name)
    if sources is None or sources.link is not link:  # a robot may repeat a link's name
        sources = memo[link.name] = _Sources(link, linkmass.geometry_sources(link, _measurer(ctx)))
    if sources.pending is None:  # all measured: most questions after the first rule's
        return iter(sources.measured)
    return sources.read()


def comparison(ctx: CheckContext, link: Link) -> InertiaComparison | None:
    """:func:`urdftool.physics.linkmass.compare_with_geometry` of *link*, from the measured solids."""
    moments = declared_moments(ctx, link.inertial) if link.inertial is not None else None
    return linkmass.compare_with_geometry(link, geometry_sources(ctx, link), moments)


def comparisons(ctx: CheckContext, links: Iterable[Link]) -> Iterator[tuple[Link, InertiaComparison | None]]:
    """Each of *links* with its :func:`comparison`, in order: the same comparisons, with the
    geometry's principal moments of all of them decomposed in one call
    (:func:`~urdftool.physics.inertia.principal_moments_many`) instead of one per link.

    An error (from *links* itself or from measuring a link's geometry) is raised after the
    links before it are yielded, where a loop calling :func:`comparison` would meet it.
    """
    prepared: list[tuple[Link, Prepared | None]] = []
    failure: Exception | None = None
    remaining = iter(links)
    try:
        for link in remaining:
            prepared.append((link, linkmass.prepare_comparison(link, geometry_sources(ctx, link))))
    except Exception as exc:  # raised in its turn below
        failure = exc
    try:
        batch: Iterator[Moments] | None = iter(
            principal_moments_many([found[2] for _, found in prepared if found is not None])
        )
    except np.linalg.LinAlgError:  # one at a time, so that only that link is left unmeasured
        batch = None
    for link, found in prepared:
        if found is None:
            yield link, None
            continue
        declared = declared_moments(ctx, link.inertial) if link.inertial is not None else None
        if batch is not None:
            moments = next(batch)
        else:
            try:
                moments = linkmass.moments_of(found[2])
            except np.linalg.LinAlgError:
                # LAPACK does not converge on a tensor of subnormal numbers (a box 4.9e-324 m deep,
                # fixtures/fuzz-regressions): such a geometry cannot be measured, as a missing one
                yield link, None
                continue
        yield link, linkmass.finish_comparison(link, found, declared, moments)
    if failure is not None:
        raise failure


class _Sources:
    """One link's geometry sources: those measured so far, and the generator measuring the rest."""

    def __init__(self, link: Link, pending: Iterator[tuple[str, SolidProperties]]) -> None:
        self.link = link
        self.measured: list[tuple[str, SolidProperties]] = []
        self.pending: Iterator[tuple[str, SolidProperties]] | None = pending

    def read(self) -> Iterator[tuple[str, SolidProperties]]:
        index = 0
        while True:
            if index < len(self.measured):
                yield self.measured[index]
                index += 1
                continue
            following = next(self.pending, None) if self.pending is not None else None
            if following is None:
                self.pending = None
                return
            self.measured.append(following)


def _measurer(ctx: CheckContext) -> linkmass.Measure:
    """:func:`~urdftool.physics.massprops.geometry_properties`, with each mesh file at each scale
    measured once per check: an arm's left and right links share their meshes."""
    meshes: dict[tuple[str | None, str, tuple[float, float, float]], SolidProperties | None]
    meshes = ctx.cache.setdefault("mesh-solids", {})

    def measure(geometry: Geometry | None) -> SolidProperties | None:
        if not isinstance(geometry, Mesh):
            return geometry_properties(geometry)
        # The file name is in the key because the solid's label quotes it.
        key = (geometry.resolved, geometry.filename, geometry.scale)
        if key not in meshes:
            meshes[key] = geometry_properties(geometry)
        return meshes[key]

    return measure
