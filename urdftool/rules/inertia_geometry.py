"""Inertia (I) that does not fit the link's geometry: the declared tensor against the uniform solid
of the link's collision (or visual) geometry at the declared mass (``inertia-geometry-mismatch``).

Split from :mod:`urdftool.rules.inertia_fit`, which keeps the other plausibility rules (density,
centre of mass, root link, mass ratios). Thresholds and the reasons for them are in
``docs/inertia.md``.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
else:
    # NumPy is imported on first use: a structural check must not pay for it.
    from urdftool.lazy import numpy as np

from urdftool.catalogue.registry import register
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.facts import link_mass
from urdftool.facts.context import CheckContext
from urdftool.model import Link
from urdftool.physics import vec3
from urdftool.physics.bodies import MIN_VALUE
from urdftool.physics.describe import fmt, fmt_tensor, tensor_rows
from urdftool.physics.linkmass import InertiaComparison
from urdftool.rules.inertia import _Inertia, _where, body_of_link

#: inertia-geometry-mismatch fires when the declared inertia is this many times
#: larger or smaller (trace ratio) than the geometry's. At √10 ≈ 3.16 or below,
#: any link the rule accepts still gets caught when its inertia is made 10×
#: larger or smaller; 3 leaves a little room for that.
INERTIA_FACTOR = 3.0
#: A declared inertia larger than the geometry's is reported only when no mass
#: distribution inside the geometry's bounds, grown by this factor in every
#: direction, could have it (see _possible_for_bounds).
BOUNDS_MARGIN = 1.0
#: Right moments, wrong axes: principal moments within this factor of the
#: geometry's, while the moment about some geometric axis is off by the next.
SAME_MOMENTS = 1.15
AXIS_FACTOR = 1.4
#: Room for the rounding of a trace against the sum of the eigenvalues (about 1e-15 of it).
ROUNDING = 1e-9


@register
class InertiaGeometryMismatch(_Inertia):
    """The declared inertia is far from what the link's geometry has at its mass.

    ## What it does
    Computes the inertia of the link's collision geometry, and of its visual
    geometry, as uniform solids of the declared mass: boxes, cylinders,
    spheres and capsules by formula, meshes from their enclosed volume (or
    their convex hull when they are not closed), several shapes composed with
    their origins; the collision geometry is used, the visual one when the
    collision geometry cannot be measured. The result is rotated into the
    inertial frame of `<inertial><origin rpy>`. The finding is reported when
    the declared tensor is 3× smaller (ratio of traces) than the geometry's,
    or larger than any distribution of the declared mass inside the
    geometry's bounds could have; and when the principal moments agree but
    sit on the wrong axes (a wheel whose spin moment is on an axis it does
    not spin about; a product of inertia of the wrong sign, when flipping it
    is the whole difference, is said so: a mirrored part's values). A link
    welded below another is judged with its body: when its own tensor,
    declared or fitted, leaves the body's inertia within 3×, nothing a
    consumer computes depends on it and it is not reported.

    ## Why it matters
    Placeholder inertias (`0.1` everywhere, `1e-3` on a 20 g finger) and
    moments pasted in the wrong frame make controllers and simulators
    accelerate the link wrongly: joints oscillate, grippers fling objects,
    a 60× too large inertia hides contact dynamics entirely.

    ## Example
    ```xml
    <link name="lidar">
      <inertial>
        <mass value="1e-5"/>
        <inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="1e-6"/>
      </inertial>
      <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
    </link>
    ```

    ## Fix
    Use the tensor from CAD, or the one in the finding's `help` (the
    geometry's at the declared mass, in the inertial frame). For a wheel
    whose cylinder is rolled onto the axle, either roll the inertial frame
    the same way or write the spin moment on the axle's axis.
    """

    code = "I006"
    name = "inertia-geometry-mismatch"
    severity = Severity.WARNING

    def check(self, ctx: CheckContext) -> Iterator[Diagnostic]:
        # Whether the moments sit on the wrong axes is asked only where the traces agree, after
        # the other links: their principal moments are decomposed in one call for all of them.
        same_traces: list[tuple[Link, InertiaComparison]] = []
        try:
            for link in ctx.robot.links:
                inertial = link.inertial
                if (
                    inertial is None
                    or inertial.mass <= MIN_VALUE  # as written: a NaN mass is judged
                    or not link_mass.declared_valid(ctx, inertial)
                ):
                    continue
                comparison = link_mass.comparison(ctx, link)
                if comparison is None:
                    continue
                factor = comparison.factor
                if factor >= INERTIA_FACTOR:
                    if not _possible_for_bounds(link, comparison) and not _lost_in_body(
                        ctx, link, comparison
                    ):
                        yield self._scale_finding(link, comparison)
                elif factor <= SAME_MOMENTS * (1 + ROUNDING):
                    # the ratio of the traces is a weighted mean of the moments' ratios: beyond
                    # SAME_MOMENTS, some moment is too, and the moments are not the geometry's
                    same_traces.append((link, comparison))
        except Exception:
            # a link that fails to measure: the links before it are reported, then the error
            yield from self._axes_findings(ctx, same_traces)
            raise
        yield from self._axes_findings(ctx, same_traces)

    def _axes_findings(
        self, ctx: CheckContext, same_traces: list[tuple[Link, InertiaComparison]]
    ) -> Iterator[Diagnostic]:
        """Right moments on the wrong axes, among links whose traces agree with the geometry's."""
        for (link, comparison), worst in zip(
            same_traces, link_mass.moment_factors(same_traces), strict=True
        ):
            if worst is None or worst > SAME_MOMENTS:
                continue
            factor = _wrong_axes(link, comparison)
            if factor is not None:
                yield self._axes_finding(link, comparison, factor)

    def _scale_finding(self, link: Link, best: InertiaComparison) -> Diagnostic:
        assert link.inertial is not None
        times = f"{fmt(best.ratio)}×" if best.ratio >= 1 else f"1/{fmt(1 / best.ratio)} of"
        return self.diagnostic(
            f"link '{link.name}': declared inertia is {times} the {best.solid.label} at "
            f"{fmt(link.inertial.mass)} kg ({fmt_tensor(best.computed)})",
            link.inertial.inertia_span or link.inertial.span or link.span,
            element=_where(link, "inertial", "inertia"),
            help=f"a uniform {best.solid.label} ({best.source} geometry) of "
            f"{fmt(link.inertial.mass)} kg "
            f"has, in the inertial frame, {fmt_tensor(best.computed)}"
            + (" (mesh not closed: measured by its convex hull)" if best.solid.approximate else ""),
            data={
                "ratio": best.ratio,
                "source": best.source,
                "geometry": best.solid.label,
                "computed": tensor_rows(best.computed),
                "declared": link.inertial.inertia_matrix.tolist(),
            },
        )

    def _axes_finding(self, link: Link, comparison: InertiaComparison, factor: float) -> Diagnostic:
        assert link.inertial is not None
        computed = np.array(comparison.computed)
        flipped = _flipped_products(link.inertial.inertia_matrix, computed)
        if flipped:
            declared = link.inertial.inertia_matrix
            values = ", ".join(f"{name} {fmt(float(declared[i, j]))} against {fmt(float(computed[i, j]))}"
                               for name, (i, j) in flipped)
            names = " and ".join(name for name, _ in flipped)
            return self.diagnostic(
                f"link '{link.name}': declared inertia has the moments of the {comparison.solid.label}, "
                f"but {names} {'has' if len(flipped) == 1 else 'have'} the opposite sign "
                f"({values} kg·m²): a mirrored part's values, or the other side's",
                link.inertial.inertia_span or link.inertial.span or link.span,
                element=_where(link, "inertial", "inertia"),
                help=f"flip the sign of {names}; in the inertial frame the {comparison.source} geometry "
                f"has {fmt_tensor(comparison.computed)}",
                data={
                    "axis_factor": factor,
                    "flipped": [name for name, _ in flipped],
                    "source": comparison.source,
                    "geometry": comparison.solid.label,
                    "computed": tensor_rows(comparison.computed),
                    "declared": link.inertial.inertia_matrix.tolist(),
                },
            )
        return self.diagnostic(
            f"link '{link.name}': declared inertia has the moments of the {comparison.solid.label} "
            f"on the wrong axes (off by {fmt(factor)}× about one of its axes in the inertial "
            "frame)",
            link.inertial.inertia_span or link.inertial.span or link.span,
            element=_where(link, "inertial", "inertia"),
            help=f"in the inertial frame the {comparison.source} geometry has "
            f"{fmt_tensor(comparison.computed)}; rotate <inertial><origin rpy> like the geometry's "
            "origin, or write these values",
            data={
                "axis_factor": factor,
                "source": comparison.source,
                "geometry": comparison.solid.label,
                "computed": tensor_rows(comparison.computed),
                "declared": link.inertial.inertia_matrix.tolist(),
            },
        )


def _possible_for_bounds(link: Link, comparison: InertiaComparison) -> bool:
    """Whether a declared inertia *larger* than the uniform solid's could still be the link's.

    Geometry is a stand-in for the part: CAD tensors include motors, cables and
    flanges that a collision hull or a primitive leaves out, so "3× the uniform
    solid" alone is no evidence. Evidence is a tensor that no distribution of
    the declared mass inside the geometry's bounds can have: about the centre
    of mass, trace(I) = 2·Σ mᵢ·|rᵢ|² ≤ 2·m·R², R the distance from the centre
    of mass to the farthest corner of the bounds, enlarged by BOUNDS_MARGIN.
    """
    assert link.inertial is not None
    if comparison.ratio < 1:
        return False
    solid = comparison.solid
    com = link.inertial.origin.xyz
    corners = itertools.product(*zip(solid.bounds_min, solid.bounds_max, strict=True))
    reach = max(vec3.norm(vec3.sub(corner, com)) for corner in corners) * BOUNDS_MARGIN  # type: ignore[arg-type]
    declared = vec3.trace(link.inertial.inertia)
    return declared <= 2.0 * link.inertial.mass * reach**2


def _lost_in_body(ctx: CheckContext, link: Link, comparison: InertiaComparison) -> bool:
    """Whether *link* is welded below another link and its own inertia, declared or fitted to
    its geometry, leaves the welded body's inertia within INERTIA_FACTOR.

    Every consumer that matters here (Pinocchio, MuJoCo's import, Gazebo's
    lumping) sees the body, not the link: a 1 g IMU link with a placeholder
    1e-4 kg·m² welded into a 10 kg trunk changes nothing anyone computes. The
    head of a body is always judged on its own, so a planted mistake in a
    moving link is always caught.
    """
    body = body_of_link(ctx, link.name)
    if body is None or body.head == link.name or link.inertial is None:
        return False
    declared = body.composite_trace()
    fitted = body.composite_trace({link.name: vec3.trace(comparison.computed)})
    if declared <= 0 or fitted <= 0:
        return False
    return max(declared / fitted, fitted / declared) < INERTIA_FACTOR


def _wrong_axes(link: Link, comparison: InertiaComparison) -> float | None:
    """The off-axis factor when the principal moments, which match the geometry's, sit on other
    axes than its."""
    assert link.inertial is not None
    computed = comparison.computed
    if not (computed[0][1] or computed[0][2] or computed[1][2] or computed[1][0] or computed[2][0]
            or computed[2][1]):
        # A shape on the inertial frame's axes (most are): its principal axes are the frame's (eigh
        # gives the unit vectors), and the moments about them are the two diagonals.
        declared = link.inertial.inertia
        factor = max(max(declared[k][k] / computed[k][k], computed[k][k] / declared[k][k]) for k in range(3))
    else:
        factor = _axis_factor(link.inertial.inertia_matrix, np.array(computed))
    return factor if factor >= AXIS_FACTOR else None


def _axis_factor(declared: np.ndarray, computed: np.ndarray) -> float:
    """How far *declared*'s moment about one of *computed*'s principal axes is from *computed*'s."""
    _, axes = np.linalg.eigh(computed)
    # each axis's moments in plain floats: NumPy's products on 3-vectors cost more than the sums
    rows_d, rows_c = declared.tolist(), computed.tolist()
    factor = 0.0
    for axis in axes.T.tolist():
        along, moment = _moment_about(rows_d, axis), _moment_about(rows_c, axis)
        factor = max(factor, along / moment, moment / along)
    return factor


def _moment_about(tensor: list[list[float]], axis: list[float]) -> float:
    """``axis @ tensor @ axis``: the moment (kg·m²) of *tensor* about the unit *axis*."""
    x, y, z = axis
    return ((x * tensor[0][0] + y * tensor[1][0] + z * tensor[2][0]) * x
            + (x * tensor[0][1] + y * tensor[1][1] + z * tensor[2][1]) * y
            + (x * tensor[0][2] + y * tensor[1][2] + z * tensor[2][2]) * z)


_PRODUCTS = (("ixy", (0, 1)), ("ixz", (0, 2)), ("iyz", (1, 2)))


def _flipped_products(declared: np.ndarray, computed: np.ndarray) -> list[tuple[str, tuple[int, int]]]:
    """The products of inertia whose sign, flipped, puts *declared* on *computed*'s axes (a CAD
    export of the mirrored part, or the left side's values on the right), when its diagonal is the
    geometry's already; else empty, and the axes themselves are wrong."""
    diagonal = [(float(declared[k, k]), float(computed[k, k])) for k in range(3)]
    if any(d <= 0 or c <= 0 or max(d / c, c / d) > SAME_MOMENTS for d, c in diagonal):
        return []
    flipped = [(name, (i, j)) for name, (i, j) in _PRODUCTS if declared[i, j] * computed[i, j] < 0]
    if not flipped:
        return []
    fixed = declared.copy()
    for _, (i, j) in flipped:
        fixed[i, j] = fixed[j, i] = -declared[i, j]
    return flipped if _axis_factor(fixed, computed) < AXIS_FACTOR else []
