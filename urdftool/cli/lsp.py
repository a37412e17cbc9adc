"""``urdftool lsp``: the language server over stdio (needs the ``lsp`` extra: pygls)."""

from __future__ import annotations

from collections.abc import Sequence

import click

from urdftool.cli.common import InputProblem, build_options, model_options, selection_options


@click.command("lsp")
@model_options
@selection_options
@click.option("--no-dynamics", is_flag=True, help="Skip the dynamics pass (Pinocchio) on open and save too.")
@click.option("--stdio", is_flag=True, help="Talk over standard input/output (the default, only transport).")
def lsp_command(xacro_args: Sequence[str], packages: Sequence[str], package_paths: Sequence[str],
                select: Sequence[str], ignore: Sequence[str], no_dynamics: bool, stdio: bool) -> None:
    """Language server for editors: findings as you type, rule docs on hover, quick fixes."""
    options = build_options(xacro_args, packages, package_paths, select, ignore, dynamics=not no_dynamics)
    try:
        from urdftool.lsp.server import serve
    except ImportError as exc:
        raise InputProblem(f"urdftool lsp needs pygls: pip install 'urdftool[lsp]' ({exc})") from exc
    serve(options)
