"""Rigid-body physics helpers in NumPy: inertia tensors, their validity, shapes' inertia."""
