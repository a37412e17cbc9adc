"""Conversion (C): what an export cannot carry, reported per element."""

from __future__ import annotations
