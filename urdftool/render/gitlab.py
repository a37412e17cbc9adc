"""GitLab Code Quality (``check --format gitlab``): the JSON array a job publishes as
``artifacts: reports: codequality`` so findings show on merge requests.

Each issue has ``description``, ``check_name``, ``fingerprint`` (stable across line moves),
``severity`` (``major`` for errors, ``minor`` for warnings, ``info``) and
``location.path``/``location.lines.begin``.
"""

from __future__ import annotations

import json
from typing import Any

from urdftool.diagnostics import Diagnostic, Report, Severity
from urdftool.render.rule_meta import fingerprints, relative_path

SEVERITIES = {Severity.ERROR: "major", Severity.WARNING: "minor", Severity.INFO: "info"}


def code_quality_issue(d: Diagnostic, file_path: str, fingerprint: str) -> dict[str, Any]:
    span = d.location
    return {
        "type": "issue",
        "engine_name": "urdftool",
        "check_name": f"{d.code} {d.name}",
        "description": d.message,
        "categories": ["Bug Risk"],
        "fingerprint": fingerprint,
        "severity": SEVERITIES[d.severity],
        "location": {
            "path": relative_path(span.path if span else file_path),
            "lines": {"begin": (span.line if span and span.line else 1)},
        },
    }


def gitlab_document(report: Report) -> list[dict[str, Any]]:
    issues: list[dict[str, Any]] = []
    for f in report.files:
        marks = fingerprints(f.diagnostics, f.path, f.robot)
        issues.extend(code_quality_issue(d, f.path, m) for d, m in zip(f.diagnostics, marks, strict=True))
    return issues


def render_gitlab(report: Report) -> str:
    return json.dumps(gitlab_document(report), indent=2) + "\n"
