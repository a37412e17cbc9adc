"""``urdftool schema``: print the JSON Schema of the JSON report."""

from __future__ import annotations

import click

from urdftool.schemas import report_schema_text


@click.command("schema")
def schema_command() -> None:
    """Print the JSON Schema that `urdftool check --format json` output follows."""
    click.echo(report_schema_text(), nl=False)
