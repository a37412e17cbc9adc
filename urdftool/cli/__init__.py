"""The ``urdftool`` command line: one module per command, registered here."""

from __future__ import annotations

import click

from urdftool import __version__
from urdftool.cli.check import check_command
from urdftool.cli.convert import convert_command
from urdftool.cli.graph import graph_command
from urdftool.cli.info import info_command
from urdftool.cli.rule import rule_command
from urdftool.cli.sim import sim_command


@click.group(context_settings={"help_option_names": ["-h", "--help"], "max_content_width": 100})
@click.version_option(__version__, prog_name="urdftool")
def main() -> None:
    """Check, convert and draw robot descriptions (URDF, xacro, SDF).

    Exit codes: 0 nothing at error severity; 1 findings at failing severity (or a
    stale output with convert --check); 2 usage error or unreadable input.
    """


main.add_command(check_command)
main.add_command(convert_command)
main.add_command(graph_command)
main.add_command(info_command)
main.add_command(rule_command)
main.add_command(sim_command)

__all__ = ["main"]
