"""The whole catalogue: look rules up by code or name, and load only the rule modules a run needs.

The rules that check a loaded robot live in one module per topic under
:mod:`urdftool.rules`; importing a module registers its rules into the one
table (:data:`~urdftool.catalogue.registry.REGISTRY`). Which module defines
which rule, with each rule's code, name, severity and summary, is in the
generated table :mod:`urdftool.rules.table`, so a run can select rules and
describe findings without importing every rule body: :func:`model_rules` imports
only the modules of the selected rules. :func:`all_rules` and :func:`lookup`
load what they return, so they always see the complete table.
"""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Callable, Iterable, Iterator
from typing import TYPE_CHECKING, NamedTuple

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
from urdftool.diagnostics import Severity
from urdftool.lazy import LazyModule
from urdftool.rules.table import RULES

if TYPE_CHECKING:
    from urdftool.rules import summaries
else:  # the summaries are text for reports; selecting rules never reads them
    summaries = LazyModule("urdftool.rules.summaries")

__all__ = [
    "CODE_PATTERN",
    "DOC_SECTIONS",
    "INDEX",
    "NAME_PATTERN",
    "REDIRECTS",
    "REGISTRY",
    "Family",
    "Rule",
    "RuleInfo",
    "all_rules",
    "doc_sections",
    "info",
    "load_all",
    "lookup",
    "model_rules",
    "register",
]


class RuleInfo(NamedTuple):
    """What the generated table says about a rule, known without importing its module."""

    code: str
    name: str
    severity: Severity
    kind: str
    default_enabled: bool
    #: the module whose import registers the rule
    module: str

    @property
    def summary(self) -> str:
        """The first line of its docstring (the generated :mod:`urdftool.rules.summaries`)."""
        return summaries.SUMMARIES.get(self.code, "")


#: code -> the rule as the generated table describes it, sorted by code
INDEX: dict[str, RuleInfo] = {
    row[0]: RuleInfo(row[0], row[1], Severity(row[2]), row[3], row[4], row[5]) for row in RULES
}
_BY_NAME: dict[str, str] = {entry.name: code for code, entry in INDEX.items()}


def _load(modules: Iterable[str]) -> None:
    for module in sorted(set(modules)):
        importlib.import_module(module)


#: the packages whose modules register rules
RULE_PACKAGES = ("urdftool.catalogue", "urdftool.rules")


def load_all() -> None:
    """Import every module of the rule packages, so :data:`REGISTRY` is complete (even a rule
    the generated table does not list yet)."""
    for package in RULE_PACKAGES:
        path = importlib.import_module(package).__path__
        _load(f"{package}.{module.name}" for module in pkgutil.iter_modules(path))


def info(code_or_name: str) -> RuleInfo | None:
    """The table's entry for this code or name (case-insensitive codes; redirects followed)."""
    key = code_or_name.strip()
    key = REDIRECTS.get(key, key)
    return INDEX.get(key.upper()) or INDEX.get(_BY_NAME.get(key.lower(), ""))


def all_rules() -> list[type[Rule]]:
    """Every registered rule, sorted by code."""
    load_all()
    return sorted(REGISTRY.values(), key=lambda r: (r.family.letter, r.code))


def lookup(code_or_name: str) -> type[Rule] | None:
    """The rule with this code or name (case-insensitive codes; redirects followed)."""
    entry = info(code_or_name)
    if entry is not None:
        _load([entry.module])
        return REGISTRY.get(entry.code)
    return None


def model_rules(enabled: Callable[[RuleInfo], bool] | None = None) -> Iterator[type[Rule]]:
    """The rules that run on a loaded robot, sorted by code; with *enabled*, only those of the
    generated table it accepts, and only their modules are imported."""
    if enabled is None:
        return (r for r in all_rules() if r.kind == "model")
    wanted = [e for e in INDEX.values() if e.kind == "model" and enabled(e)]
    _load(e.module for e in wanted)
    return (REGISTRY[e.code] for e in sorted(wanted, key=lambda e: (e.code[0], e.code)))
