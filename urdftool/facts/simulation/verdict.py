"""Reading the smoke simulation's verdicts back from a report: ``sim`` and ``check --sim`` exit 1
when an engine's verdict is "failed"."""

from __future__ import annotations

from urdftool.diagnostics import Diagnostic, Report

#: the rule that carries each engine's verdict (sim-summary); its ``data["verdict"]`` is
#: ``"passed"``, ``"failed"`` or ``"not simulated"``
VERDICT_CODE = "R005"


def is_failed_verdict(diagnostic: Diagnostic) -> bool:
    """True for a sim-summary finding whose verdict is "failed"."""
    return diagnostic.code == VERDICT_CODE and diagnostic.data.get("verdict") == "failed"


def verdict_failed(report: Report) -> bool:
    return any(is_failed_verdict(d) for d in report.diagnostics)
