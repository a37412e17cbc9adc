"""Rendering reports: text for people; JSON, SARIF, GitHub, JUnit and GitLab for tools.

Each format's module is imported when a report is rendered in it (see :mod:`.formats`).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from urdftool.render.formats import FORMATS, render_report
from urdftool.render.text import render_text

if TYPE_CHECKING:
    from urdftool.render.json import render_json

__all__ = ["FORMATS", "render_json", "render_report", "render_text"]


def __getattr__(name: str) -> Any:
    if name != "render_json":
        raise AttributeError(f"module 'urdftool.render' has no attribute '{name}'")
    return importlib.import_module("urdftool.render.json").render_json
