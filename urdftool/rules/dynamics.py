"""Dynamics (D): rigid-body checks with Pinocchio (mass matrix, gravity torques)."""

from __future__ import annotations
