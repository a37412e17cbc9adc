"""The collision shape of each collision mesh (hull, concavity, winding), once per file per check.

Reads through :mod:`urdftool.backends.mesh_shape`, which caches by content on
disk; only files the mesh survey found readable are measured.
"""

from __future__ import annotations

from urdftool.backends.mesh_shape import ShapeFacts, shape_facts
from urdftool.facts import meshes as survey
from urdftool.facts.context import CheckContext
from urdftool.facts.meshes import MeshError, MeshUse

__all__ = ["ShapeFacts", "collision_shapes"]


def collision_shapes(ctx: CheckContext) -> dict[str, tuple[ShapeFacts, list[MeshUse]]]:
    """Existing, readable collision mesh files -> their shape facts and the elements using them."""
    if "mesh-shapes" not in ctx.cache:
        found: dict[str, tuple[ShapeFacts, list[MeshUse]]] = {}
        contents = survey.contents(ctx)
        for path, uses in survey.by_file(ctx, role="collision").items():
            if isinstance(contents.get(path, MeshError("unread")), MeshError):
                continue
            try:
                found[path] = (shape_facts(path), uses)
            except MeshError:
                continue
        ctx.cache["mesh-shapes"] = found
    shapes: dict[str, tuple[ShapeFacts, list[MeshUse]]] = ctx.cache["mesh-shapes"]
    return shapes
