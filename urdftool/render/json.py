"""The JSON report of CONTRACTS.md (``schemas/report.schema.json``)."""

from __future__ import annotations

import json
import math
import os
from typing import Any

from urdftool.diagnostics import Report
from urdftool.render.rule_meta import relative_path
from urdftool.version import __version__

SCHEMA_VERSION = 1


def report_document(report: Report) -> dict[str, Any]:
    files = [f.to_json() for f in report.files]
    for file in files:
        for diagnostic in file["diagnostics"]:
            _relative_locations(diagnostic, file["path"])
        # the SRDF and controllers files are named as the findings in them are
        if "srdf" in file:
            file["srdf"] = relative_path(file["srdf"])
        if "controllers" in file:
            file["controllers"] = [relative_path(path) for path in file["controllers"]]
    return {
        "schema_version": SCHEMA_VERSION,
        "tool": {"name": "urdftool", "version": __version__},
        "files": files,
        "summary": report.summary(),
    }


def _relative_locations(diagnostic: dict[str, Any], checked: str) -> None:
    """Every location of a finding (its own, its related ones, its fix's edits) in the checked
    file names it as the file entry does (as given); one in another file (an included
    ``.xacro``, a mesh, an SRDF) as the text and SARIF reports do: relative to the working
    folder when below it, so it reads the same on every machine (a file outside stays absolute)."""
    checked_absolute = os.path.abspath(checked)
    places = [diagnostic.get("location")]
    places += [r.get("location") for r in diagnostic.get("related", ())]
    places += [e.get("location") for e in (diagnostic.get("fix") or {}).get("edits", ())]
    for place in places:
        if place and place.get("path"):
            same = os.path.abspath(place["path"]) == checked_absolute
            place["path"] = checked if same else relative_path(place["path"])


def finite(value: Any) -> Any:
    """*value* with every non-finite float (a density of a geometry with no volume, say) as
    ``None``: JSON has no infinity or NaN, and ``json.dumps`` would write ``Infinity``, which a
    strict reader (jq, a CI dashboard) refuses."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite(v) for v in value]
    return value


def render_json(report: Report) -> str:
    return json.dumps(finite(report_document(report)), indent=2, sort_keys=False, default=str,
                      allow_nan=False) + "\n"
