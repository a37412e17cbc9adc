"""``--select`` / ``--ignore``: which rules are on.

Each selector is a full code (``S005``), a code prefix (``S``, ``S0``) or a rule
name (``invalid-number``). The decision for a rule is taken by the most specific
selector that matches it: a name or full code beats a longer prefix, which beats
a shorter one. At equal specificity ``ignore`` wins. With no ``select``, every
rule is selected at the lowest specificity.

A rule whose ``default_enabled`` is false (an optional convention) is on only
when a selector names it exactly, by code or name; prefixes leave it off.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Iterable
from typing import Protocol

from urdftool.catalogue.suggest import did_you_mean
from urdftool.records import record
from urdftool.rules.registry import INDEX, REDIRECTS


class Named(Protocol):
    """A rule class or its table entry (:class:`~urdftool.rules.registry.RuleInfo`): all a
    selection reads."""

    @property
    def code(self) -> str: ...

    @property
    def name(self) -> str: ...

    @property
    def default_enabled(self) -> bool: ...

#: specificity of an exact code or a rule name
EXACT = 100
_PREFIX = re.compile(r"^[A-Z]{1,2}[0-9]{0,2}$")


class UnknownSelector(ValueError):
    """A selector that names no rule, code or prefix."""


def _specificity(selector: str, rule: Named) -> int | None:
    """How specifically *selector* names *rule*, or ``None`` when it does not."""
    sel = REDIRECTS.get(selector, selector)
    if sel.lower() == rule.name or sel.upper() == rule.code:
        return EXACT
    if _PREFIX.match(sel.upper()) and rule.code.startswith(sel.upper()):
        return len(sel)
    return None


@record
class Selection:
    select: tuple[str, ...] | None = None
    ignore: tuple[str, ...] = ()

    @classmethod
    def of(cls, select: Iterable[str] | None = None, ignore: Iterable[str] | None = None) -> Selection:
        """Build a selection, splitting comma-separated lists and validating every selector."""
        sel = _split(select) if select is not None else None
        ign = _split(ignore) if ignore is not None else ()
        for s in (*(sel or ()), *ign):
            if not _names_a_rule(s):
                raise UnknownSelector(f"'{s}' matches no rule code, prefix or name{suggestion(s)}")
        return cls(sel if sel else None, ign)

    def enabled(self, rule: Named) -> bool:
        best_select = 0 if self.select is None else None
        for s in self.select or ():
            spec = _specificity(s, rule)
            if spec is not None and (best_select is None or spec > best_select):
                best_select = spec
        if best_select is None:
            return False
        if not rule.default_enabled and best_select < EXACT:
            return False
        best_ignore = max(
            (spec for s in self.ignore if (spec := _specificity(s, rule)) is not None),
            default=None,
        )
        return best_ignore is None or best_select > best_ignore

    def enabled_code(self, code: str) -> bool:
        """Whether the rule with this code is on (memoised: called once per finding)."""
        return _enabled_code(self, code)


_CODE_LIKE = re.compile(r"^([A-Za-z]{1,2})0*([0-9]{1,3})$")


def suggestion(word: str) -> str:
    """``"; did you mean 'I004'?"`` for a misspelt code or rule name, or the empty string.

    A code with a digit left out (``I04``) is padded (``I004``) before string
    similarity is tried: similarity alone finds ``I014`` as close as ``I004``.
    """
    code = _CODE_LIKE.match(word)
    if code:
        padded = f"{code.group(1).upper()}{int(code.group(2)):03d}"
        if padded in INDEX:
            return f"; did you mean '{padded}'?"
    return did_you_mean(word.lower(), [r.name for r in INDEX.values()])


@functools.lru_cache(maxsize=1024)
def _names_a_rule(selector: str) -> bool:
    """Whether *selector* matches any rule (memoised: every file of a run builds its selection)."""
    return any(_specificity(selector, r) is not None for r in INDEX.values())


@functools.lru_cache(maxsize=4096)
def _enabled_code(selection: Selection, code: str) -> bool:
    rule = INDEX.get(code)
    return rule is not None and selection.enabled(rule)


def _split(values: Iterable[str]) -> tuple[str, ...]:
    out: list[str] = []
    for value in values:
        out.extend(part.strip() for part in value.split(",") if part.strip())
    return tuple(out)
