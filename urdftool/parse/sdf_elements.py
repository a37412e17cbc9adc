"""Reading what a ``<link>`` and a ``<joint>`` hold: inertial, shapes, materials, axis, limits.

Poses here are returned as written: an inertial's in the link frame, a
visual's or collision's in the frame its ``relative_to`` names (the model
reader places them in the link frame). Defaults follow the SDF specification:
an ``<inertial>`` without ``<mass>`` has 1 kg, without ``<inertia>`` a unit
diagonal; a joint limit of ±1e16 means "no limit", an effort or velocity of
-1 means "unlimited".
"""

from __future__ import annotations

import dataclasses

from lxml import etree

from urdftool.catalogue.suggest import did_you_mean
from urdftool.catalogue.syntax import MissingElement, UnknownElement, UnknownJointType
from urdftool.diagnostics import Severity
from urdftool.model import (
    Box,
    Capsule,
    Collision,
    Cylinder,
    Dynamics,
    Ellipsoid,
    Geometry,
    Inertial,
    JointType,
    Limit,
    Material,
    Mesh,
    Mimic,
    Plane,
    Sphere,
    Visual,
)
from urdftool.parse.locate import span_of
from urdftool.parse.packages import PackageResolver
from urdftool.parse.sdf_spec import custom_element
from urdftool.parse.sdf_values import SdfValues
from urdftool.records import record
from urdftool.source import Span

#: SDF joint type -> model type (``ball`` is the model's SPHERICAL)
JOINT_TYPES: dict[str, JointType] = {
    "revolute": JointType.REVOLUTE,
    "continuous": JointType.CONTINUOUS,
    "prismatic": JointType.PRISMATIC,
    "fixed": JointType.FIXED,
    "ball": JointType.SPHERICAL,
    "universal": JointType.UNIVERSAL,
    "revolute2": JointType.REVOLUTE2,
    "screw": JointType.SCREW,
    "gearbox": JointType.GEARBOX,
}

#: |limit| at or beyond this is SDF's "no limit" (the specification's default is 1e16)
NO_LIMIT = 1e15

SHAPES = ("box", "cylinder", "sphere", "capsule", "ellipsoid", "plane", "mesh")
#: shapes SDF defines that the model does not carry (reported as unknown-element warnings)
UNSUPPORTED_SHAPES = ("heightmap", "polyline", "image", "cone", "empty")


@record(frozen=False)
class PlacedElement:
    """A visual or collision with its pose as written and the frame it is relative to."""

    item: Visual | Collision
    relative_to: str | None
    pose_span: object | None


