"""The rule catalogue. Importing this package registers every rule family."""

from urdftool.rules import (  # noqa: F401  (importing registers the rules)
    conversion,
    dynamics,
    gazebo,
    inertia,
    joints,
    loops,
    meshes,
    runtime,
    sdf,
    syntax,
    xacro,
)
from urdftool.rules.registry import REGISTRY, CheckContext, Family, Rule, all_rules, lookup
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
