"""Did-you-mean for misspelt commands: ``urdftool chek`` suggests ``check``.

(Misspelt options get click's own suggestion: ``--fromat`` → ``--format``.)
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

import click

from urdftool.lazy import LazyModule

if TYPE_CHECKING:
    import difflib
else:  # imported when a command is misspelt, not at every start
    difflib = LazyModule("difflib")


def nearest(word: str, candidates: Iterable[str]) -> list[str]:
    names = sorted(set(candidates))
    close = difflib.get_close_matches(word, names, n=3, cutoff=0.7)
    if close or not word:
        return close
    return [name for name in names if name.startswith(word)][:3]


def unknown_command(ctx: click.Context, word: str, candidates: Iterable[str]) -> click.UsageError:
    matches = nearest(word, candidates)
    hint = ""
    if matches:
        hint = " Did you mean " + " or ".join(f"'{m}'" for m in matches) + "?"
    return click.UsageError(f"No such command '{word}'.{hint}", ctx)
