"""Numbers and tensors written the way a robot description writes them, for messages.

Also the values a finding suggests: a mass for a massless link from its
geometry, a valid tensor for a link from its geometry at its mass.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
else:
    # NumPy is imported on first use: a structural check must not pay for it.
    from urdftool.lazy import numpy as np

from urdftool.model import Inertial, Link
from urdftool.model.pose import Matrix
from urdftool.physics.inertia import assess
from urdftool.physics.linkmass import TYPICAL_DENSITY, Sources, geometry_sources, geometry_tensor
from urdftool.physics.vec3 import Tensor3

#: Entries below this (kg·m²) print and count as zero.
ZERO_TENSOR = 1e-15


def fmt(value: float) -> str:
    """A number with three significant digits, as a URDF author would write it."""
    return f"{value:.3g}"


def fmt_tensor(tensor: Matrix | Tensor3) -> str:
    """``ixx=… iyy=… izz=…`` plus the non-zero products of inertia, in kg·m²."""
    rows = tensor if isinstance(tensor, tuple) else tensor.tolist()
    scale = max(ZERO_TENSOR, *(abs(v) for row in rows for v in row))
    diagonal = (rows[0][0], rows[1][1], rows[2][2])
    first = diagonal[0]
    # numpy.allclose(diagonal, first, rtol=1e-3, atol=0): infinities equal only themselves
    if all(d == first or abs(d - first) <= 1e-3 * abs(first) for d in diagonal):
        text = f"ixx=iyy=izz={fmt(first)}"
    elif abs(diagonal[0] - diagonal[1]) <= 1e-3 * scale:
        text = f"ixx=iyy={fmt(diagonal[0])} izz={fmt(diagonal[2])}"
    else:
        text = f"ixx={fmt(diagonal[0])} iyy={fmt(diagonal[1])} izz={fmt(diagonal[2])}"
    for name, (i, j) in (("ixy", (0, 1)), ("ixz", (0, 2)), ("iyz", (1, 2))):
        if abs(rows[i][j]) > 1e-6 * scale:
            text += f" {name}={fmt(rows[i][j])}"
    return text


#: An entry of a computed tensor this small against its largest is a rounding residue.
RESIDUE = 1e-12


def tensor_rows(tensor: Matrix | Tensor3) -> list[list[float]]:
    """*tensor* as three rows for a finding's ``data``, its rounding residues written as 0.0.

    A product of inertia that is zero in exact arithmetic comes out of the rotations and sums as
    a residue (1e-26 beside moments of 1e-2) whose digits depend on the order of the operations;
    JSON readers would see noise that changes between versions."""
    rows = tensor if isinstance(tensor, tuple) else tensor.tolist()
    scale = max((abs(v) for row in rows for v in row), default=0.0)
    floor = RESIDUE * scale if math.isfinite(scale) else 0.0
    return [[0.0 if abs(v) < floor else float(v) for v in row] for row in rows]


def tensor_data(tensor: Matrix) -> dict[str, Any]:
    """The six URDF components of a tensor, for a finding's ``data``."""
    t = np.asarray(tensor, dtype=float)
    return {
        "inertia": {
            "ixx": t[0, 0],
            "ixy": t[0, 1],
            "ixz": t[0, 2],
            "iyy": t[1, 1],
            "iyz": t[1, 2],
            "izz": t[2, 2],
        }
    }


def is_zero_tensor(tensor: Matrix) -> bool:
    """True for a tensor written as all zeros: a deliberate point mass.

    Exactly zero, not "small": ``ixz="1.35e-20"`` with zero moments is numeric
    residue from a converter, and MuJoCo refuses it as not positive definite.
    """
    return not np.any(np.asarray(tensor, dtype=float))


def is_zero_inertia(inertial: Inertial) -> bool:
    """:func:`is_zero_tensor` of the tensor as written, read from its six numbers without
    building the matrix (every inertia rule asks it of every link): -0 is zero too, NaN is not."""
    return inertial.inertia == _ZERO_INERTIA


_ZERO_INERTIA = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))


def suggested_mass(link: Link, sources: Sources | None = None) -> str | None:
    """A help text with the mass the link's geometry has at a typical density, if measurable
    (*sources*: the link's geometry, already measured)."""
    for source, solid in (geometry_sources(link) if sources is None else sources):
        mass = solid.volume * TYPICAL_DENSITY
        tensor = solid.inertia_for_mass(mass)
        return (
            f"its {source} geometry ({solid.label}) would weigh {fmt(mass)} kg at "
            f"{TYPICAL_DENSITY:.0f} kg/m³, with {fmt_tensor(tensor)} in the link frame"
        )
    return None


def valid_tensor_help(link: Link, sources: Sources | None = None) -> str | None:
    """A help text with the tensor of the link's geometry at its mass, in the inertial frame
    (*sources*: the link's geometry, already measured)."""
    if link.inertial is None or link.inertial.mass <= 0:
        return None
    for source, solid in (geometry_sources(link) if sources is None else sources):
        computed = geometry_tensor(link, solid)
        if computed is not None and assess(computed).valid:
            return (
                f"a uniform {solid.label} ({source} geometry) of {fmt(link.inertial.mass)} kg has, "
                f"in the inertial frame, {fmt_tensor(computed)}"
            )
    return None