@record(frozen=False)
class LinkBodyReader:
    """Reads inertial, visual and collision elements of SDF links."""

    values: SdfValues
    resolver: PackageResolver
    path: str

    def inertial(self, element: etree._Element, where: str) -> Inertial:
        """The link's ``<inertial>``, pose in the link frame (SDF allows no ``relative_to`` here)."""
        here = f"{where}/inertial"
        v = self.values
        mass = v.text_number(element, "mass", here, 1.0)
        inertia_el = v.child(element, "inertia")
        moments = {"ixx": 1.0, "iyy": 1.0, "izz": 1.0, "ixy": 0.0, "ixz": 0.0, "iyz": 0.0}
        for key, default in list(moments.items()):
            value = v.text_number(inertia_el, key, f"{here}/inertia", default)
            moments[key] = default if value is None else value
        mass_el = v.child(element, "mass")
        return Inertial(
            mass=1.0 if mass is None else mass,
            inertia=Inertial.tensor(**moments),
            origin=v.pose(v.child(element, "pose"), f"{here}/pose"),
            span=span_of(element),
            mass_span=span_of(mass_el) if mass_el is not None else None,
            inertia_span=span_of(inertia_el) if inertia_el is not None else None,
        )

    def visual(self, element: etree._Element, where: str) -> PlacedElement:
        name = element.get("name")
        here = f"{where}/visual[{name}]" if name else f"{where}/visual"
        pose_el = self.values.child(element, "pose")
        visual = Visual(
            geometry=self.geometry(element, here),
            origin=self.values.pose(pose_el, f"{here}/pose"),
            name=name,
            material=self.material(self.values.child(element, "material")),
            span=span_of(element),
        )
        return PlacedElement(visual, _relative_to(pose_el), span_of(pose_el) if pose_el is not None else None)

    def collision(self, element: etree._Element, where: str) -> PlacedElement:
        name = element.get("name")
        here = f"{where}/collision[{name}]" if name else f"{where}/collision"
        pose_el = self.values.child(element, "pose")
        collision = Collision(
            geometry=self.geometry(element, here),
            origin=self.values.pose(pose_el, f"{here}/pose"),
            name=name,
            span=span_of(element),
        )
        return PlacedElement(
            collision, _relative_to(pose_el), span_of(pose_el) if pose_el is not None else None
        )

    def geometry(self, parent: etree._Element, where: str) -> Geometry | None:
        geometry = self.values.child(parent, "geometry")
        if geometry is None:
            self.values.diagnostics.append(
                MissingElement.diagnostic(
                    f"{where}: <{parent.tag}> has no <geometry>", span_of(parent), element=where,
                    severity=Severity.WARNING,  # libsdformat adds an empty default geometry
                )
            )
            return None
        # A namespaced shape (<drake:ellipsoid>, Drake's own) is a custom element: libsdformat
        # keeps it and ignores it, the tool it is written for reads it.
        shapes = [c for c in geometry if isinstance(c.tag, str) and not custom_element(c.tag)]
        if not shapes and any(isinstance(c.tag, str) for c in geometry):
            return None
        known = [c for c in shapes if c.tag in SHAPES]
        for other in shapes:
            if other.tag not in SHAPES:
                supported = other.tag in UNSUPPORTED_SHAPES
                self.values.diagnostics.append(
                    UnknownElement.diagnostic(
                        f"{where}/geometry: <{other.tag}> "
                        + ("is an SDF shape urdftool does not model; it is skipped" if supported
                           else "is not an SDF shape" + did_you_mean(other.tag, SHAPES)),
                        span_of(other),
                        element=f"{where}/geometry",
                    )
                )
        if not known:
            if not shapes:
                self.values.diagnostics.append(
                    MissingElement.diagnostic(
                        f"{where}: <geometry> has no shape", span_of(geometry), element=where,
                        severity=Severity.WARNING,  # libsdformat loads an empty geometry
                    )
                )
            return None
        return self.shape(known[0], f"{where}/geometry/{known[0].tag}")

    def shape(self, shape: etree._Element, where: str) -> Geometry | None:
        v = self.values
        span = span_of(shape)
        tag = shape.tag
        if tag == "box":
            size = v.text_vector(shape, "size", where) or (1.0, 1.0, 1.0)
            return Box((size[0], size[1], size[2]), span)
        if tag == "sphere":
            return Sphere(v.text_number(shape, "radius", where, 1.0) or 0.0, span)
        if tag in ("cylinder", "capsule"):
            radius = v.text_number(shape, "radius", where, 1.0 if tag == "cylinder" else 0.5) or 0.0
            length = v.text_number(shape, "length", where, 1.0) or 0.0
            return Cylinder(radius, length, span) if tag == "cylinder" else Capsule(radius, length, span)
        if tag == "ellipsoid":
            radii = v.text_vector(shape, "radii", where) or (1.0, 1.0, 1.0)
            return Ellipsoid((radii[0], radii[1], radii[2]), span)
        if tag == "plane":
            normal = v.text_vector(shape, "normal", where) or (0.0, 0.0, 1.0)
            size = v.text_vector(shape, "size", where, 2) or (1.0, 1.0)
            return Plane((normal[0], normal[1], normal[2]), (size[0], size[1]), span)
        return self.mesh(shape, where)

    def mesh(self, shape: etree._Element, where: str) -> Mesh | None:
        v = self.values
        uri_el = v.child(shape, "uri")
        uri = (uri_el.text or "").strip() if uri_el is not None else ""
        if not uri:
            v.diagnostics.append(
                MissingElement.diagnostic(f"{where}: <mesh> has no <uri>", span_of(shape), element=where)
            )
            return None
        scale = v.text_vector(shape, "scale", where) or (1.0, 1.0, 1.0)
        span = span_of(uri_el)
        found = self.resolver.resolution(uri, span.path if span else self.path)
        return Mesh(uri, found.path, (scale[0], scale[1], scale[2]), span_of(shape), found)

    def material(self, element: etree._Element | None) -> Material | None:
        """Colour from ``<diffuse>`` (else ``<ambient>``); a script name alone carries no colour."""
        if element is None:
            return None
        v = self.values
        color = None
        for tag in ("diffuse", "ambient"):
            rgba = (
                v.text_numbers(v.child(element, tag), f"material/{tag}", (3, 4))
                if v.child(element, tag) is not None
                else None
            )
            if rgba:
                color = (rgba[0], rgba[1], rgba[2], rgba[3] if len(rgba) == 4 else 1.0)
                break
        if color is None:
            return None
        return Material(None, color, None, span_of(element))


