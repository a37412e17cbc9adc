"""What a link's geometry says about its mass properties, for comparing with its ``<inertial>``.

For each link there are up to two descriptions of its shape: the collision
geometry (what simulators use) and the visual geometry (often the full CAD
part). Each gives, at uniform density, a volume, a centroid, an inertia and
bounds in the link frame. Collision geometry is often simplified (a sphere at
the foot of a leg, a box around a camera), so rules that judge the declared
values against geometry ask both and trust the one that agrees best.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator

from urdftool.model import Collision, Geometry, Link, Visual
from urdftool.model.pose import Matrix, Vec3
from urdftool.physics import vec3
from urdftool.physics.inertia import principal_moments
from urdftool.physics.massprops import (
    SolidProperties,
    combine,
    geometry_properties,
    place,
    rotate_into,
)
from urdftool.physics.vec3 import Tensor3
from urdftool.records import record

#: Density (kg/m³) used to suggest a mass for a massless link: a solid of
#: plastic, or a hollow aluminium part, which is what most robot links weigh.
TYPICAL_DENSITY = 1000.0

#: Measures one geometry in its own frame (:func:`geometry_properties`, or a memo of it).
Measure = Callable[[Geometry | None], SolidProperties | None]
#: Principal moments (kg·m²), ascending.
Moments = tuple[float, float, float]
#: A link's ("collision" or "visual", solid) pairs, as :func:`geometry_sources` yields them.
Sources = Iterable[tuple[str, SolidProperties]]


def link_solid(
    elements: tuple[Collision, ...] | tuple[Visual, ...], measure: Measure = geometry_properties
) -> SolidProperties | None:
    """The combined uniform-density solid of a link's collision or visual elements (link frame).

    ``None`` when any element's volume cannot be known (an unresolved or
    unreadable mesh, a plane): a partial shape would mislead.
    """
    if len(elements) == 1:  # most links: one shape, nothing to combine
        solid = measure(elements[0].geometry)
        return place(solid, elements[0].origin) if solid is not None and solid.volume > 0 else None
    parts: list[SolidProperties] = []
    for element in elements:
        solid = measure(element.geometry)
        if solid is None:
            return None
        parts.append(place(solid, element.origin))
    return combine(parts)


def geometry_sources(
    link: Link, measure: Measure = geometry_properties
) -> Iterator[tuple[str, SolidProperties]]:
    """``("collision", solid)`` then ``("visual", solid)``, lazily, skipping the unmeasurable.

    The visual solid is skipped when the visual elements are the same shapes
    as the collision ones (common in hand-written URDF). A check asks through
    :func:`urdftool.facts.link_mass.geometry_sources`, which measures each link once.
    """
    collision = collision_solid(link, measure)
    if collision is not None:
        yield "collision", collision
    visual = visual_solid(link, measure)
    if visual is not None:
        yield "visual", visual


def collision_solid(link: Link, measure: Measure = geometry_properties) -> SolidProperties | None:
    """The link's collision solid (:func:`link_solid`), ``None`` without one."""
    return link_solid(link.collisions, measure) if link.collisions else None


def visual_solid(link: Link, measure: Measure = geometry_properties) -> SolidProperties | None:
    """The link's visual solid (:func:`link_solid`), ``None`` without one or when the visual
    elements are the same shapes as the collision ones."""
    if link.visuals and _shapes(link.visuals) != _shapes(link.collisions):
        return link_solid(link.visuals, measure)
    return None


def _shapes(elements: tuple[Collision, ...] | tuple[Visual, ...]) -> list[tuple[object, object]]:
    return [(e.geometry, e.origin) for e in elements]


@record
class InertiaComparison:
    """The declared tensor against a uniform solid of the declared mass, both in the inertial frame.

    ``ratio`` is trace(declared) / trace(computed): how many times larger the
    declared inertia is overall. How the principal moments compare
    (:func:`moment_factor`) is a second question, asked only where the traces agree: it needs
    both tensors' eigenvalues.
    """

    source: str
    solid: SolidProperties
    computed: Tensor3
    ratio: float

    @property
    def factor(self) -> float:
        """The overall disagreement as a factor ≥ 1, whichever way round."""
        return max(self.ratio, 1.0 / self.ratio) if self.ratio > 0 else math.inf


