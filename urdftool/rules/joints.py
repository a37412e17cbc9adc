"""Joints (J): axes, limits, mimic chains and the home configuration."""

from __future__ import annotations
