"""Which xacro arguments the files of an expansion know, and the given ones that look misspelt.

xacro ignores an argument no file uses, so ``-a gazbo:=true`` leaves ``gazebo``
at its default without a word. The files read during the expansion are
scanned for ``<xacro:arg name="…" default="…"/>`` and ``$(arg NAME)``; a given
argument none of them knows, with a close name among them, becomes a
``misspelt-xacro-argument`` finding at the close one. Given arguments with no
close name are not reported: one setting given to every file of a tree is not
a typo.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping

from urdftool.catalogue.suggest import closest
from urdftool.catalogue.xacro import MisspeltXacroArgument
from urdftool.diagnostics import Diagnostic
from urdftool.records import record
from urdftool.source import Span

#: ``<xacro:arg …>`` (any prefix bound to xacro), its attributes in group 1
_DECLARATION = re.compile(r"<[\w.-]+:arg\b([^>]*)>")
_ATTRIBUTE = re.compile(r"""\b(name|default)\s*=\s*(["'])(.*?)\2""", re.DOTALL)
#: ``$(arg NAME)`` and ``xacro.arg('NAME')`` / ``arg("NAME")`` in expressions
#: how alike a given and a known name must be (difflib's ratio) to call the given one a typo:
#: ``gazbo``/``gazebo`` 0.91, ``ur_typ``/``ur_type`` 0.92; on the real-world corpus, 0.6 also
#: matched ``name`` to ``username``, and 0.8 ``prefix`` to ``no_prefix`` (docs/realworld.md)
TYPO_CUTOFF = 0.85
_USE = re.compile(r"""\$\(\s*arg\s+([^\s)]+)\s*\)|\barg\(\s*["']([^"']+)["']\s*\)""")


@record
class KnownArgument:
    """An argument a file declares or uses: where first seen, and its declared default."""

    span: Span
    default: str | None


def known_arguments(path: str, text: str) -> dict[str, KnownArgument]:
    """The arguments *text* (the file at *path*) declares or uses, first occurrence each."""
    found: dict[str, KnownArgument] = {}
    for match in _DECLARATION.finditer(text):
        attributes = {m.group(1): m.group(3) for m in _ATTRIBUTE.finditer(match.group(1))}
        name = attributes.get("name")
        if name and name not in found:
            found[name] = KnownArgument(_span(path, text, match.start()), attributes.get("default"))
    for match in _USE.finditer(text):
        name = match.group(1) or match.group(2)
        if name not in found:
            found[name] = KnownArgument(_span(path, text, match.start()), None)
    return found


def _span(path: str, text: str, offset: int) -> Span:
    line = text.count("\n", 0, offset) + 1
    return Span(path, line, offset - (text.rfind("\n", 0, offset) + 1) + 1)


def misspelt_arguments(given: Mapping[str, str], known: Mapping[str, KnownArgument]) -> list[Diagnostic]:
    """A ``misspelt-xacro-argument`` finding for each given argument no file knows, when a known
    argument has a close name."""
    found = []
    for name in given:
        if name in known:
            continue
        meant = closest(name, known, TYPO_CUTOFF)
        if meant is None:
            continue
        default = known[meant].default
        keeps = f", so '{meant}' keeps its default '{default}'" if default is not None else ""
        found.append(MisspeltXacroArgument.diagnostic(
            f"xacro argument '{name}' is used by no file read; did you mean '{meant}'? "
            f"(xacro ignores it{keeps})",
            known[meant].span,
            help=f"pass -a {meant}:={given[name]}",
            data={"given": name, "meant": meant, "default": default},
        ))
    return found


def merge(found: Iterable[Mapping[str, KnownArgument]]) -> dict[str, KnownArgument]:
    """The arguments of several files, the first file's occurrence winning."""
    merged: dict[str, KnownArgument] = {}
    for one in found:
        for name, argument in one.items():
            merged.setdefault(name, argument)
    return merged
