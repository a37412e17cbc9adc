"""Rendering reports: text for people, JSON for tools."""

from urdftool.render.json import render_json
from urdftool.render.text import render_text

__all__ = ["render_json", "render_text"]
