"""Rule documentation pages and the rule table, generated from the registered rules.

``python -m urdftool.rules.docs [DIR]`` writes ``docs/rules/`` (one page per
rule and an index) and ``urdftool/rules/table.py`` (each rule's code, name,
severity, kind and module, read by :mod:`urdftool.rules.registry` so that a run
imports only the rule modules it selects); the test suite fails when either drifts.
"""

from __future__ import annotations

import sys
from pathlib import Path

from urdftool.rules.registry import Rule, all_rules

#: What each severity promises (docs/severity.md), stated on every rule's page.
SEVERITY_MEANING = {
    "error": "a consumer will reject the file or silently misbehave on it",
    "warning": "probably not what the author meant, though every consumer loads it",
    "info": "a note or a style point; it never fails a check",
}


def rule_markdown(rule: type[Rule]) -> str:
    sections = rule.sections()
    lines = [
        f"# {rule.code} {rule.name}",
        "",
        rule.summary(),
        "",
        f"- family: {rule.family.title} ({rule.family.letter})",
        f"- default severity: {rule.severity.value}: {SEVERITY_MEANING[rule.severity.value]} "
        "(docs/severity.md; the *Why it matters* section says what happens to this file's consumers)",
        f"- since: {rule.since}",
        "",
    ]
    for title, body in sections.items():
        lines += [f"## {title}", "", body, ""]
    return "\n".join(lines).rstrip() + "\n"


def index_markdown() -> str:
    lines = [
        "# Rules",
        "",
        "Generated from the rule registry by `python -m urdftool.rules.docs`; do not edit.",
        "",
        "| code | name | family | severity | summary |",
        "|---|---|---|---|---|",
    ]
    for rule in all_rules():
        summary = rule.summary().replace("|", "\\|")
        lines.append(
            f"| [{rule.code}]({rule.code}.md) | `{rule.name}` | {rule.family.title} | "
            f"{rule.severity.value} | {summary} |"
        )
    return "\n".join(lines) + "\n"


def pages() -> dict[str, str]:
    """File name -> content for the whole docs/rules/ folder."""
    out = {"README.md": index_markdown()}
    for rule in all_rules():
        out[f"{rule.code}.md"] = rule_markdown(rule)
    return out


TABLE_PATH = Path(__file__).with_name("table.py")
SUMMARIES_PATH = Path(__file__).with_name("summaries.py")

_GENERATED = "Generated from the registered rules by ``python -m urdftool.rules.docs``; do not edit."


def table_source() -> str:
    """The text of :mod:`urdftool.rules.table`, from every registered rule: what a run needs to
    select rules and import only their modules."""
    lines = [
        '"""Every rule\'s code, name, severity, kind, default and module: the selection index.',
        "",
        _GENERATED,
        "tests/test_registry.py fails when it drifts from the rule modules.",
        '"""',
        "",
        "RULES: tuple[tuple[str, str, str, str, bool, str], ...] = (",
    ]
    for rule in all_rules():
        row = (rule.code, rule.name, rule.severity.value, rule.kind, rule.default_enabled, rule.__module__)
        lines.append(f"    {row!r},")
    lines.append(")")
    return "\n".join(lines) + "\n"


def summaries_source() -> str:
    """The text of :mod:`urdftool.rules.summaries`: each rule's one-line summary, read only when a
    report or ``urdftool rule`` describes a rule."""
    lines = [
        '"""Every rule\'s summary, the first line of its docstring, by code.',
        "",
        _GENERATED,
        "tests/test_registry.py fails when it drifts from the rule modules.",
        '"""',
        "",
        "SUMMARIES: dict[str, str] = {",
    ]
    lines += [f"    {rule.code!r}: {rule.summary()!r}," for rule in all_rules()]
    lines.append("}")
    return "\n".join(lines) + "\n"


def write(directory: Path) -> None:
    directory.mkdir(parents=True, exist_ok=True)
    wanted = pages()
    for stale in directory.glob("*.md"):
        if stale.name not in wanted:
            stale.unlink()
    for name, text in wanted.items():
        (directory / name).write_text(text, encoding="utf-8")
    TABLE_PATH.write_text(table_source(), encoding="utf-8")
    SUMMARIES_PATH.write_text(summaries_source(), encoding="utf-8")


if __name__ == "__main__":
    write(Path(sys.argv[1] if len(sys.argv) > 1 else "docs/rules"))
