"""Model rules: pure checks of a loaded robot and the facts about it.

Each module here registers its family's model rules into the one catalogue
(:mod:`urdftool.catalogue`), beside the reader and conversion rules defined
there. Importing this package loads none of them: :mod:`urdftool.rules.registry`
knows every rule from the generated table :mod:`urdftool.rules.table` and
imports a rule's module when a run selects it (a ``--select S`` check imports
only the structural rules). :func:`all_rules` and :func:`lookup` load what they
return; :data:`REGISTRY`, read from this package, is the complete table.
"""

from __future__ import annotations

from typing import Any

from urdftool.facts.context import CheckContext
from urdftool.rules.registry import REGISTRY as _REGISTRY
from urdftool.rules.registry import Family, Rule, RuleInfo, all_rules, info, load_all, lookup
from urdftool.rules.selection import Selection, UnknownSelector

__all__ = [
    "REGISTRY",
    "CheckContext",
    "Family",
    "Rule",
    "RuleInfo",
    "Selection",
    "UnknownSelector",
    "all_rules",
    "info",
    "lookup",
]


def __getattr__(name: str) -> Any:
    """``REGISTRY``: the catalogue with every rule module loaded."""
    if name != "REGISTRY":
        raise AttributeError(f"module 'urdftool.rules' has no attribute '{name}'")
    load_all()
    return _REGISTRY
