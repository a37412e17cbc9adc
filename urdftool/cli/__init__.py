"""The ``urdftool`` command line: one module per command, registered here.

Commands are imported when they are run, not when ``urdftool`` starts: a CI
gate that runs ``urdftool check`` should not pay for loading the exporters,
Graphviz and simulation front ends.
"""

from __future__ import annotations

import importlib

import click

from urdftool.budgets import set_budgets
from urdftool.cli.suggest import unknown_command
from urdftool.safe_files import DEFAULT_LIMITS, set_limits
from urdftool.version import __version__

#: command name -> "module:attribute" of its click command
COMMANDS: dict[str, str] = {
    "check": "urdftool.cli.check:check_command",
    "collisions": "urdftool.cli.collisions:collisions_command",
    "convert": "urdftool.cli.convert:convert_command",
    "diff": "urdftool.cli.diff:diff_command",
    "graph": "urdftool.cli.graph:graph_command",
    "info": "urdftool.cli.info:info_command",
    "lsp": "urdftool.cli.lsp:lsp_command",
    "rule": "urdftool.cli.rule:rule_command",
    "schema": "urdftool.cli.schema:schema_command",
    "sim": "urdftool.cli.sim:sim_command",
}


class LazyGroup(click.Group):
    """A click group whose subcommands are imported on first use."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted(COMMANDS)

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        target = COMMANDS.get(cmd_name)
        if target is None:
            return None
        module_name, attribute = target.split(":")
        command = getattr(importlib.import_module(module_name), attribute)
        assert isinstance(command, click.Command)
        return command

    def resolve_command(
        self, ctx: click.Context, args: list[str]
    ) -> tuple[str | None, click.Command | None, list[str]]:
        """As click's, but an unknown command suggests the nearest ones (urdftool/cli/suggest.py)."""
        name = args[0]
        if self.get_command(ctx, name) is None and not name.startswith("-"):
            raise unknown_command(ctx, name, self.list_commands(ctx))
        return super().resolve_command(ctx, args)


@click.group(
    cls=LazyGroup,
    context_settings={"help_option_names": ["-h", "--help"], "max_content_width": 100},
)
@click.version_option(__version__, prog_name="urdftool")
@click.pass_context
def main(ctx: click.Context) -> None:
    """Check, convert and draw robot descriptions (URDF, xacro, SDF).

    Exit codes: 0 nothing at error severity; 1 findings at failing severity (or a
    stale output with convert --check); 2 usage error or unreadable input.
    """
    # --max-file-size sets the read caps for this invocation only: a program (or a test) that
    # runs several commands in one process must not inherit the last one's caps.
    _defaults()
    ctx.call_on_close(_defaults)


def _defaults() -> None:
    set_limits(DEFAULT_LIMITS)
    set_budgets({})


__all__ = ["COMMANDS", "main"]
