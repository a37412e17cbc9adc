"""COLLADA (.dae) files as trimesh meshes: the lean reader's scene handed to trimesh, the file's
unit, and the ways a file pycollada refuses is read again as the C and C++ readers read it.

:func:`urdftool.backends.meshes.load_trimesh` reads every mesh; for a ``.dae`` it tries
:func:`lean_collada` first, then trimesh (pycollada), then :func:`collada_before_nul` and
:func:`collada_geometry_only`, and scales the result by :func:`collada_unit` (metres per unit).
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
else:  # NumPy loads when a mesh is first read: a structural check never pays for it
    from urdftool.lazy import numpy as np

from urdftool.backends import collada, mesh_files
from urdftool.safe_files import read_head, read_regular

_DAE_UNIT = re.compile(rb"<unit\b[^>]*?\bmeter\s*=\s*[\"']\s*([0-9.eE+-]+)\s*[\"']")


def collada_unit(path: str) -> float:
    """The ``<asset><unit meter="…">`` of a COLLADA file (1.0 when absent or not COLLADA)."""
    if not path.lower().endswith(".dae"):
        return 1.0
    try:
        head = read_head(path, 1 << 16)  # <asset> comes first in a COLLADA document
    except OSError:
        return 1.0
    match = _DAE_UNIT.search(head)
    try:
        unit = float(match.group(1)) if match else 1.0
    except ValueError:
        return 1.0
    return unit if np.isfinite(unit) and unit > 0 else 1.0


def collada_declares_entities(path: str) -> bool:
    """True for a ``.dae`` whose prolog declares entities (they can read other files or expand
    without bound; the mesh parser would expand them)."""
    if not path.lower().endswith(".dae"):
        return False
    try:
        head = read_head(path, 1 << 16)
    except OSError:
        return False
    return b"<!ENTITY" in head.upper()




def lean_collada(path: str) -> Any:
    """The COLLADA file as trimesh would load it (before units), through the lean reader.

    ``None`` when the reader does not handle the file or finds no triangles:
    the caller then loads it with trimesh. Each primitive becomes a mesh whose
    vertices are merged as trimesh merges them (by position, normal and, when
    textured, texture coordinates), placed by its node's matrix; the meshes are
    concatenated, as trimesh's scene ``to_mesh`` does.
    """
    import trimesh

    try:
        scene = collada.read(path)
    except (collada.Unsupported, OSError, RecursionError, MemoryError):
        return None
    try:
        # trimesh's own scene assembly is private API; a trimesh that moved it
        # simply sends every COLLADA file down the regular (pycollada) path.
        from trimesh.exchange.load import _load_kwargs
    except ImportError:
        return None

    geometry: dict[str, dict[str, Any]] = {}
    graph = []
    for number, part in enumerate(scene.parts):
        visual = None
        if part.textured:
            visual = trimesh.visual.TextureVisuals(
                uv=part.uv, material=trimesh.visual.material.SimpleMaterial()
            )
        name = f"geometry_{number}"
        geometry[name] = {
            "vertices": part.vertices,
            "faces": np.arange(len(part.vertices)).reshape(-1, 3),
            "vertex_normals": part.normals,
            "visual": visual,
        }
        graph.append({"frame_to": name, "matrix": part.matrix, "geometry": name})
    if not geometry:
        return None
    # trimesh's own scene assembly, as for the scene its COLLADA loader returns
    built: Any = _load_kwargs({"class": "Scene", "graph": graph, "geometry": geometry})
    loaded = built.to_mesh()
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        return None
    return loaded


def collada_before_nul(path: str) -> Any:
    """A ``.dae`` file read by trimesh up to its first NUL byte and with ``<`` in attribute values
    escaped, as the C and C++ readers read it (:func:`urdftool.backends.collada.before_nul`,
    :func:`~urdftool.backends.collada.escape_angled_attributes`); ``None`` when that changes
    nothing or fails."""
    import io

    import trimesh

    if not path.lower().endswith(".dae"):
        return None
    try:
        data = read_regular(path, "mesh")
    except OSError:
        return None
    document = collada.escape_angled_attributes(collada.before_nul(data))
    if document == data:
        return None
    try:
        return trimesh.load(
            io.BytesIO(document), file_type="dae", force="mesh", process=True,
            resolver=mesh_files.resolver(path),
        )
    except Exception:  # broken before the NUL too: the caller reports the file
        return None


def collada_geometry_only(path: str) -> Any:
    """The COLLADA file read again without its materials and comments, or ``None``.

    pycollada drops a whole node when one of its materials has a broken
    reference (a missing texture surface), and refuses a comment among a
    mesh's primitives; assimp, which RViz, Gazebo and Pinocchio use, keeps the
    geometry. Removing the materials and comments lets trimesh keep it too.
    """
    import io

    import trimesh
    from lxml import etree

    parser = etree.XMLParser(
        resolve_entities=False, no_network=True, load_dtd=False, huge_tree=True
    )
    try:
        root = etree.parse(path, parser).getroot()
    except (OSError, etree.XMLSyntaxError):
        return None
    namespace = root.nsmap.get(None)
    for tag in ("library_effects", "library_materials", "library_images", "bind_material"):
        for element in list(root.iter(f"{{{namespace}}}{tag}" if namespace else tag)):
            element.getparent().remove(element)
    # pycollada takes an XML comment inside <mesh> for a geometry it does not know ("Unknown
    # geometry tag"); assimp and gz-common read the children by name and skip comments
    etree.strip_tags(root, etree.Comment)
    try:
        return trimesh.load(
            io.BytesIO(etree.tostring(root)), file_type="dae", force="mesh", process=True
        )
    except Exception:  # the geometry itself is broken: the caller reports the file
        return None