def _relative_to(pose: etree._Element | None) -> str | None:
    if pose is None:
        return None
    value = pose.get("relative_to") or pose.get("frame")
    return value or None


@record(frozen=False)
class JointDetails:
    """A joint's type, axis as written (and the frame it is expressed in), limit and dynamics."""

    type: JointType
    axis: tuple[float, float, float]
    #: "joint" (the joint frame), "model" (``use_parent_model_frame``/SDF 1.4) or a frame name
    axis_frame: str
    limit: Limit | None
    dynamics: Dynamics | None
    axis_span: object | None
    #: the second axis of a universal or revolute2 joint, as written, with its frame and limit
    axis2: tuple[float, float, float] | None = None
    axis2_frame: str = "joint"
    limit2: Limit | None = None


def joint_type(values: SdfValues, element: etree._Element, where: str) -> JointType:
    raw = element.get("type")
    if raw is None:
        values.diagnostics.append(
            MissingElement.diagnostic(f"{where}: <joint> needs a 'type' attribute (read as fixed)",
                                      span_of(element), element=where)
        )
        return JointType.FIXED
    if raw in JOINT_TYPES:
        return JOINT_TYPES[raw]
    values.diagnostics.append(
        UnknownJointType.diagnostic(
            f'{where}: unknown SDF joint type "{raw}"' + did_you_mean(raw, JOINT_TYPES) + " (read as fixed)",
            values.attr_span(element, "type"),
            element=where,
            data={"type": raw},
        )
    )
    return JointType.FIXED


def joint_details(
    values: SdfValues, element: etree._Element, where: str, version: tuple[int, int]
) -> JointDetails:
    """Type, axis, limit and dynamics of one ``<joint>``; SDF 1.4 axes are in the model frame."""
    jtype = joint_type(values, element, where)
    axis_el = values.child(element, "axis")
    here = f"{where}/axis"
    xyz_el = values.child(axis_el, "xyz")
    xyz = values.text_numbers(xyz_el, f"{here}/xyz", (3,)) if xyz_el is not None else None
    default_axis = (0.0, 0.0, 1.0)
    axis = (xyz[0], xyz[1], xyz[2]) if xyz else default_axis
    frame = "model" if version < (1, 5) else "joint"
    if axis_el is not None and values.child(axis_el, "use_parent_model_frame") is not None:
        frame = "model" if values.text_bool(axis_el, "use_parent_model_frame", here) else "joint"
    if xyz_el is not None and xyz_el.get("expressed_in"):
        frame = xyz_el.get("expressed_in") or "joint"
    limit, dynamics = _limit(values, axis_el, here), _dynamics(values, axis_el, here)
    if jtype is JointType.REVOLUTE and _unbounded(limit):
        jtype = JointType.CONTINUOUS
    details = JointDetails(
        jtype, axis, frame, limit, dynamics, span_of(axis_el) if axis_el is not None else None
    )
    if jtype in (JointType.UNIVERSAL, JointType.REVOLUTE2):
        axis2_el = values.child(element, "axis2")
        here2 = f"{where}/axis2"
        xyz2_el = values.child(axis2_el, "xyz")
        xyz2 = values.text_numbers(xyz2_el, f"{here2}/xyz", (3,)) if xyz2_el is not None else None
        frame2 = "model" if version < (1, 5) else "joint"
        if axis2_el is not None and values.child(axis2_el, "use_parent_model_frame") is not None:
            frame2 = "model" if values.text_bool(axis2_el, "use_parent_model_frame", here2) else "joint"
        if xyz2_el is not None and xyz2_el.get("expressed_in"):
            frame2 = xyz2_el.get("expressed_in") or "joint"
        details = dataclasses.replace(
            details, axis2=(xyz2[0], xyz2[1], xyz2[2]) if xyz2 else (0.0, 1.0, 0.0), axis2_frame=frame2,
            limit2=_limit(values, axis2_el, here2),
        )
    return details