def geometry_tensor(link: Link, solid: SolidProperties) -> Tensor3 | None:
    """Inertia (kg·m²) of *solid* at the declared mass, about its centroid, inertial frame."""
    inertial = link.inertial
    if inertial is None or inertial.mass <= 0 or solid.volume <= 0:
        return None
    return rotate_into(solid.inertia_for_mass(inertial.mass), inertial.origin)


def compare_inertia(link: Link, source: str, solid: SolidProperties) -> InertiaComparison | None:
    """*link*'s declared inertia against *solid* at its mass; ``None`` if not comparable."""
    computed = geometry_tensor(link, solid)
    if computed is None or link.inertial is None:
        return None
    computed_trace = vec3.trace(computed)
    declared_trace = vec3.trace(link.inertial.inertia)
    if computed_trace <= 0 or declared_trace <= 0:
        return None
    return InertiaComparison(source, solid, computed, declared_trace / computed_trace)


def moment_factor(declared: Moments, computed: Moments) -> float:
    """The largest factor (≥ 1) between matching principal moments (kg·m², ascending) of the
    declared tensor and the computed one; ``inf`` when a moment is not positive.

    Never below the comparison's :attr:`~InertiaComparison.factor`: the ratio of the traces is a
    weighted mean of the moments' ratios.
    """
    worst = 1.0
    for d, c in zip(declared, computed, strict=True):
        if d <= 0 or c <= 0:
            return math.inf
        worst = max(worst, d / c, c / d)
    return worst


#: Diagonal (m) of a shape's bounds below which it stands in for a part instead of shaping it.
MARKER_SIZE = 0.005


def compare_with_geometry(link: Link, sources: Sources | None = None) -> InertiaComparison | None:
    """The declared inertia against the collision geometry, or the visual one when the
    collision geometry cannot be measured (*sources*: the link's, already measured; read
    lazily, as far as needed).

    One source only, never the better of two: then a link whose inertia is
    accepted is always caught when that inertia is made 10× larger or smaller.
    A shape under MARKER_SIZE across is a marker, not the part (Baxter's 0.55 kg
    head collides as a 1 mm sphere): the next source is used.
    """
    for source, solid in geometry_sources(link) if sources is None else sources:
        if bounds_diagonal(solid) < MARKER_SIZE:
            continue
        comparison = compare_inertia(link, source, solid)
        if comparison is not None:
            return comparison
    return None


def density(link: Link, solid: SolidProperties) -> float | None:
    """Declared mass / geometric volume (kg/m³), or ``None`` without a positive mass."""
    if link.inertial is None or link.inertial.mass <= 0 or solid.volume <= 0:
        return None
    value = link.inertial.mass / solid.volume
    return value if math.isfinite(value) else None  # a subnormal volume: no density to judge


def distance_outside(point: Vec3, solid: SolidProperties) -> float:
    """How far (m) *point* lies outside the solid's bounds, link frame (0 inside)."""
    (x0, y0, z0), (x1, y1, z1), (x, y, z) = solid.bounds_min, solid.bounds_max, point
    return vec3.norm((max(x0 - x, x - x1, 0.0), max(y0 - y, y - y1, 0.0), max(z0 - z, z - z1, 0.0)))


def moments_of(tensor: Matrix | Tensor3) -> Moments:
    """Principal moments (kg·m², ascending) of *tensor*, as floats."""
    values, _ = principal_moments(tensor)
    return (float(values[0]), float(values[1]), float(values[2]))


def bounds_diagonal(solid: SolidProperties) -> float:
    """Length (m) of the diagonal of the solid's bounds: the size of the part."""
    return vec3.norm(vec3.sub(solid.bounds_max, solid.bounds_min))
