"""``urdftool diff`` output: text for a terminal, JSON for tools, Markdown for a pull-request comment."""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from typing import Any

from urdftool.pipeline.diff import Change, RobotDiff

_TITLES = {
    "link-renamed": "renamed", "joint-renamed": "renamed", "link-added": "added", "joint-added": "added",
    "link-removed": "removed", "joint-removed": "removed", "joint": "joint", "pose": "moved",
    "mass": "mass", "com": "centre of mass", "inertia": "inertia", "mesh": "mesh",
    "total-mass": "total mass", "total-com": "total centre of mass", "extension": "extension",
    "finding-new": "new finding", "finding-gone": "finding gone",
}


def _number(value: Any) -> str:
    if isinstance(value, float):
        # rounding noise of a pose composition (-2.3e-17 m) is a zero to the reader
        return f"{0.0 if abs(value) < 1e-12 else value:.6g}"
    if isinstance(value, list):
        return "(" + " ".join(_number(v) for v in value) + ")"
    if isinstance(value, dict):
        return " ".join(f"{k}={_number(v)}" for k, v in value.items())
    return "—" if value is None else str(value)


def describe(change: Change) -> str:
    """One line saying what changed and by how much."""
    kind = change.kind
    if kind.endswith("-renamed"):
        return f"{kind.split('-')[0]} '{change.old}' renamed to '{change.new}'"
    if kind.endswith(("-added", "-removed")):
        what, how = kind.split("-")
        return f"{what} '{change.subject}' {how}"
    if kind == "pose":
        if change.field == "orientation":
            return f"link '{change.subject}' turned {change.size:.6g}° at the zero configuration"
        return (f"link '{change.subject}' moved {change.size:.6g} mm at the zero configuration "
                f"{_number(change.old)} → {_number(change.new)} m")
    if kind in ("finding-new", "finding-gone"):
        text = change.new if kind == "finding-new" else change.old
        return f"{_TITLES[kind]}: {change.severity} {change.subject} {text}"
    size = ""
    if change.size is not None and math.isfinite(change.size):  # a change from zero has no percentage
        size = f" ({change.size:+.6g} {change.unit})" if change.unit != "%" else f" ({change.size:.6g}%)"
        if change.unit in ("mm", "kg·m²"):
            size = f" ({change.size:.6g} {change.unit})"
    # total-mass and total-com name their field already ("total mass", not "total mass mass")
    named = change.field and change.field != kind and not kind.startswith("total-")
    field = f" {change.field}" if named else ""
    owner = "joint" if kind == "joint" else "link" if kind in ("mass", "com", "inertia", "mesh") else ""
    subject = f"{owner} '{change.subject}'" if owner else f"'{change.subject}'"
    values = f"{_number(change.old)} → {_number(change.new)}"
    return f"{_TITLES.get(kind, kind)}{field} of {subject}: {values}{size}"


def render_text(diff: RobotDiff, tripped: Sequence[str] = ()) -> str:
    if diff.empty:
        lines = [f"{diff.old} → {diff.new}: no change to the robot"]
    else:
        lines = [f"{diff.old} → {diff.new}: {len(diff.changes)} change(s)"]
        lines += [f"  {describe(c)}" for c in diff.changes]
    if tripped:
        lines.append("fail-on tripped: " + ", ".join(tripped))
    return "\n".join(lines) + "\n"


def render_json(diff: RobotDiff, tripped: Sequence[str] = ()) -> str:
    return json.dumps({**diff.to_json(), "tripped": list(tripped)}, indent=2, sort_keys=False) + "\n"


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def render_markdown(diff: RobotDiff, tripped: Sequence[str] = ()) -> str:
    head = f"### Robot diff: `{diff.old}` → `{diff.new}`\n\n"
    if diff.empty:
        return head + "No change to the robot.\n"
    rows = ["| what | subject | change | size |", "|---|---|---|---|"]
    for c in diff.changes:
        size = "" if c.size is None else f"{c.size:.6g} {c.unit}"
        title = _TITLES.get(c.kind, c.kind)
        rows.append(f"| {title} | `{_cell(c.subject)}` | {_cell(describe(c))} | {size} |")
    tail = f"\n\n**fail-on tripped:** {', '.join(tripped)}\n" if tripped else "\n"
    return head + "\n".join(rows) + tail


RENDERERS = {"text": render_text, "json": render_json, "markdown": render_markdown}
