"""The rule catalogue is complete and consistent (codes, names, docs, contract)."""

from __future__ import annotations

from pathlib import Path

import pytest

from urdftool.rules import Selection, UnknownSelector, all_rules, lookup
from urdftool.rules.docs import SUMMARIES_PATH, TABLE_PATH, pages, summaries_source, table_source
from urdftool.rules.registry import CODE_PATTERN, DOC_SECTIONS, NAME_PATTERN

ROOT = Path(__file__).resolve().parent.parent
CONTRACTS = ROOT / "fixtures" / "contracts" / "CONTRACTS.md"


def test_codes_and_names_are_unique_and_well_formed() -> None:
    rules = all_rules()
    codes = [r.code for r in rules]
    names = [r.name for r in rules]
    assert len(set(codes)) == len(codes)
    assert len(set(names)) == len(names)
    for rule in rules:
        assert CODE_PATTERN.match(rule.code), rule.code
        assert NAME_PATTERN.match(rule.name), rule.name
        assert rule.code.startswith(rule.family.letter)


@pytest.mark.parametrize("rule", all_rules(), ids=lambda r: r.code)
def test_rule_documents_itself(rule) -> None:
    sections = rule.sections()
    for title in DOC_SECTIONS:
        assert sections.get(title), f"{rule.code} {rule.name}: docstring lacks '## {title}'"
    assert rule.summary(), f"{rule.code} has no summary line"


def _required_names() -> set[str]:
    """Rule names the contract requires, for the families implemented so far."""
    text = CONTRACTS.read_text()
    names: set[str] = set()
    for line in text.splitlines():
        if line.startswith("| syntax and structure |") or line.startswith("| xacro |"):
            names |= {part.strip().strip("`") for part in line.split("|")[2].split(",")}
    return names


def test_contract_names_exist() -> None:
    have = {r.name for r in all_rules()}
    missing = _required_names() - have
    assert not missing, f"required by CONTRACTS.md but not registered: {sorted(missing)}"


def test_lookup_by_code_and_name() -> None:
    assert lookup("S005") is lookup("invalid-number") is lookup("s005")
    assert lookup("no-such-rule") is None


@pytest.mark.parametrize(
    ("select", "ignore", "code", "enabled"),
    [
        (None, (), "S005", True),
        (("S",), (), "S005", True),
        (("X",), (), "S005", False),
        (("S",), ("S005",), "S005", False),
        (("S005",), ("S",), "S005", True),  # exact beats prefix
        (("S0",), ("S00",), "S005", False),  # longer prefix wins
        (("S00",), ("S0",), "S005", True),
        (None, ("invalid-number",), "S005", False),
        (("invalid-number",), ("S",), "S005", True),
        (("S005",), ("invalid-number",), "S005", False),  # equal: ignore wins
    ],
)
def test_selection_decision_table(select, ignore, code, enabled) -> None:
    selection = Selection.of(select, ignore)
    assert selection.enabled(lookup(code)) is enabled


def test_unknown_selector_is_refused() -> None:
    with pytest.raises(UnknownSelector):
        Selection.of(["Q999"], None)


def test_generated_rule_docs_are_current() -> None:
    folder = ROOT / "docs" / "rules"
    wanted = pages()
    on_disk = {p.name: p.read_text() for p in folder.glob("*.md")}
    assert on_disk == wanted, "docs/rules/ drifted: run `python -m urdftool.rules.docs`"


def test_generated_rule_table_is_current() -> None:
    """The table a run selects rules from (without importing them) matches the rule modules."""
    assert SUMMARIES_PATH.read_text() == summaries_source(), (
        "urdftool/rules/summaries.py drifted: run `python -m urdftool.rules.docs`"
    )
    assert TABLE_PATH.read_text() == table_source(), (
        "urdftool/rules/table.py drifted: run `python -m urdftool.rules.docs`"
    )

