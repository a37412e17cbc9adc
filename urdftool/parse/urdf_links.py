"""The parts of a URDF ``<link>``: inertial, visuals, collisions, their geometry and materials,
read as urdfdom reads them with every problem located. A mixin of
:class:`~urdftool.parse.urdf.UrdfReader`, which supplies the value reader, the span lookup, the
children and attribute checks, the origin reader, the package resolver and the report."""

from __future__ import annotations

from collections.abc import Callable

from lxml import etree

from urdftool.catalogue.suggest import did_you_mean
from urdftool.catalogue.syntax import MissingAttribute, MissingElement, RepeatedElement, UnknownElement
from urdftool.diagnostics import Diagnostic
from urdftool.model import (
    Box,
    Capsule,
    Collision,
    Cylinder,
    Geometry,
    Inertial,
    Material,
    Mesh,
    Pose,
    Sphere,
    Visual,
)
from urdftool.parse.packages import PackageResolver
from urdftool.parse.values import ValueReader
from urdftool.source import Span

_UNSCALED = (1.0, 1.0, 1.0)
_INERTIA_COMPONENTS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
#: the shapes of a ``<geometry>`` (``<capsule>`` is not URDF, but PyBullet and MuJoCo read it)
_SHAPES = frozenset({"box", "cylinder", "sphere", "mesh", "capsule"})


