"""Which child elements each SDFormat version defines, for the elements urdftool checks.

The table lists, for the parents the reader walks (``sdf``, ``world``,
``model``, ``link``, ``joint``, ``axis``, ...), the first and the last
version (1.4 to 1.11) whose specification defines each child. It was read
off the SDFormat element descriptions (``sdf/1.x/*.sdf`` in libsdformat) and
lets the reader tell an element that is newer or older than the file's
declared version from one that SDFormat never had.
"""

from __future__ import annotations

Version = tuple[int, int]

#: (parent, child) -> first and last SDFormat version that defines the child element
ELEMENTS: dict[str, dict[str, tuple[Version, Version]]] = {
    "axis": {
        "dynamics": ((1, 4), (1, 11)), "initial_position": ((1, 6), (1, 8)), "limit": ((1, 4), (1, 11)),
        "mimic": ((1, 11), (1, 11)), "use_parent_model_frame": ((1, 5), (1, 6)), "xyz": ((1, 4), (1, 11)),
    },
    "collision": {
        "auto_inertia_params": ((1, 11), (1, 11)), "density": ((1, 11), (1, 11)), "frame": ((1, 5), (1, 6)),
        "geometry": ((1, 4), (1, 11)), "laser_retro": ((1, 4), (1, 11)), "max_contacts": ((1, 4), (1, 11)),
        "pose": ((1, 4), (1, 11)), "surface": ((1, 4), (1, 11)),
    },
    "frame": {
        "pose": ((1, 5), (1, 11)),
    },
    "geometry": {
        "box": ((1, 4), (1, 11)), "capsule": ((1, 8), (1, 11)), "cone": ((1, 11), (1, 11)),
        "cylinder": ((1, 4), (1, 11)), "ellipsoid": ((1, 8), (1, 11)), "empty": ((1, 4), (1, 11)),
        "heightmap": ((1, 4), (1, 11)), "image": ((1, 4), (1, 11)), "mesh": ((1, 4), (1, 11)),
        "plane": ((1, 4), (1, 11)), "polyline": ((1, 5), (1, 11)), "sphere": ((1, 4), (1, 11)),
    },
    "include": {
        "name": ((1, 5), (1, 11)), "namespace": ((1, 11), (1, 11)), "placement_frame": ((1, 8), (1, 11)),
        "plugin": ((1, 5), (1, 11)), "pose": ((1, 5), (1, 11)), "static": ((1, 5), (1, 11)),
        "uri": ((1, 4), (1, 11)),
    },
    "inertial": {
        "auto_inertia_params": ((1, 11), (1, 11)), "density": ((1, 11), (1, 11)),
        "fluid_added_mass": ((1, 10), (1, 11)), "frame": ((1, 5), (1, 6)), "inertia": ((1, 4), (1, 11)),
        "mass": ((1, 4), (1, 11)), "pose": ((1, 4), (1, 11)),
    },
    "joint": {
        "axis": ((1, 4), (1, 11)), "axis2": ((1, 4), (1, 11)), "child": ((1, 4), (1, 11)),
        "frame": ((1, 5), (1, 6)), "gearbox_ratio": ((1, 4), (1, 11)),
        "gearbox_reference_body": ((1, 4), (1, 11)), "parent": ((1, 4), (1, 11)),
        "physics": ((1, 4), (1, 11)), "pose": ((1, 4), (1, 11)), "screw_thread_pitch": ((1, 10), (1, 11)),
        "sensor": ((1, 4), (1, 11)), "thread_pitch": ((1, 4), (1, 11)),
    },
    "limit": {
        "dissipation": ((1, 4), (1, 11)), "effort": ((1, 4), (1, 11)), "lower": ((1, 4), (1, 11)),
        "stiffness": ((1, 4), (1, 11)), "upper": ((1, 4), (1, 11)), "velocity": ((1, 4), (1, 11)),
    },
    "link": {
        "audio_sink": ((1, 4), (1, 11)), "audio_source": ((1, 4), (1, 11)), "battery": ((1, 5), (1, 11)),
        "collision": ((1, 4), (1, 11)), "enable_wind": ((1, 6), (1, 11)), "frame": ((1, 5), (1, 6)),
        "gravity": ((1, 4), (1, 11)), "inertial": ((1, 4), (1, 11)), "kinematic": ((1, 4), (1, 11)),
        "light": ((1, 6), (1, 11)), "must_be_base_link": ((1, 4), (1, 11)),
        "particle_emitter": ((1, 6), (1, 11)), "pose": ((1, 4), (1, 11)), "projector": ((1, 4), (1, 11)),
        "self_collide": ((1, 4), (1, 11)), "sensor": ((1, 4), (1, 11)), "velocity_decay": ((1, 4), (1, 11)),
        "visual": ((1, 4), (1, 11)),
    },
    "model": {
        "allow_auto_disable": ((1, 4), (1, 11)), "enable_wind": ((1, 6), (1, 11)),
        "frame": ((1, 5), (1, 11)), "gripper": ((1, 4), (1, 11)), "include": ((1, 5), (1, 11)),
        "joint": ((1, 4), (1, 11)), "link": ((1, 4), (1, 11)), "model": ((1, 5), (1, 11)),
        "plugin": ((1, 4), (1, 11)), "pose": ((1, 4), (1, 11)), "self_collide": ((1, 5), (1, 11)),
        "static": ((1, 4), (1, 11)),
    },
    "sdf": {
        "actor": ((1, 4), (1, 11)), "light": ((1, 4), (1, 11)), "model": ((1, 4), (1, 11)),
        "world": ((1, 4), (1, 11)),
    },
    "visual": {
        "cast_shadows": ((1, 4), (1, 11)), "frame": ((1, 5), (1, 6)), "geometry": ((1, 4), (1, 11)),
        "laser_retro": ((1, 4), (1, 11)), "material": ((1, 4), (1, 11)), "meta": ((1, 5), (1, 11)),
        "plugin": ((1, 4), (1, 11)), "pose": ((1, 4), (1, 11)), "transparency": ((1, 4), (1, 11)),
        "visibility_flags": ((1, 7), (1, 11)),
    },
    "world": {
        "actor": ((1, 4), (1, 11)), "atmosphere": ((1, 6), (1, 11)), "audio": ((1, 4), (1, 11)),
        "frame": ((1, 7), (1, 11)), "gravity": ((1, 6), (1, 11)), "gui": ((1, 4), (1, 11)),
        "include": ((1, 4), (1, 11)), "joint": ((1, 10), (1, 11)), "light": ((1, 4), (1, 11)),
        "magnetic_field": ((1, 6), (1, 11)), "model": ((1, 4), (1, 11)), "physics": ((1, 4), (1, 11)),
        "plugin": ((1, 4), (1, 11)), "population": ((1, 5), (1, 11)), "road": ((1, 4), (1, 11)),
        "scene": ((1, 4), (1, 11)), "spherical_coordinates": ((1, 4), (1, 11)), "state": ((1, 4), (1, 11)),
        "wind": ((1, 6), (1, 11)),
    },
}


def versions_of(parent: str, child: str) -> tuple[Version, Version] | None:
    """The first and last version defining ``<child>`` in ``<parent>``, or ``None`` (never, or not tabled)."""
    return ELEMENTS.get(parent, {}).get(child)


def fmt(version: Version) -> str:
    return f"{version[0]}.{version[1]}"


def custom_element(tag: str) -> bool:
    """A custom element of SDFormat 1.6+ (``prefix:name``, or namespaced): not SDFormat's to check."""
    return ":" in tag or tag.startswith("{")
