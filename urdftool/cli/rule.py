"""``urdftool rule CODE-or-NAME``: a rule's documentation."""

from __future__ import annotations

import click

from urdftool.cli.common import EXIT_USAGE
from urdftool.rules import all_rules, lookup
from urdftool.rules.docs import rule_markdown
from urdftool.rules.selection import suggestion


@click.command("rule")
@click.argument("code_or_name", required=False)
@click.option("--all", "show_all", is_flag=True, help="List every rule: code, name, severity, summary.")
def rule_command(code_or_name: str | None, show_all: bool) -> None:
    """Print a rule's documentation (or the whole catalogue with --all)."""
    if show_all or code_or_name is None:
        for rule in all_rules():
            click.echo(f"{rule.code:6} {rule.name:34} {rule.severity.value:8} {rule.summary()}")
        return
    found = lookup(code_or_name)
    if found is None:
        hint = suggestion(code_or_name)
        click.echo(f"urdftool: no rule with code or name '{code_or_name}'{hint}", err=True)
        raise SystemExit(EXIT_USAGE)
    click.echo(rule_markdown(found))
