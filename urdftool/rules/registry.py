"""The whole catalogue, with every rule family registered: look rules up by code or name.

Importing :mod:`urdftool.rules` (which any import of this module does first)
registers the model rules beside the reader and conversion rules of
:mod:`urdftool.catalogue`, so these functions always see the complete table.
"""

from __future__ import annotations

from collections.abc import Iterator

from urdftool.catalogue.registry import (
    CODE_PATTERN,
    DOC_SECTIONS,
    NAME_PATTERN,
    REDIRECTS,
    REGISTRY,
    Family,
    Rule,
    doc_sections,
    register,
)

__all__ = [
    "CODE_PATTERN",
    "DOC_SECTIONS",
    "NAME_PATTERN",
    "REDIRECTS",
    "REGISTRY",
    "Family",
    "Rule",
    "all_rules",
    "doc_sections",
    "lookup",
    "model_rules",
    "register",
]


def all_rules() -> list[type[Rule]]:
    """Every registered rule, sorted by code."""
    return sorted(REGISTRY.values(), key=lambda r: (r.family.letter, r.code))


def lookup(code_or_name: str) -> type[Rule] | None:
    """The rule with this code or name (case-insensitive codes; redirects followed)."""
    key = code_or_name.strip()
    key = REDIRECTS.get(key, key)
    if key.upper() in REGISTRY:
        return REGISTRY[key.upper()]
    for rule in REGISTRY.values():
        if rule.name == key.lower():
            return rule
    return None


def model_rules() -> Iterator[type[Rule]]:
    """The rules that run on a loaded robot."""
    return (r for r in all_rules() if r.kind == "model")
