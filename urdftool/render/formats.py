"""Every output format of ``urdftool check``, by name."""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import cast

from urdftool.diagnostics import Report
from urdftool.render.text import render_text

#: the values of ``--format``, in the order the help lists them
FORMATS = ("text", "json", "sarif", "github", "junit", "gitlab")


#: format -> its module; imported when a report is rendered in it (JSON needs hashing, JUnit
#: the host name, ...), so that a check printing text loads none of them
_MODULES = {"json": "json", "sarif": "sarif", "github": "github", "junit": "junit", "gitlab": "gitlab"}


def _renderer(fmt: str) -> Callable[[Report], str]:
    if fmt not in _MODULES:
        raise ValueError(f"unknown format '{fmt}'; expected one of {', '.join(FORMATS)}")
    module = importlib.import_module(f"urdftool.render.{_MODULES[fmt]}")
    return cast("Callable[[Report], str]", getattr(module, f"render_{fmt}"))


def render_report(report: Report, fmt: str, colour: bool = False, quiet: bool = False) -> str:
    """*report* in format *fmt*; *colour* and *quiet* apply to ``text`` only."""
    if fmt == "text":
        return render_text(report, colour=colour, quiet=quiet)
    return _renderer(fmt)(report)