def _unbounded(limit: Limit | None) -> bool:
    return limit is None or limit.lower is None or limit.upper is None


def _limit(values: SdfValues, axis: etree._Element | None, where: str) -> Limit | None:
    element = values.child(axis, "limit")
    if element is None:
        return None
    here = f"{where}/limit"
    lower = values.text_limit(element, "lower", here)
    upper = values.text_limit(element, "upper", here)
    effort = values.text_limit(element, "effort", here)
    velocity = values.text_limit(element, "velocity", here)
    return Limit(
        lower=lower if lower is not None and abs(lower) < NO_LIMIT else None,
        upper=upper if upper is not None and abs(upper) < NO_LIMIT else None,
        effort=effort if effort is not None and 0 <= effort < NO_LIMIT else None,
        velocity=velocity if velocity is not None and 0 <= velocity < NO_LIMIT else None,
        span=span_of(element),
        lower_span=_child_span(values, element, "lower"),
        upper_span=_child_span(values, element, "upper"),
    )


def _child_span(values: SdfValues, element: etree._Element, tag: str) -> Span | None:
    child = values.child(element, tag)
    return span_of(child) if child is not None else None


def _dynamics(values: SdfValues, axis: etree._Element | None, where: str) -> Dynamics | None:
    element = values.child(axis, "dynamics")
    if element is None:
        return None
    here = f"{where}/dynamics"
    damping = values.text_number(element, "damping", here, 0.0)
    friction = values.text_number(element, "friction", here, 0.0)
    stiffness = values.text_number(element, "spring_stiffness", here, 0.0)
    reference = values.text_number(element, "spring_reference", here, 0.0)
    return Dynamics(damping or 0.0, friction or 0.0, span_of(element),
                    spring_stiffness=stiffness or 0.0,  # a negative one is kept for the rule (J011)
                    spring_reference=reference or 0.0)


def mimic(values: SdfValues, joint: etree._Element, where: str) -> Mimic | None:
    """The joint's ``<axis><mimic joint="…">`` (SDFormat 1.11), leader as written (unscoped).

    SDF's follower position is ``multiplier · (leader − reference) + offset``; the model's
    :class:`Mimic` is ``multiplier · leader + offset``, so the reference is folded into the offset.
    """
    element = values.child(values.child(joint, "axis"), "mimic")
    leader = (element.get("joint") or "").strip() if element is not None else ""
    if element is None or not leader:
        return None  # libsdformat requires the attribute; missing-attribute is the file pass's
    here = f"{where}/axis/mimic"
    multiplier = values.text_number(element, "multiplier", here, 1.0)
    offset = values.text_number(element, "offset", here, 0.0)
    reference = values.text_number(element, "reference", here, 0.0)
    factor = 1.0 if multiplier is None else multiplier
    return Mimic(leader, factor, (offset or 0.0) - factor * (reference or 0.0), span_of(element))
