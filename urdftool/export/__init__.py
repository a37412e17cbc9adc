"""Exporters: the model written for other tools (MJCF, URDF, SDF, DOT)."""
