"""Closed chains (L): loops in SDF models and links with several parents."""

from __future__ import annotations
