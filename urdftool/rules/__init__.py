"""Model rules: pure checks of a loaded robot and the facts about it.

Importing this package registers every family's model rules into the one
catalogue (:mod:`urdftool.catalogue`), beside the reader and conversion rules
defined there, so :func:`all_rules` and :func:`lookup` see the whole table.
"""

from urdftool.catalogue import collision, conversion, sdf, xacro  # noqa: F401  (register the definitions)
from urdftool.catalogue import ros2_control as _reader_ros2_control  # noqa: F401
from urdftool.catalogue import syntax as _reader_syntax  # noqa: F401
from urdftool.facts.context import CheckContext
from urdftool.rules import (  # noqa: F401  (importing registers the rules)
    controllers,
    dynamics,
    gazebo,
    gazebo_frames,
    gz_systems,
    inertia,
    inertia_fit,
    intent_camera,
    intent_consistency,
    intent_ros,
    intent_symmetry,
    intent_units,
    joints,
    loops,
    mesh_contents,
    meshes,
    ros2_control,
    ros2_control_sensors,
    runtime,
    self_collision,
    srdf,
    srdf_parts,
    syntax,
    target_meshes,
    targets,
    transmissions,
)
from urdftool.rules.registry import REGISTRY, Family, Rule, all_rules, lookup
from urdftool.rules.selection import Selection, UnknownSelector

__all__ = [
    "REGISTRY",
    "CheckContext",
    "Family",
    "Rule",
    "Selection",
    "UnknownSelector",
    "all_rules",
    "lookup",
]
