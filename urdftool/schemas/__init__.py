"""Schemas that ship with urdftool: the JSON report's (``report.schema.json``)."""

from __future__ import annotations

from importlib import resources

REPORT_SCHEMA = "report.schema.json"


def report_schema_text() -> str:
    """The JSON Schema of ``check --format json`` (CONTRACTS.md), as shipped in the package."""
    return resources.files(__name__).joinpath(REPORT_SCHEMA).read_text(encoding="utf-8")
