"""Meshes and geometry (M): files that resolve, load, and have plausible sizes."""

from __future__ import annotations
