"""What URDF allows where: attributes and children per element, and the extensions loaders expect.

The tables the URDF reader (:mod:`urdftool.parse.urdf`) judges elements by,
following urdfdom's reading of the format.
"""

from __future__ import annotations

import functools

from urdftool.model import JointType
from urdftool.source import SRC_ATTRIBUTE

#: Attributes each URDF element may carry.
ATTRIBUTES: dict[str, frozenset[str]] = {
    "robot": frozenset({"name", "version"}),
    "link": frozenset({"name"}),
    "inertial": frozenset(),
    "origin": frozenset({"xyz", "rpy"}),
    "mass": frozenset({"value"}),
    "inertia": frozenset({"ixx", "ixy", "ixz", "iyy", "iyz", "izz"}),
    "visual": frozenset({"name"}),
    "collision": frozenset({"name"}),
    "geometry": frozenset(),
    "box": frozenset({"size"}),
    "cylinder": frozenset({"radius", "length"}),
    "sphere": frozenset({"radius"}),
    "capsule": frozenset({"radius", "length"}),
    "mesh": frozenset({"filename", "scale"}),
    "material": frozenset({"name"}),
    "color": frozenset({"rgba"}),
    "texture": frozenset({"filename"}),
    "joint": frozenset({"name", "type"}),
    "parent": frozenset({"link"}),
    "child": frozenset({"link"}),
    "axis": frozenset({"xyz"}),
    "calibration": frozenset({"rising", "falling", "reference_position"}),
    "dynamics": frozenset({"damping", "friction"}),
    "limit": frozenset({"lower", "upper", "effort", "velocity"}),
    "mimic": frozenset({"joint", "multiplier", "offset"}),
    "safety_controller": frozenset({"soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity"}),
}

#: Children each element may have; ``None`` marks a repeatable child.
CHILDREN: dict[str, dict[str, bool]] = {
    "link": {"inertial": False, "visual": True, "collision": True},
    "inertial": {"origin": False, "mass": False, "inertia": False},
    "visual": {"origin": False, "geometry": False, "material": False},
    "collision": {"origin": False, "geometry": False},
    "joint": {
        "origin": False,
        "parent": False,
        "child": False,
        "axis": False,
        "calibration": False,
        "dynamics": False,
        "limit": False,
        "mimic": False,
        "safety_controller": False,
    },
    "material": {"color": False, "texture": False},
}

#: Children whose repetition changes only how the robot looks (urdfdom, yourdfpy, Pinocchio and
#: Gazebo use the first): a warning, not an error that blocks every export.
COSMETIC_REPEATS = frozenset({"material"})

#: Top-level elements that are not URDF proper but are expected there (MuJoCo's URDF import
#: reads ``<mujoco><compiler …/></mujoco>``).
KNOWN_EXTENSIONS = frozenset(
    {"gazebo", "transmission", "ros2_control", "sensor", "klampt", "plugin", "mujoco"}
)

#: Attributes real vendors add to URDF elements, (element, attribute) -> who reads them.
#: Reported once per kind as ``vendor-extension`` (info), not as ``unknown-attribute``
#: per element (docs/extensions.md).
VENDOR_ATTRIBUTES: dict[tuple[str, str], str] = {
    ("dynamics", "D"): "Franka's joint friction model (franka_description), read by franka_gazebo",
    ("dynamics", "K"): "Franka's joint friction model (franka_description), read by franka_gazebo",
    ("dynamics", "mu_coulomb"): "Franka's joint friction model (franka_description), read by franka_gazebo",
    ("dynamics", "mu_viscous"): "Franka's joint friction model (franka_description), read by franka_gazebo",
    ("joint", "dont_collapse"): "Gazebo's URDF conversion (sdformat): keeps a fixed joint from being lumped",
    ("link", "type"): "a vendor annotation (PR2's descriptions); no URDF reader uses it",
}

#: Child elements real vendors add, (parent, child) -> who reads them (``vendor-extension``).
VENDOR_ELEMENTS: dict[tuple[str, str], str] = {
    ("collision", "material"): "ROS-Industrial support packages colour collisions; URDF readers ignore it",
    ("link", "self_filter"): "robot_self_filter's per-link padding (ANYmal); URDF readers ignore it",
    ("link", "self_collision_checking"): "PR2's self-collision shapes; URDF readers ignore it",
    ("robot", "frame"): "Drake's URDF parser adds it to the plant as a frame fixed to its link "
    "(Spot's foot centres); other URDF readers ignore it",
}

#: Elements that SDF or Gazebo define and that URDF loaders silently ignore.
#: They are kept on the link or joint and judged by ``sdf-element-in-urdf``.
SDF_ISMS = frozenset(
    {"pose", "sensor", "self_collide", "gravity", "kinematic", "velocity_decay", "must_be_base_link"}
)

#: Simulator extensions inside a link or collision that loaders honour (PyBullet's contact block).
LINK_EXTENSIONS = frozenset({"contact"})

URDF_TYPES = {t.value for t in (JointType.REVOLUTE, JointType.CONTINUOUS, JointType.PRISMATIC,
                                 JointType.FIXED, JointType.FLOATING, JointType.PLANAR)}
SPHERICAL_NAMES = {"spherical", "ball"}


def is_extension_name(tag: str) -> bool:
    """Namespaced elements (``drake:joint``, ``{ns}tag``) belong to their own tools."""
    return tag.startswith("{") or ":" in tag


@functools.lru_cache(maxsize=1024)
def attribute_verdict(
    tag: str, names: tuple[str, ...]
) -> tuple[tuple[str, ...], tuple[tuple[str, tuple[str, ...]], ...]]:
    """The attributes of a ``<tag>`` with these attribute *names* that it does not have, and
    the vendor attributes by reader (memoised: a file repeats a few attribute sets)."""
    allowed = ATTRIBUTES[tag]
    unknown: list[str] = []
    vendor: dict[str, list[str]] = {}
    for name in names:
        if name == SRC_ATTRIBUTE or name.startswith("{") or ":" in name or name.startswith("xmlns"):
            continue
        if (tag, name) in VENDOR_ATTRIBUTES:
            vendor.setdefault(VENDOR_ATTRIBUTES[tag, name], []).append(name)
        elif name not in allowed:
            unknown.append(name)
    return tuple(unknown), tuple((reader, tuple(found)) for reader, found in vendor.items())
