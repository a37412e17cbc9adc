"""Visual and collision geoms of one link.

Visual geoms use the default class ``visual`` (group 2, contype and
conaffinity 0: seen, never touched) with their colour: a COLLADA mesh's own
materials (one geom per colour), else the URDF material's; collision
geoms use the class ``collision`` (group 3). Sizes follow MJCF: half extents
for boxes, radius and half length for cylinders and capsules.

An SDF model's links collide with each other only where ``<self_collide>`` asks
(SDFormat's default is off); MuJoCo collides every pair of bodies not joined by a
joint. The collision geoms of a link that does not self-collide carry
:data:`NO_SELF_CONTACT` so that the exported robot touches what its source touches.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from lxml import etree

from urdftool.catalogue.conversion import ConversionDropped, MeshNotExportable
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.export.assets import MeshUnavailable
from urdftool.export.mjcf_assets import AssetPlan
from urdftool.export.mjcf_format import pose_attributes
from urdftool.export.numbers import num, vec
from urdftool.model import (
    Box,
    Capsule,
    Cylinder,
    Ellipsoid,
    Geometry,
    Link,
    Material,
    Mesh,
    Plane,
    Robot,
    Sphere,
)
from urdftool.model.pose import Pose
from urdftool.physics.sdf_defaults import sdf_self_colliding
from urdftool.source import Span

VISUAL_CLASS = "visual"
COLLISION_CLASS = "collision"
VISUAL_GROUP = 2
COLLISION_GROUP = 3
#: MuJoCo pairs two geoms when ``contype`` of either shares a bit with ``conaffinity`` of the
#: other. A link that does not self-collide has bit 1 in ``conaffinity`` and only bit 2 in
#: ``contype``: two such links never pair (2 & 1 = 0 both ways), but each still pairs with the
#: floor, the world and the self-colliding links, which keep MuJoCo's default (1, 1).
NO_SELF_CONTACT = {"contype": "2", "conaffinity": "1"}


def shape_attributes(geometry: Geometry, mesh_name: Callable[[Mesh], str]) -> dict[str, str]:
    """``type`` and ``size`` (or ``mesh``) of a geometry. Raises :class:`MeshUnavailable`."""
    if isinstance(geometry, Box):
        return {"type": "box", "size": vec(s / 2 for s in geometry.size)}
    if isinstance(geometry, Cylinder):
        return {"type": "cylinder", "size": vec((geometry.radius, geometry.length / 2))}
    if isinstance(geometry, Capsule):
        return {"type": "capsule", "size": vec((geometry.radius, geometry.length / 2))}
    if isinstance(geometry, Sphere):
        return {"type": "sphere", "size": num(geometry.radius)}
    if isinstance(geometry, Ellipsoid):
        return {"type": "ellipsoid", "size": vec(geometry.radii)}
    if isinstance(geometry, Plane):
        return {"type": "plane", "size": vec((geometry.size[0] / 2, geometry.size[1] / 2, 1.0))}
    return {"type": "mesh", "mesh": mesh_name(geometry)}


def _degenerate(geometry: Geometry) -> bool:
    """Shapes MuJoCo refuses: zero or negative sizes."""
    if isinstance(geometry, Box):
        return min(geometry.size) <= 0
    if isinstance(geometry, (Cylinder, Capsule)):
        return geometry.radius <= 0 or geometry.length < 0 or (
            isinstance(geometry, Cylinder) and geometry.length <= 0)
    if isinstance(geometry, Sphere):
        return geometry.radius <= 0
    if isinstance(geometry, Ellipsoid):
        return min(geometry.radii) <= 0
    return False


#: Sliding friction written to MJCF at most: Gazebo files write 1e5 for "never slips", which makes
#: MuJoCo's friction cone stiff to solve; 3 is beyond any rubber on concrete (about 1) and slips
#: no more in practice.
MU_MAX = 3.0


def _friction_value(element: etree._Element) -> float | None:
    """The number a ``<mu1>``/``<mu2>`` holds (text, or a ``value`` attribute), when it is a
    friction coefficient (finite, not negative)."""
    text = element.get("value") or element.text or ""
    try:
        value = float(text.strip())
    except ValueError:
        return None
    return value if math.isfinite(value) and value >= 0.0 else None


def gazebo_friction_elements(robot: Robot) -> dict[str, dict[str, etree._Element]]:
    """Per link that exists, the ``<mu1>``/``<mu2>`` elements of its ``<gazebo reference="LINK">``
    blocks that hold a coefficient (a later block's overrides an earlier one's)."""
    found: dict[str, dict[str, etree._Element]] = {}
    for extension in robot.extensions:
        element = extension.element
        reference = element.get("reference") if element is not None else None
        if extension.tag != "gazebo" or not reference or robot.link(reference) is None:
            continue
        for tag in ("mu1", "mu2"):
            child = element.find(tag)
            if child is not None and _friction_value(child) is not None:
                found.setdefault(reference, {})[tag] = child
    return found


def gazebo_friction(robot: Robot) -> dict[str, float]:
    """Sliding friction per link from ``<gazebo reference="LINK"><mu1>/<mu2>``: the smaller of the
    two (MuJoCo's friction is isotropic; Gazebo's ODE reads mu1 along ``fdir1`` and mu2 across it,
    so the smaller is the one a wheel or foot can rely on in every direction)."""
    return {link: min(v for v in (_friction_value(e) for e in elements.values()) if v is not None)
            for link, elements in gazebo_friction_elements(robot).items()}


def carried_friction(robot: Robot) -> list[etree._Element]:
    """Every ``<mu1>``/``<mu2>`` element whose value the export writes (the smaller of a link's
    two, or both when they are equal); the others are lost, and reported. Compare with ``is``:
    lxml hands out the same proxy for an element while one is alive, which this list keeps."""
    carried: list[etree._Element] = []
    for elements in gazebo_friction_elements(robot).values():
        values = {tag: _friction_value(e) for tag, e in elements.items()}
        least = min(v for v in values.values() if v is not None)
        carried.extend(elements[tag] for tag, value in values.items() if value == least)
    return carried


class GeomWriter:
    """Writes a link's geoms into its body, collecting what could not be carried."""

    def __init__(self, robot: Robot, assets: AssetPlan, diagnostics: list[Diagnostic]):
        self.assets = assets
        self.diagnostics = diagnostics
        self.materials = {m.name: m for m in robot.materials if m.name}
        self.friction = gazebo_friction(robot)
        #: ``None``: every link collides with every other (URDF); else the SDF links that do
        self.self_colliding = sdf_self_colliding(robot)

    def write(self, body: etree._Element, link: Link, moving: bool) -> None:
        for index, visual in enumerate(link.visuals):
            where = f"link[{link.name}]/visual[{index}]"
            shapes = self._shapes(visual.geometry, visual.origin, where, moving, visual.span, visual=True)
            if not shapes:
                continue
            colour = self._colour(visual.material, where)
            for attrs, material in shapes:
                # the mesh's own material wins over the URDF's colour, as in RViz (docs/mjcf.md)
                if material is not None:
                    attrs["material"] = material
                elif colour is not None:
                    attrs["rgba"] = vec(colour)
                etree.SubElement(body, "geom", {"class": VISUAL_CLASS, **attrs})
        for index, collision in enumerate(link.collisions):
            where = f"link[{link.name}]/collision[{index}]"
            shapes = self._shapes(collision.geometry, collision.origin, where, moving, collision.span)
            for attrs, _ in shapes:
                mu = self.friction.get(link.name)
                if mu is not None:  # MuJoCo's default torsional and rolling friction are kept
                    attrs["friction"] = f"{min(mu, MU_MAX):g} 0.005 0.0001"
                if self.self_colliding is not None and link.name not in self.self_colliding:
                    attrs.update(NO_SELF_CONTACT)
                etree.SubElement(body, "geom", {"class": COLLISION_CLASS, **attrs})

    def _shapes(self, geometry: Geometry | None, origin: Pose, where: str, moving: bool,
                span: Span | None, visual: bool = False) -> list[tuple[dict[str, str], str | None]]:
        """Geom attributes with the ``<material>`` of each (``None``: no colour of its own): one
        geom, or for a visual COLLADA mesh of several colours one per colour. Empty when the
        shape is left out (and reported)."""
        if geometry is None:
            return []
        location = geometry.span or span
        if _degenerate(geometry):
            self._drop(f"{where}: {geometry.kind} with a zero or negative size", location, where)
            return []
        if isinstance(geometry, Plane) and moving:
            self._drop(f"{where}: MuJoCo allows planes only on static bodies", location, where)
            return []
        pose = pose_attributes(origin)
        try:
            if visual and isinstance(geometry, Mesh):
                return [({"type": "mesh", "mesh": part.mesh, **pose}, part.material)
                        for part in self.assets.visual_parts(geometry)]
            return [({**shape_attributes(geometry, self.assets.mesh_name), **pose}, None)]
        except MeshUnavailable as exc:
            role = "collision shape" if "/collision" in where else "visual"
            self.diagnostics.append(MeshNotExportable.diagnostic(
                f"{where}: mesh left out ({role}): {exc}", location, element=where,
                data={"filename": getattr(geometry, "filename", None), "role": role}))
            return []

    def _colour(self, material: Material | None, where: str) -> tuple[float, ...] | None:
        if material is None:
            return None
        named = self.materials.get(material.name) if material.name else None
        colour = material.color or (named.color if named else None)
        texture = material.texture or (named.texture if named else None)
        if texture:
            self.diagnostics.append(ConversionDropped.diagnostic(
                f"{where}: texture '{texture}' is not carried (only the colour is)",
                material.span, element=f"{where}/material", severity=Severity.INFO,
                data={"element": "texture", "reason": "textures are not exported"}))
        return colour

    def _drop(self, message: str, location, where: str) -> None:  # type: ignore[no-untyped-def]
        self.diagnostics.append(ConversionDropped.diagnostic(
            message + "; the geom is left out", location, element=where,
            data={"element": where, "reason": message}))
