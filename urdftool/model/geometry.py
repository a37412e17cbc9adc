"""Shapes of visual and collision elements, in metres, in the element's own frame.

Cylinders and capsules have their axis along local z, centred at the origin, as
in URDF, SDF and MJCF alike.
"""

from __future__ import annotations

from dataclasses import field

from urdftool.model.pose import Vec3
from urdftool.records import record
from urdftool.source import Span


@record
class Box:
    """Axis-aligned box with full edge lengths ``size`` (m)."""

    size: Vec3
    span: Span | None = field(default=None, compare=False)

    kind = "box"


@record
class Cylinder:
    """Cylinder along local z: ``radius`` and full ``length`` (m)."""

    radius: float
    length: float
    span: Span | None = field(default=None, compare=False)

    kind = "cylinder"


@record
class Sphere:
    radius: float
    span: Span | None = field(default=None, compare=False)

    kind = "sphere"


@record
class Capsule:
    """Capsule along local z: ``radius`` and ``length`` of the cylindrical part (m)."""

    radius: float
    length: float
    span: Span | None = field(default=None, compare=False)

    kind = "capsule"


@record
class Ellipsoid:
    """Ellipsoid with semi-axes ``radii`` (m) along local x, y, z (SDF)."""

    radii: Vec3
    span: Span | None = field(default=None, compare=False)

    kind = "ellipsoid"


@record
class Plane:
    """Infinite plane through the origin with ``normal`` (SDF); ``size`` is for display."""

    normal: Vec3 = (0.0, 0.0, 1.0)
    size: tuple[float, float] = (0.0, 0.0)
    span: Span | None = field(default=None, compare=False)

    kind = "plane"


@record
class Resolution:
    """How a reader resolved one URI: the file it led to (``None`` when none), every place it
    looked, and the package or model it went through."""

    path: str | None
    tried: tuple[str, ...] = ()
    package: str | None = None
    #: the package itself was not found (as opposed to a missing file inside it)
    package_missing: bool = False
    #: for a URI inside a package or model that was found: that package's folder
    package_dir: str | None = None


@record
class Mesh:
    """A mesh file.

    ``filename`` is the URI as written (``package://pkg/meshes/x.stl``);
    ``resolved`` the absolute path it resolved to, or ``None`` when it did not.
    ``scale`` multiplies the file's vertex coordinates. ``resolution`` records
    how the reader resolved the URI (where it looked), so later stages never
    resolve it again.
    """

    filename: str
    resolved: str | None = None
    scale: Vec3 = (1.0, 1.0, 1.0)
    span: Span | None = field(default=None, compare=False)
    resolution: Resolution | None = field(default=None, compare=False)

    kind = "mesh"


Geometry = Box | Cylinder | Sphere | Capsule | Ellipsoid | Plane | Mesh
