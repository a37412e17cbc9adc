"""SARIF 2.1.0 (``check --format sarif``): for GitHub code scanning and other SARIF viewers.

One run; ``tool.driver.rules`` holds each rule that fired (id = code, name, summary,
documentation page, default level); each result points at the file the user edits, with a
path relative to the working folder (``%SRCROOT%``) where the file lies below it.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any
from urllib.parse import quote

from urdftool.diagnostics import Diagnostic, Report, Severity
from urdftool.render.json import finite
from urdftool.render.rule_meta import (
    PROJECT_URL,
    RuleMeta,
    end_of,
    fingerprints,
    related_spans,
    relative_path,
    rule_meta,
)
from urdftool.source import Span
from urdftool.version import __version__

SARIF_SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"
SARIF_VERSION = "2.1.0"
SRCROOT = "%SRCROOT%"
LEVELS = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}


def artifact_location(path: str) -> dict[str, Any]:
    rel = relative_path(path)
    if rel.startswith("/") or (len(rel) > 1 and rel[1] == ":"):
        return {"uri": Path(os.path.abspath(path)).as_uri()}
    return {"uri": quote(rel), "uriBaseId": SRCROOT}


def physical_location(span: Span) -> dict[str, Any]:
    location: dict[str, Any] = {"artifactLocation": artifact_location(span.path)}
    if span.line is not None and span.line >= 1:
        region: dict[str, Any] = {"startLine": span.line}
        if span.column is not None and span.column >= 1:
            region["startColumn"] = span.column
        end_line, end_column = end_of(span)
        if end_line is not None and end_line >= span.line:
            region["endLine"] = end_line
        if end_column is not None and end_column >= 1:
            region["endColumn"] = end_column
        location["region"] = region
    return location


def rule_descriptor(meta: RuleMeta) -> dict[str, Any]:
    return {
        "id": meta.code,
        "name": meta.name,
        "shortDescription": {"text": meta.summary},
        "helpUri": meta.help_uri,
        "help": {"text": f"{meta.summary} See {meta.help_uri} or run `urdftool rule {meta.code}`."},
        "defaultConfiguration": {"level": LEVELS[meta.severity]},
    }


def _result(d: Diagnostic, file_path: str, index: int, fingerprint: str) -> dict[str, Any]:
    span = d.location or Span(file_path)
    location: dict[str, Any] = {"physicalLocation": physical_location(span)}
    if d.element:
        location["logicalLocations"] = [{"fullyQualifiedName": d.element, "kind": "element"}]
    result: dict[str, Any] = {
        "ruleId": d.code,
        "ruleIndex": index,
        "level": LEVELS[d.severity],
        "message": {"text": d.message + (f"\nhelp: {d.help}" if d.help else "")},
        "locations": [location],
        "partialFingerprints": {"urdftool/v1": fingerprint},
    }
    related = [
        {"id": n, "physicalLocation": physical_location(other), "message": {"text": label or "related"}}
        for n, (other, label) in enumerate(related_spans(d))
    ]
    if related:
        result["relatedLocations"] = related
    fixes = _fixes(d)
    if fixes:
        result["fixes"] = fixes
    properties: dict[str, Any] = {"name": d.name}
    if d.fix is not None:
        properties["fixApplicability"] = d.fix.applicability.value
    if d.data:
        properties["data"] = dict(d.data)
    result["properties"] = properties
    return result


def _fixes(d: Diagnostic) -> list[dict[str, Any]]:
    """The finding's fix as SARIF ``fixes`` (byte regions, one artifact change per file), so
    code-scanning tools can offer it; display-only fixes and edits without offsets are left out."""
    fix = d.fix
    if fix is None or fix.applicability.value == "display-only" or not fix.edits:
        return []
    changes: dict[str, list[dict[str, Any]]] = {}
    for edit in fix.edits:
        span = edit.span
        if span.offset is None or span.end_offset is None:
            return []
        changes.setdefault(span.path, []).append({
            "deletedRegion": {"byteOffset": span.offset, "byteLength": span.end_offset - span.offset},
            "insertedContent": {"text": edit.content},
        })
    return [{
        "description": {"text": f"{fix.message} ({fix.applicability.value})"},
        "artifactChanges": [
            {"artifactLocation": artifact_location(path), "replacements": replacements}
            for path, replacements in changes.items()
        ],
    }]


def sarif_document(report: Report) -> dict[str, Any]:
    rules: dict[str, int] = {}
    descriptors: list[dict[str, Any]] = []
    for d in sorted({d.code: d for d in report.diagnostics}.values(), key=lambda d: d.code):
        rules[d.code] = len(descriptors)
        descriptors.append(rule_descriptor(rule_meta(d)))
    results = []
    for file_report in report.files:
        marks = fingerprints(file_report.diagnostics, file_report.path, file_report.robot)
        for d, mark in zip(file_report.diagnostics, marks, strict=True):
            results.append(_result(d, file_report.path, rules[d.code], mark))
    run: dict[str, Any] = {
        "tool": {
            "driver": {
                "name": "urdftool",
                "version": __version__,
                "semanticVersion": __version__,
                "informationUri": PROJECT_URL,
                "rules": descriptors,
            }
        },
        "originalUriBaseIds": {SRCROOT: {"uri": Path(os.getcwd()).as_uri().rstrip("/") + "/"}},
        "columnKind": "unicodeCodePoints",
        "results": results,
    }
    return {"$schema": SARIF_SCHEMA, "version": SARIF_VERSION, "runs": [run]}


def render_sarif(report: Report) -> str:
    return json.dumps(finite(sarif_document(report)), indent=2, default=str, allow_nan=False) + "\n"
