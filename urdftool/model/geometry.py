"""Shapes of visual and collision elements, in metres, in the element's own frame.

Cylinders and capsules have their axis along local z, centred at the origin, as
in URDF, SDF and MJCF alike.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from urdftool.model.pose import Vec3
from urdftool.source import Span


@dataclass(frozen=True)
class Box:
    """Axis-aligned box with full edge lengths ``size`` (m)."""

    size: Vec3
    span: Span | None = field(default=None, compare=False)

    kind = "box"


@dataclass(frozen=True)
class Cylinder:
    """Cylinder along local z: ``radius`` and full ``length`` (m)."""

    radius: float
    length: float
    span: Span | None = field(default=None, compare=False)

    kind = "cylinder"


@dataclass(frozen=True)
class Sphere:
    radius: float
    span: Span | None = field(default=None, compare=False)

    kind = "sphere"


@dataclass(frozen=True)
class Capsule:
    """Capsule along local z: ``radius`` and ``length`` of the cylindrical part (m)."""

    radius: float
    length: float
    span: Span | None = field(default=None, compare=False)

    kind = "capsule"


@dataclass(frozen=True)
class Ellipsoid:
    """Ellipsoid with semi-axes ``radii`` (m) along local x, y, z (SDF)."""

    radii: Vec3
    span: Span | None = field(default=None, compare=False)

    kind = "ellipsoid"


@dataclass(frozen=True)
class Plane:
    """Infinite plane through the origin with ``normal`` (SDF); ``size`` is for display."""

    normal: Vec3 = (0.0, 0.0, 1.0)
    size: tuple[float, float] = (0.0, 0.0)
    span: Span | None = field(default=None, compare=False)

    kind = "plane"


@dataclass(frozen=True)
class Mesh:
    """A mesh file.

    ``filename`` is the URI as written (``package://pkg/meshes/x.stl``);
    ``resolved`` the absolute path it resolved to, or ``None`` when it did not.
    ``scale`` multiplies the file's vertex coordinates.
    """

    filename: str
    resolved: str | None = None
    scale: Vec3 = (1.0, 1.0, 1.0)
    span: Span | None = field(default=None, compare=False)

    kind = "mesh"


Geometry = Box | Cylinder | Sphere | Capsule | Ellipsoid | Plane | Mesh
