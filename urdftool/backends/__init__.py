"""Optional engines behind lazy imports: trimesh, Pinocchio, MuJoCo, PyBullet.

Nothing here is imported by ``import urdftool`` or by a plain ``check`` of a
URDF; each module imports its engine inside the functions that need it.
"""
