"""Snapshots of what users read: each rule family's text and JSON output on its fixtures.

A change in a message, a help line, a location or the numbers in ``data`` is a
visible diff in ``tests/__snapshots__/``: review it, then accept it with
``python3 scripts/test tests/test_snapshots.py --snapshot-update``.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest

from tests.conftest import FIXTURES, ROOT
from tests.test_rule_fixtures import EXPORT_ONLY, SIM_ONLY, fixture_xacro_args
from urdftool.diagnostics import Report
from urdftool.pipeline.check import CheckOptions, check_file
from urdftool.render import render_json, render_text

RULES = FIXTURES / "rules"
FAMILIES = sorted({p.name[0] for p in RULES.iterdir() if p.is_dir()} - {"C", "R"})


def _fixtures(family: str) -> list[Path]:
    return sorted(
        p
        for p in RULES.glob(f"{family}*/*.*")
        if p.suffix in (".urdf", ".xacro", ".sdf", ".world")
        and p.parent.name not in EXPORT_ONLY | SIM_ONLY
        and p.name.startswith(("bad", "good"))
    )


def _report(family: str) -> Report:
    files = []
    for path in _fixtures(family):
        relative = str(path.relative_to(ROOT))
        options = CheckOptions(select=(path.parent.name,), package_paths=(str(path.parent),),
                               xacro_args=fixture_xacro_args(path))
        files.extend(check_file(relative, options))
    return Report(tuple(files))


#: Where a resolver searched depends on where the clone and its virtual environment live:
#: the lists are replaced by a placeholder (the resolver's own tests check them).
_SEARCHED = re.compile(r"(searched|tried): [^)'\"\n]*")
_SEARCH_KEYS = ("searched", "tried")


def _portable(text: str) -> str:
    return _SEARCHED.sub(r"\1: <locations>", text.replace(str(ROOT) + "/", ""))


def _without_searches(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: "<locations>" if k in _SEARCH_KEYS else _without_searches(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_without_searches(v) for v in value]
    return value


@pytest.mark.parametrize("family", FAMILIES)
def test_text_output_of_each_family(family: str, snapshot, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    assert _portable(render_text(_report(family), colour=False)) == snapshot


@pytest.mark.parametrize("family", FAMILIES)
def test_json_output_of_each_family(family: str, snapshot, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    document = _without_searches(json.loads(_portable(render_json(_report(family)))))
    document["tool"]["version"] = "<version>"
    for file in document["files"]:
        for diagnostic in file["diagnostics"]:
            diagnostic["data"].pop("wall_time", None)
    assert document == snapshot
