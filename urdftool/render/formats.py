"""Every output format of ``urdftool check``, by name."""

from __future__ import annotations

from collections.abc import Callable

from urdftool.diagnostics import Report
from urdftool.render.github import render_github
from urdftool.render.gitlab import render_gitlab
from urdftool.render.json import render_json
from urdftool.render.junit import render_junit
from urdftool.render.sarif import render_sarif
from urdftool.render.text import render_text

#: the values of ``--format``, in the order the help lists them
FORMATS = ("text", "json", "sarif", "github", "junit", "gitlab")


def _renderer(fmt: str) -> Callable[[Report], str]:
    if fmt == "json":
        return render_json
    if fmt == "sarif":
        return render_sarif
    if fmt == "github":
        return render_github
    if fmt == "junit":
        return render_junit
    if fmt == "gitlab":
        return render_gitlab
    raise ValueError(f"unknown format '{fmt}'; expected one of {', '.join(FORMATS)}")


def render_report(report: Report, fmt: str, colour: bool = False, quiet: bool = False) -> str:
    """*report* in format *fmt*; *colour* and *quiet* apply to ``text`` only."""
    if fmt == "text":
        return render_text(report, colour=colour, quiet=quiet)
    return _renderer(fmt)(report)
