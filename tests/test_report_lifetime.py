"""A report outlives its check without holding the model's document.

A finding's span is looked up in the document's position table when first read
(``urdftool.source.deferred_span``). Once the check is over, a report keeps plain spans, so
that a run over many files does not keep every document with a finding, and a check leaves
no reference cycles for the collector (``check_file`` pauses it while the model is built).
"""

from __future__ import annotations

import dataclasses
import gc
from typing import Any

import pytest
from lxml import etree

from tests.conftest import FIXTURES, erd_urdfs
from urdftool.diagnostics import Applicability, Diagnostic, Edit, Fix, Related, Severity
from urdftool.pipeline.check import CheckOptions, check_file
from urdftool.source import Span, deferred_span, is_deferred

#: rule fixtures whose findings are located by the reader: on an element (S008), on an
#: attribute (S009), on a repeated element (S007); and a real robot with findings (PR2)
CASES = [str(FIXTURES / "rules" / code / "bad.urdf") for code in ("S007", "S008", "S009")]
OPTIONS = [CheckOptions(select=("S", "X")), CheckOptions(rule_options={"dynamics": False})]


def _cases() -> list[str]:
    return CASES + [p for p in erd_urdfs() if p.endswith(("pr2.urdf", "anymal.urdf"))]


def _spans(report_diagnostics) -> list[Span]:  # type: ignore[no-untyped-def]
    out = []
    for d in report_diagnostics:
        out.append(d.location)
        out.extend(r.span for r in d.related)
        if d.fix is not None:
            out.extend(e.span for e in d.fix.edits)
    return [s for s in out if s is not None]


@pytest.mark.parametrize("options", OPTIONS, ids=["structural", "default"])
@pytest.mark.parametrize("path", _cases(), ids=lambda p: p.rsplit("/", 2)[-2] + "/" + p.rsplit("/", 1)[-1])
def test_reports_hold_plain_spans_and_no_document(path: str, options: CheckOptions) -> None:
    reports = check_file(path, options)
    spans = _spans(d for r in reports for d in r.diagnostics)
    assert spans, "each case has located findings"
    assert not any(is_deferred(s) for s in spans)
    gc.collect()
    # Nothing reachable from the reports is an element of the parsed document.
    seen, stack = set(), list(reports)
    while stack:
        obj = stack.pop()
        if id(obj) in seen:
            continue
        seen.add(id(obj))
        assert not isinstance(obj, etree._Element), f"a report of {path} holds an element"
        if isinstance(obj, (type, str, bytes, int, float)):
            continue
        stack.extend(gc.get_referents(obj))


@pytest.mark.parametrize("path", _cases(), ids=lambda p: p.rsplit("/", 2)[-2] + "/" + p.rsplit("/", 1)[-1])
def test_a_check_leaves_no_reference_cycles(path: str) -> None:
    """Reader findings live in the reader's list; their spans once held the reader's own method,
    which made a cycle that kept the whole document until the collector ran."""
    options = CheckOptions(rule_options={"dynamics": False})
    check_file(path, options)  # first-use caches and imports
    gc.collect()
    gc.set_debug(gc.DEBUG_SAVEALL)
    try:
        check_file(path, options)
        gc.collect()
        garbage = [type(o).__name__ for o in gc.garbage]
    finally:
        gc.set_debug(0)
        gc.garbage.clear()
    assert garbage == []


def test_no_robot_of_the_corpora_is_left_to_the_collector() -> None:
    """Every robot of example-robot-data and the SDF fixtures, checked with every default rule,
    is freed by reference counting. Facts that keep a closure over the check's context (the link
    solids' memo reads the mesh survey through it) made a cycle that held the whole robot until
    the collector walked it: 50 ms a pass over example-robot-data, a tenth of the default check.
    (A xacro file leaves xacro's own minidom cycles, which are not urdftool's.)"""
    options = CheckOptions(rule_options={"dynamics": False})
    paths = erd_urdfs() + sorted(str(p) for p in (FIXTURES / "robots" / "sdf").glob("*.sdf"))
    assert len(paths) > 60
    for path in paths:
        check_file(path, options)  # first-use caches and imports
    gc.collect()
    left = {}
    gc.disable()
    try:
        for path in paths:
            check_file(path, options)
            found = gc.collect()
            if found:
                left[path] = found
    finally:
        gc.enable()
    assert left == {}


def test_settled_span_keeps_every_field() -> None:
    reports = check_file(CASES[2], CheckOptions(select=("S",)))
    located = [d for r in reports for d in r.diagnostics if d.code == "S009"]
    assert located and all(d.location.line and d.location.column for d in located)
    assert all(type(d.location) is Span for d in located)


def test_detached_keeps_every_field_of_a_finding() -> None:
    """``Diagnostic.detached`` builds the finding field by field (not by ``dataclasses.replace``):
    every field, including one added to the record later, must come through, with its spans
    settled."""
    deferred = deferred_span("robot.urdf", lambda key: Span("robot.urdf", 3, 5), "link")
    values: dict[str, Any] = {
        "code": "X999", "name": "some-rule", "severity": Severity.WARNING, "message": "a message",
        "location": deferred, "element": "link[a]", "help": "a help", "data": {"mass": 1.5},
        "related": (Related(deferred, "the other"),),
        "fix": Fix("a fix", (Edit(deferred, "text"),), Applicability.UNSAFE),
    }
    assert [f.name for f in dataclasses.fields(Diagnostic)] == list(values), \
        "a field was added to Diagnostic: give it a value here and keep it in Diagnostic.detached"
    kept = Diagnostic(**values).detached()
    plain = Span("robot.urdf", 3, 5)
    assert type(kept.location) is Span and kept.location == plain
    assert kept.related == (Related(plain, "the other"),) and type(kept.related[0].span) is Span
    assert kept.fix == Fix("a fix", (Edit(plain, "text"),), Applicability.UNSAFE)
    assert type(kept.fix.edits[0].span) is Span
    for name in ("code", "name", "severity", "message", "element", "help", "data"):
        assert getattr(kept, name) is values[name]
    already = Diagnostic("X999", "some-rule", Severity.ERROR, "m", plain)
    assert already.detached() is already