class LinkParts:
    """Reads the parts of a link; the reader supplies what these methods use."""

    path: str
    values: ValueReader
    resolver: PackageResolver
    span: Callable[[etree._Element], Span | None]

    def _report(self, diagnostic: Diagnostic) -> None:
        raise NotImplementedError

    def _check_attributes(self, element: etree._Element, tag: str, where: str) -> None:
        raise NotImplementedError

    def _children(self, element: etree._Element, parent: str, where: str) -> dict[str, list[etree._Element]]:
        raise NotImplementedError

    def _origin(self, groups: dict[str, list[etree._Element]], where: str) -> Pose:
        raise NotImplementedError

    def _inertial(self, element: etree._Element, where: str) -> Inertial | None:
        here = f"{where}/inertial"
        groups = self._children(element, "inertial", here)
        origin = self._origin(groups, here)
        mass_el = groups["mass"][0] if "mass" in groups else None
        inertia_el = groups["inertia"][0] if "inertia" in groups else None
        if mass_el is None or inertia_el is None:
            for tag, el in (("mass", mass_el), ("inertia", inertia_el)):
                if el is None:
                    self._report(
                        MissingElement.diagnostic(
                            f"{here}: <inertial> has no <{tag}>", self.span(element), element=here
                        )
                    )
        mass = 0.0
        if mass_el is not None:
            self._check_attributes(mass_el, "mass", f"{here}/mass")
            value = self.values.number(mass_el, "value", f"{here}/mass", required=True)
            mass = value if value is not None else 0.0
        components = [0.0] * 6  # ixx, ixy, ixz, iyy, iyz, izz
        if inertia_el is not None:
            at = f"{here}/inertia"
            self._check_attributes(inertia_el, "inertia", at)
            for index, key in enumerate(_INERTIA_COMPONENTS):
                value = self.values.number(inertia_el, key, at, required=True)
                if value is not None:
                    components[index] = value
        tensor = Inertial.tensor(*components)
        return Inertial(  # mass, inertia, origin, span, mass_span, inertia_span
            mass,
            tensor,
            origin,
            self.span(element),
            self.span(mass_el) if mass_el is not None else None,
            self.span(inertia_el) if inertia_el is not None else None,
        )

    def _visual(self, element: etree._Element, where: str) -> Visual:
        self._check_attributes(element, "visual", where)
        groups = self._children(element, "visual", where)
        material = None
        if "material" in groups:
            material = self._material(groups["material"][0], f"{where}/material")
        # (geometry, origin, name, material, span: by position, as the parts below are built; a call
        # by keywords builds a dict of them)
        return Visual(
            self._geometry("visual", element, groups, where),
            self._origin(groups, where),
            element.get("name"),
            material,
            self.span(element),
        )

    def _collision(self, element: etree._Element, where: str) -> Collision:
        self._check_attributes(element, "collision", where)
        groups = self._children(element, "collision", where)
        return Collision(  # geometry, origin, name, span
            self._geometry("collision", element, groups, where),
            self._origin(groups, where),
            element.get("name"),
            self.span(element),
        )

    def _geometry(
        self, tag: str, parent: etree._Element, groups: dict[str, list[etree._Element]], where: str
    ) -> Geometry | None:
        """The shape of *parent* (a ``<visual>`` or ``<collision>``, as *tag* says)."""
        items = groups.get("geometry")
        if not items:
            self._report(
                MissingElement.diagnostic(
                    f"{where}: <{tag}> has no <geometry>", self.span(parent), element=where
                )
            )
            return None
        geometry = items[0]
        here = f"{where}/geometry"
        known: list[tuple[str, etree._Element]] = []  # the shapes, each with its tag
        others = False
        for child in geometry[:]:  # (the children listed in C, as UrdfReader._children does)
            name = child.tag
            if name in _SHAPES:
                known.append((name, child))
            elif isinstance(name, str):  # an element, not a comment kept by xacro
                others = True
                self._report(
                    UnknownElement.diagnostic(
                        f"{here}: <geometry> has no shape <{name}>"
                        + did_you_mean(name, ["box", "cylinder", "sphere", "mesh"]),
                        self.span(child),
                        element=here,
                    )
                )
        if not known:
            if not others:
                self._report(
                    MissingElement.diagnostic(
                        f"{here}: <geometry> has no shape (box, cylinder, sphere or mesh)",
                        self.span(geometry),
                        element=here,
                    )
                )
            return None
        kind, shape = known[0]
        for extra, element in known[1:]:
            self._report(
                RepeatedElement.diagnostic(
                    f"{here}: <geometry> has more than one shape; <{kind}> is used, "
                    f"<{extra}> ignored",
                    self.span(element),
                    element=here,
                )
            )
        return self._shape(shape, kind, f"{here}/{kind}")

    def _shape(self, shape: etree._Element, kind: str, where: str) -> Geometry | None:
        """The ``<box>``, ``<sphere>``, ``<cylinder>``, ``<capsule>`` or ``<mesh>`` *shape*, as
        *kind* (its tag) says."""
        self._check_attributes(shape, kind, where)
        v = self.values
        span = self.span(shape)
        if kind == "box":
            size = v.vector(shape, "size", where, required=True)
            return Box(size, span) if size else None
        if kind == "sphere":
            radius = v.number(shape, "radius", where, required=True)
            return Sphere(radius, span) if radius is not None else None
        if kind in ("cylinder", "capsule"):
            radius = v.number(shape, "radius", where, required=True)
            length = v.number(shape, "length", where, required=True)
            if kind == "capsule":
                self._report(
                    UnknownElement.diagnostic(
                        f"{where}: <capsule> is not URDF (PyBullet and MuJoCo read it; urdfdom, "
                        "ROS and Gazebo reject it)",
                        span,
                        element=where,
                        help="use a cylinder (and two spheres) for portability",
                    )
                )
            if radius is None or length is None:
                return None
            return (
                Cylinder(radius, length, span) if kind == "cylinder" else Capsule(radius, length, span)
            )
        filename = v.text(shape, "filename", where, required=True)
        if filename is None:
            return None
        scale = v.vector(shape, "scale", where) or _UNSCALED
        found = self.resolver.resolution(filename, span.path if span else self.path)
        return Mesh(filename, found.path, scale, span, found)

    def _material(self, element: etree._Element, where: str) -> Material:
        name = element.get("name")
        if where == "robot/material" and not name:
            self._report(
                MissingAttribute.diagnostic(
                    "top-level <material> needs a 'name' attribute", self.span(element), element=where
                )
            )
        here = f"{where}[{name}]" if where == "robot/material" else where
        self._check_attributes(element, "material", here)
        groups = self._children(element, "material", here)
        color = None
        texture = None
        if "color" in groups:
            self._check_attributes(groups["color"][0], "color", f"{here}/color")
            rgba = self.values.vector(groups["color"][0], "rgba", f"{here}/color", length=4, required=True)
            color = (rgba[0], rgba[1], rgba[2], rgba[3]) if rgba else None
        if "texture" in groups:
            self._check_attributes(groups["texture"][0], "texture", f"{here}/texture")
            texture = groups["texture"][0].get("filename")
        return Material(name, color, texture, self.span(element))

    # -- joints ------------------------------------------------------------------
