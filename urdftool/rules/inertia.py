"""Inertia (I): masses and tensors a simulator can use, and that match the geometry."""

from __future__ import annotations
