"""Runtime (R): verdicts of the bundled smoke simulation."""

from __future__ import annotations
