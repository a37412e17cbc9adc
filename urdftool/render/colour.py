"""Whether text output is coloured: ``--color auto|always|never``, ``NO_COLOR`` and
``FORCE_COLOR``.

``always`` and ``never`` win. With ``auto`` a non-empty ``NO_COLOR`` turns colour off
(https://no-color.org), then a ``FORCE_COLOR`` other than ``0``/``false`` turns it on (for CI
logs that render ANSI colours), and otherwise colour follows whether the output is a terminal.
"""

from __future__ import annotations

import os
from collections.abc import Mapping

CHOICES = ("auto", "always", "never")


def want_colour(choice: str, is_terminal: bool, environ: Mapping[str, str] | None = None) -> bool:
    env = os.environ if environ is None else environ
    if choice == "always":
        return True
    if choice == "never":
        return False
    if env.get("NO_COLOR", ""):
        return False
    force = env.get("FORCE_COLOR")
    if force is not None and force.strip().lower() not in ("0", "false", "no", "off"):
        return True
    return is_terminal
