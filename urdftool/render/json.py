"""The JSON report of CONTRACTS.md (``schemas/report.schema.json``)."""

from __future__ import annotations

import json
from typing import Any

from urdftool.diagnostics import Report
from urdftool.version import __version__

SCHEMA_VERSION = 1


def report_document(report: Report) -> dict[str, Any]:
    return {
        "schema_version": SCHEMA_VERSION,
        "tool": {"name": "urdftool", "version": __version__},
        "files": [f.to_json() for f in report.files],
        "summary": report.summary(),
    }


def render_json(report: Report) -> str:
    return json.dumps(report_document(report), indent=2, sort_keys=False, default=str) + "\n"
