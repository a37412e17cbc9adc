"""Shared ground of the intent rules (N): options, element paths, the robot's size.

Every threshold of an intent rule is a module constant with a rule option of
the same meaning: ``CheckOptions(rule_options={"intent": {"degree_step": 15}})``
(Python API) overrides it for one run. The names are listed in docs/intent.md.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
else:
    from urdftool.lazy import numpy as np

from urdftool.catalogue.registry import Family, Rule
from urdftool.facts import home
from urdftool.facts.context import CheckContext
from urdftool.model import Collision, Joint, KinematicTree, Link, Visual
from urdftool.model.geometry import Box, Capsule, Cylinder, Ellipsoid, Geometry, Mesh, Sphere
from urdftool.model.pose import Matrix, Vec3, vector_norm
from urdftool.physics import vec3

#: Defaults of every intent threshold, by option name (docs/intent.md explains each).
DEFAULTS: dict[str, float] = {
    # units: angles
    "degree_turns": 1.0,  # a limit beyond this many turns (2π·k rad) is not meant as radians
    "degree_step": 0.5,  # ... when it is a multiple of this many degrees (whole or half degrees)
    # units: lengths
    "length_factor": 20.0,  # a travel or size this many times the robot's extent is suspect
    "length_min": 2.0,  # ... and longer than this (m)
    # units: masses
    "grams_density": 100_000.0,  # kg/m³ above which a mass is read as grams
    "grams_min_mass": 10.0,  # ... when it is at least this many (grams of a real part)
    # ROS conventions
    "angle_tolerance_deg": 2.0,  # frame rotations within this are taken as the convention
    "offset_tolerance": 0.005,  # m: base_footprint's horizontal offset from base_link
    # symmetry
    "mirror_length_tolerance": 0.002,  # m, plus the relative tolerance below
    "mirror_relative_tolerance": 0.05,
    "mirror_mass_tolerance": 0.10,  # relative mass difference of a left/right pair
    # self-consistency
    "scale_slip_tolerance": 0.15,  # a size ratio within this of 10, 100 or 1000
    "axisymmetric_tolerance": 0.02,  # two principal moments this close are one
    "mimic_tolerance": 1e-3,  # rad or m beyond the follower's limit
    # joint range against the geometry (N305)
    "sweep_step_deg": 2.0,  # sampling step of the sweep over a joint's range
    "sweep_share": 0.3,  # share of the child's collision volume inside its parent beyond home's
    "sweep_depth_min": 0.01,  # m: ... and this much deeper than at home
    "sweep_margin_deg": 5.0,  # the limit must lie this far beyond where the passing starts
    "sweep_home_share_max": 0.25,  # a child this far inside its parent at home is not judged
}


class IntentRule(Rule):
    family = Family.INTENT
    since = "0.2.0"


def option(ctx: CheckContext, name: str) -> float:
    """The threshold *name*: ``rule_options["intent"][name]`` when given, else the default."""
    given: Any = ctx.options.get("intent")
    if given is None:  # the usual run, without the isinstance check (thousands of calls a check)
        return DEFAULTS[name]
    if isinstance(given, Mapping) and name in given:
        return float(given[name])
    return DEFAULTS[name]


def written(value: float) -> str:
    """A number as its author wrote it (up to six significant digits, no exponent for 1200)."""
    return f"{value:.6g}"


def where_joint(joint: Joint, *parts: str) -> str:
    return "/".join((f"joint[{joint.name}]", *parts))


def where_link(link: Link, *parts: str) -> str:
    return "/".join((f"link[{link.name}]", *parts))


def home_poses(ctx: CheckContext) -> dict[str, Matrix]:
    """World pose of every link frame at q = 0 (the fact :func:`urdftool.facts.home.home_poses`)."""
    return home.home_poses(ctx)


def on_one_chain(tree: KinematicTree, a: str, b: str) -> bool:
    """``tree.lineal(a, b)``: whether one of the links lies on the other's path to the root.

    Found by walking up from each link, a few joints per pair, where ``lineal()`` first numbers
    every link of the tree: the mirror rules ask it of a few pairs of a large robot.
    """
    return a == b or _above(tree, a, b) or _above(tree, b, a)


def _above(tree: KinematicTree, upper: str, link: str) -> bool:
    joint = tree.parent_joint.get(link)
    while joint is not None:  # the parent joints form a forest: the walk ends at a root
        if joint.parent == upper:
            return True
        joint = tree.parent_joint.get(joint.parent)
    return False


def shape_dims(geometry: Geometry | None) -> tuple[float, ...] | None:
    """A primitive's full extents along its own axes (m), or ``None`` for meshes and planes."""
    if type(geometry) is Mesh:  # the most common shape of all, answered first
        return None
    if isinstance(geometry, Box):
        return tuple(float(v) for v in geometry.size)
    if isinstance(geometry, Sphere):
        return (2 * geometry.radius,) * 3
    if isinstance(geometry, Cylinder):
        return (2 * geometry.radius, 2 * geometry.radius, geometry.length)
    if isinstance(geometry, Capsule):
        return (2 * geometry.radius, 2 * geometry.radius, geometry.length + 2 * geometry.radius)
    if isinstance(geometry, Ellipsoid):
        return tuple(2 * float(r) for r in geometry.radii)
    return None


def robot_extent(ctx: CheckContext) -> float:
    """The diagonal (m) of the box around every link frame at home, widened by primitive shapes.

    Meshes are left out (they need loading) and so are shapes larger than
    ``length_min`` (a ground plane, or the very slip being looked for), so one
    wrong number cannot make the robot look big enough to hide itself.
    """
    key = "intent-extent"
    if key in ctx.cache:
        return float(ctx.cache[key])
    limit = option(ctx, "length_min")
    points: list[Vec3] = []
    for name, (rotation, origin) in home.home_frames(ctx).items():
        points.append(origin)
        link = ctx.robot.link(name)
        elements: list[Collision | Visual] = [*link.collisions, *link.visuals] if link else []
        for element in elements:
            dims = shape_dims(element.geometry)
            if dims is None or max(dims) > limit:
                continue
            x, y, z = vec3.apply(rotation, element.origin.xyz)
            x, y, z = x + origin[0], y + origin[1], z + origin[2]
            half = max(dims) / 2
            points.extend(((x - half, y - half, z - half), (x + half, y + half, z + half)))
    # a point with a coordinate that is not finite (a shape written as inf) does not count
    finite = [point for point in points if all(map(math.isfinite, point))]
    if not finite:
        extent = 0.0
    else:
        xs, ys, zs = zip(*finite, strict=True)
        dx, dy, dz = max(xs) - min(xs), max(ys) - min(ys), max(zs) - min(zs)
        extent = math.sqrt(dx * dx + dy * dy + dz * dz)
    ctx.cache[key] = extent
    return extent


def angle_between(a: Matrix, b: Matrix) -> float:
    """Angle (rad) between two directions, ignoring sign (parallel and anti-parallel are 0)."""
    na, nb = vector_norm(a), vector_norm(b)
    if na == 0 or nb == 0:
        return 0.0
    cos = abs(float(np.dot(a, b))) / (na * nb)
    return math.acos(min(1.0, cos))


def rotation_angle(rotation: Matrix) -> float:
    """The angle (rad) of a rotation matrix."""
    cos = (float(np.trace(rotation)) - 1.0) / 2.0
    return math.acos(max(-1.0, min(1.0, cos)))
