"""A COLLADA or OBJ file's triangles split by the colour of their material, for visual exports.

The lean reader (:mod:`urdftool.backends.collada`) takes geometry only, which is
all a check needs. An export that shows the robot as RViz shows it needs the
colours too: a ``.dae`` visual often holds several materials (the Panda's
``link0.dae``: off-white shell, dark joint caps, white details). This reads the
file with trimesh's COLLADA loader (pycollada), which keeps each primitive's
material, and returns one triangle soup per distinct diffuse colour, placed by
the scene graph and scaled by ``<unit meter>`` as :func:`~urdftool.backends.meshes.load_trimesh`
places and scales the whole mesh. An OBJ file's colours are in the ``.mtl`` library it names
(``mtllib``, ``usemtl``), which trimesh reads too; OBJ has no unit (metres, as URDF reads it).

Colours are trimesh's: the material's diffuse colour (``baseColorFactor``),
8 bits per channel. A textured material has no colour here (the texture is not
carried), nor has a primitive without a material: both come back with colour
``None``, and the exporter gives them the URDF's colour.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
else:  # NumPy loads on first use
    from urdftool.lazy import numpy as np

from urdftool.backends import mesh_files
from urdftool.backends.collada_trimesh import collada_declares_entities, collada_unit
from urdftool.backends.meshes import _quiet_trimesh_log, quiet_numerics
from urdftool.records import record
from urdftool.safe_files import check_regular

#: A part MuJoCo can compile as a mesh of its own needs 4 distinct vertices and some area (m²):
#: MuJoCo refuses fewer vertices, and a shell's inertia needs a surface. Smaller colour patches
#: (a badge of one triangle) take the colour of the largest part instead.
MIN_VERTICES = 4
MIN_AREA = 1e-8

#: Colour as 8-bit red, green, blue, alpha.
RGBA8 = tuple[int, int, int, int]


@record(eq=False)  # compared by identity: its fields are arrays
class ColouredPart:
    """The triangles of one colour: ``vertices`` (n × 3, metres, the file's frame) and ``faces``."""

    rgba: RGBA8 | None
    vertices: np.ndarray
    faces: np.ndarray


def material_rgba(visual: Any) -> RGBA8 | None:
    """The 8-bit diffuse colour of a trimesh visual's material; ``None`` without a material, for a
    textured one, or for a colour-per-vertex visual (none of these is one colour).

    A fully transparent colour (alpha 0) is read as opaque: COLLADA exporters disagree on which
    way ``<transparency>`` counts, and an invisible visual is never what the author meant."""
    material = getattr(visual, "material", None)
    if material is None or getattr(visual, "kind", None) not in ("texture", None):
        return None
    if any(getattr(material, texture, None) is not None for texture in ("baseColorTexture", "image")):
        return None
    colour = getattr(material, "baseColorFactor", None)
    if colour is None:
        colour = getattr(material, "diffuse", None)
    if colour is None:
        return None
    r, g, b, a = (int(c) for c in np.asarray(colour, dtype=np.int64).reshape(-1)[:4])
    return (r, g, b, a or 255)


#: The mesh formats whose files carry material colours (STL carries none).
COLOURED_SUFFIXES = (".dae", ".obj")


def coloured_parts(path: str) -> list[ColouredPart]:
    """The COLLADA or OBJ file at *path* as one part per diffuse colour (sorted: no colour first,
    then by colour; patches too small for a MuJoCo mesh joined to the largest part); ``[]`` when it
    has no coloured material or trimesh cannot read it (the caller then uses the mesh as one
    piece, without a colour of its own)."""
    import trimesh

    _quiet_trimesh_log()
    try:
        check_regular(path, "mesh")
    except OSError:
        return []
    collada = path.lower().endswith(".dae")
    if not path.lower().endswith(COLOURED_SUFFIXES) or (collada and collada_declares_entities(path)):
        return []
    try:
        with quiet_numerics():
            scene: Any = mesh_files.load(path, force="scene", process=True)
    except Exception:  # trimesh raises many kinds; the geometry-only path reports the file
        return []
    groups: dict[RGBA8 | None, list[Any]] = {}
    for node in scene.graph.nodes_geometry:
        matrix, name = scene.graph[node]
        geometry = scene.geometry.get(name)
        if not isinstance(geometry, trimesh.Trimesh) or len(geometry.faces) == 0:
            continue
        placed = geometry.copy()
        placed.apply_transform(matrix)
        groups.setdefault(material_rgba(geometry.visual), []).append(placed)
    if not any(key is not None for key in groups):
        return []
    unit = collada_unit(path) if collada else 1.0
    parts = []
    for rgba, meshes in groups.items():
        vertices = np.concatenate([m.vertices for m in meshes]) * unit
        offsets = np.cumsum([0] + [len(m.vertices) for m in meshes[:-1]])
        faces = np.concatenate([m.faces + o for m, o in zip(meshes, offsets, strict=True)])
        parts.append(ColouredPart(rgba, vertices, faces))
    parts = _merge_small(parts)
    if all(part.rgba is None for part in parts):
        return []
    return sorted(parts, key=lambda p: (p.rgba is not None, p.rgba or (0, 0, 0, 0)))


def _viable(part: ColouredPart) -> bool:
    """MuJoCo compiles this part as a mesh of its own (:data:`MIN_VERTICES`, :data:`MIN_AREA`)."""
    if len(np.unique(part.vertices[np.unique(part.faces)], axis=0)) < MIN_VERTICES:
        return False
    corners = part.vertices[part.faces]
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    return float(np.linalg.norm(cross, axis=1).sum()) / 2 >= MIN_AREA


def _merge_small(parts: list[ColouredPart]) -> list[ColouredPart]:
    """Parts that are not :func:`_viable` joined to the largest part (by triangles), which keeps
    its colour; with none viable, everything is one part of the largest one's colour."""
    largest = max(parts, key=lambda p: len(p.faces))
    small = [p for p in parts if p is not largest and not _viable(p)]
    if not small:
        return parts
    joined = [largest, *small]
    offsets = np.cumsum([0] + [len(p.vertices) for p in joined[:-1]])
    merged = ColouredPart(
        largest.rgba,
        np.concatenate([p.vertices for p in joined]),
        np.concatenate([p.faces + o for p, o in zip(joined, offsets, strict=True)]),
    )
    dropped = {id(p) for p in small}
    return [merged if p is largest else p for p in parts if id(p) not in dropped]
