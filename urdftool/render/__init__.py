"""Rendering reports: text for people; JSON, SARIF, GitHub, JUnit and GitLab for tools."""

from urdftool.render.formats import FORMATS, render_report
from urdftool.render.json import render_json
from urdftool.render.text import render_text

__all__ = ["FORMATS", "render_json", "render_report", "render_text"]
