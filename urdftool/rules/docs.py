"""Rule documentation pages, generated from the docstrings.

``python -m urdftool.rules.docs [DIR]`` writes ``docs/rules/`` (one page per
rule and an index); the test suite fails when the committed pages drift.
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


def write(directory: Path) -> None:
    directory.mkdir(parents=True, exist_ok=True)
    wanted = pages()
    for stale in directory.glob("*.md"):
        if stale.name not in wanted:
            stale.unlink()
    for name, text in wanted.items():
        (directory / name).write_text(text, encoding="utf-8")


if __name__ == "__main__":
    write(Path(sys.argv[1] if len(sys.argv) > 1 else "docs/rules"))
