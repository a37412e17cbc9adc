"""A lean COLLADA (.dae) geometry reader: triangles and scene transforms, nothing else.

pycollada builds a full object model of a COLLADA document (materials,
effects, images, every input of every primitive) before trimesh turns its
triangles into meshes; for a check that needs only the geometry that is most
of the time spent on meshes. This reader takes from the document exactly what
trimesh's COLLADA loader keeps:

* each ``<geometry>``'s ``<mesh>``: ``<triangles>``, ``<polylist>`` and
  ``<polygons>`` (polygons triangulated as fans), with the positions of the
  ``VERTEX`` input (the ``POSITION`` of its ``<vertices>``), the normals and,
  when a material is bound to the primitive, the first texture coordinates
  (trimesh keeps vertices with different normals or texture coordinates
  apart, so they decide which triangles share edges);
* the scene instanced by ``<scene><instance_visual_scene>``: nested
  ``<node>``s with ``<matrix>``, ``<translate>``, ``<rotate>`` and ``<scale>``
  and their ``<instance_geometry>``;
* ``<asset><unit meter>``.

Anything else that could change the result (``<instance_node>``, other
transforms, ``<polygons>`` with holes, triangle strips and fans, broken
references, counts that disagree with the data) raises :class:`Unsupported`:
the caller then reads the file with trimesh as before. Lines are skipped, as
trimesh skips them.

The file is untrusted: it is parsed without entities, DTDs or network access.
"""

from __future__ import annotations

import math
import re
import warnings
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
else:  # NumPy loads on first use: importing the rules must not pay for it
    from urdftool.lazy import numpy as np
from lxml import etree

from urdftool.records import record
from urdftool.safe_files import read_regular

COLLADA_NAMESPACES = (
    "http://www.collada.org/2005/11/COLLADASchema",
    "http://www.collada.org/2008/03/COLLADASchema",
)

#: Primitives that hold no triangles (trimesh skips them too).
_SKIPPED = frozenset({"lines", "linestrips"})
_TRIANGLES = frozenset({"triangles", "polylist", "polygons"})


class Unsupported(Exception):
    """The document uses something this reader does not handle: read it another way."""


@record
class Part:
    """One primitive instanced once in the scene, as trimesh's COLLADA loader builds it.

    ``vertices`` holds three rows per triangle (unshared, like trimesh's), in
    the geometry's own frame; ``matrix`` places it in the document frame.
    """

    vertices: np.ndarray
    normals: np.ndarray | None
    uv: np.ndarray | None
    textured: bool
    matrix: np.ndarray


@record
class ColladaScene:
    parts: list[Part]
    #: ``<asset><unit meter>`` (1.0 when absent)
    unit: float


def _parser() -> etree.XMLParser:
    return etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        huge_tree=True,  # float arrays of large meshes exceed libxml2's default text cap
        remove_comments=True,
        remove_pis=True,
    )


def read(path: str) -> ColladaScene:
    """The triangles of the COLLADA file at *path*. Raises :class:`Unsupported` or ``OSError``."""
    return read_bytes(read_regular(path, "mesh"))


def before_nul(data: bytes) -> bytes:
    """The document as the C and C++ COLLADA readers see it: up to its first NUL byte.

    Assimp (RViz; coal for Pinocchio) and PyBullet's reader take the file as a
    C string. A file overwritten in place by a shorter export can keep NUL
    padding and the old file's tail after ``</COLLADA>`` (KUKA's LBR iiwa base);
    those readers never see the tail, an XML parser reading every byte does.
    UTF-16 text, where NUL bytes are part of the characters, is left alone.
    """
    if b"\0" in data[:2] or data[:2] in (b"\xff\xfe", b"\xfe\xff"):
        return data
    return data.split(b"\0", 1)[0]


#: An attribute value holding ``<`` or ``>``, on one line.
_ANGLED_ATTRIBUTE = re.compile(rb'="([^"\n<>]*[<>][^"\n]*)"')


def escape_angled_attributes(data: bytes) -> bytes:
    """The document with ``<`` and ``>`` inside attribute values escaped, as tolerant readers take it.

    Assimp's STL-to-COLLADA export of 2015 writes ``<node id="<STL_BINARY>">``
    (velodyne_description's VLP-16 and HDL-32E meshes). XML forbids ``<`` there
    and lxml refuses the file, but Assimp (RViz, Gazebo, coal) and PyBullet's
    tinyxml2 read the value up to its closing quote. Call it only on a document
    the strict parse refused: a valid one has no such value.
    """
    return _ANGLED_ATTRIBUTE.sub(
        lambda m: b'="' + m.group(1).replace(b"<", b"&lt;").replace(b">", b"&gt;") + b'"', data)


def read_bytes(data: bytes) -> ColladaScene:
    data = before_nul(data)
    if b"<!ENTITY" in data[: 1 << 16].upper() or b"<!DOCTYPE" in data[: 1 << 16].upper():
        raise Unsupported("the document has a DOCTYPE")
    try:
        root = etree.fromstring(data, _parser())
    except etree.XMLSyntaxError as exc:
        escaped = escape_angled_attributes(data)
        if escaped == data:
            raise Unsupported(f"XML: {exc}") from exc
        try:
            root = etree.fromstring(escaped, _parser())
        except etree.XMLSyntaxError:
            raise Unsupported(f"XML: {exc}") from exc
    return _Reader(root).scene()


class _Reader:
    def __init__(self, root: etree._Element) -> None:
        namespace = root.nsmap.get(None)
        if root.tag not in {f"{{{ns}}}COLLADA" for ns in COLLADA_NAMESPACES}:
            raise Unsupported("not a COLLADA 1.4/1.5 document")
        self.ns = f"{{{namespace}}}"
        self.root = root
        self.ids: dict[str, etree._Element] = {}
        self.duplicates: set[str] = set()
        for element in root.iter(etree.Element):
            ident = element.get("id")
            if ident is not None:
                if ident in self.ids:
                    self.duplicates.add(ident)
                self.ids[ident] = element
        self.sources: dict[str, np.ndarray] = {}

    def tag(self, name: str) -> str:
        return self.ns + name

    def local(self, element: etree._Element) -> str:
        tag = element.tag
        if not isinstance(tag, str) or not tag.startswith(self.ns):
            raise Unsupported(f"unexpected element {tag!r}")
        return tag[len(self.ns) :]

    def target(self, url: str | None, kind: str) -> etree._Element:
        if not url or not url.startswith("#"):
            raise Unsupported(f"external or missing reference {url!r}")
        element = self.ids.get(url[1:])
        if url[1:] in self.duplicates:
            raise Unsupported(f"ambiguous reference {url!r}")
        if element is None or self.local(element) != kind:
            raise Unsupported(f"broken reference {url!r}")
        return element

    # -- document ---------------------------------------------------------------

    def unit(self) -> float:
        asset = self.root.find(self.tag("asset"))
        unit = asset.find(self.tag("unit")) if asset is not None else None
        if unit is None or unit.get("meter") is None:
            return 1.0
        try:
            value = float(unit.get("meter", ""))
        except ValueError as exc:
            raise Unsupported("bad unit") from exc
        if not (math.isfinite(value) and value > 0):
            raise Unsupported("bad unit")
        return value

    def scene(self) -> ColladaScene:
        scene = self.root.find(self.tag("scene"))
        instance = scene.find(self.tag("instance_visual_scene")) if scene is not None else None
        if instance is None:
            raise Unsupported("no <scene><instance_visual_scene>")
        visual = self.target(instance.get("url"), "visual_scene")
        parts: list[Part] = []
        for child in visual:
            name = self.local(child)
            if name == "node":
                self.node(child, np.eye(4), parts, depth=0)
            elif name not in ("asset", "extra", "evaluate_scene"):
                raise Unsupported(f"<{name}> in a visual scene")
        return ColladaScene(parts, self.unit())

    def node(self, node: etree._Element, parent: np.ndarray, parts: list[Part], depth: int) -> None:
        if depth > 200:
            raise Unsupported("nodes nested too deep")
        transforms = []
        children = []
        for child in node:
            name = self.local(child)
            if name in ("matrix", "translate", "rotate", "scale"):
                transforms.append(_transform(name, child.text))
            elif name in ("node", "instance_geometry"):
                children.append(child)
            elif name in ("asset", "extra", "instance_camera", "instance_light"):
                continue
            else:  # lookat, skew, instance_node, instance_controller, ...
                raise Unsupported(f"<{name}> in a node")
        # pycollada multiplies the transforms in single precision, trimesh the parent by that
        matrix = np.identity(4, dtype=np.float32)
        if len(transforms) == 1:
            matrix = transforms[0]
        elif transforms:
            for transform in transforms:
                matrix = np.dot(matrix, transform)
        placed = np.dot(parent, matrix)
        for child in children:
            if self.local(child) == "node":
                self.node(child, placed, parts, depth + 1)
            else:
                self.instance_geometry(child, placed, parts)

    def instance_geometry(
        self, instance: etree._Element, matrix: np.ndarray, parts: list[Part]
    ) -> None:
        geometry = self.target(instance.get("url"), "geometry")
        bound: set[str] = set()
        for bind in instance.iter(self.tag("bind_material")):
            for material in bind.iter(self.tag("instance_material")):
                symbol = material.get("symbol")
                self.target(material.get("target"), "material")
                if symbol is not None:
                    bound.add(symbol)
        meshes = [child for child in geometry if self.local(child) not in ("asset", "extra")]
        if len(meshes) != 1 or self.local(meshes[0]) != "mesh":
            raise Unsupported("a geometry that is not one <mesh>")
        for primitive in meshes[0]:
            name = self.local(primitive)
            if name in ("source", "vertices", "extra") or name in _SKIPPED:
                continue
            if name not in _TRIANGLES:
                raise Unsupported(f"<{name}> primitives")
            part = self.primitive(primitive, name, bound, matrix)
            if part is not None:
                parts.append(part)

    # -- primitives ----------------------------------------------------------------

    def primitive(
        self, primitive: etree._Element, name: str, bound: set[str], matrix: np.ndarray
    ) -> Part | None:
        inputs = []
        for element in primitive.findall(self.tag("input")):
            try:
                offset = int(element.get("offset", ""))
            except ValueError as exc:
                raise Unsupported("an input without offset") from exc
            inputs.append((element.get("semantic"), offset, element.get("source"), element))
        if not inputs:
            raise Unsupported("a primitive without inputs")
        stride = max(offset for _, offset, _, _ in inputs) + 1
        vertex_inputs = [i for i in inputs if i[0] == "VERTEX"]
        if len(vertex_inputs) != 1:
            raise Unsupported("not exactly one VERTEX input")
        _, vertex_offset, vertex_url, _ = vertex_inputs[0]
        vertices_element = self.target(vertex_url, "vertices")
        positions = None
        normal_source: tuple[int, str | None] | None = None
        texcoords: list[tuple[int, str | None]] = []
        for element in vertices_element.findall(self.tag("input")):
            semantic = element.get("semantic")
            if semantic == "POSITION":
                positions = self.source(element.get("source"), 3)
            elif semantic == "NORMAL":
                normal_source = (vertex_offset, element.get("source"))
            elif semantic == "TEXCOORD":
                texcoords.append((vertex_offset, element.get("source")))
            else:
                raise Unsupported(f"a {semantic} input in <vertices>")
        if positions is None:
            raise Unsupported("<vertices> without POSITION")
        for semantic, offset, url, _ in inputs:
            if semantic == "NORMAL":
                if normal_source is not None:
                    raise Unsupported("two NORMAL inputs")
                normal_source = (offset, url)
            elif semantic == "TEXCOORD":
                texcoords.append((offset, url))

        count = _count(primitive.get("count"))
        if name == "polygons":
            index, vcount = self.polygons(primitive, stride)
        else:
            index = _ints(_text(primitive.find(self.tag("p"))))
            vcount = None
            if name == "polylist":
                vcount = _ints(_text(primitive.find(self.tag("vcount"))))
        if index.size % stride:
            raise Unsupported("index count not a multiple of the inputs")
        index = index.reshape(-1, stride)
        if vcount is None:
            if count is not None and index.shape[0] != 3 * count:
                raise Unsupported("triangle count disagrees with the indices")
            if index.shape[0] % 3:
                raise Unsupported("triangle indices not a multiple of 3")
            corners = index
        else:
            if count is not None and vcount.size != count:
                raise Unsupported("polygon count disagrees with vcount")
            if vcount.size and (vcount.min() < 3 or int(vcount.sum()) != index.shape[0]):
                raise Unsupported("vcount disagrees with the indices")
            corners = index[_fan(vcount)] if vcount.size else index[:0]
        if corners.shape[0] == 0:
            return Part(np.zeros((0, 3)), None, None, False, matrix)

        vertices = _take(positions, corners[:, vertex_offset])
        normals = None
        if normal_source is not None:
            offset, url = normal_source
            normals = _take(self.source(url, 3), corners[:, offset])
        textured = primitive.get("material") in bound
        uv = None
        if textured and texcoords:
            offset, url = texcoords[0]
            uv = _take(self.source(url, 2), corners[:, offset])
        return Part(vertices, normals, uv, textured, matrix)

    def polygons(self, primitive: etree._Element, stride: int) -> tuple[np.ndarray, np.ndarray]:
        chunks, counts = [], []
        for child in primitive:
            name = self.local(child)
            if name == "p":
                values = _ints(_text(child))
                if values.size % stride:
                    raise Unsupported("polygon indices not a multiple of the inputs")
                chunks.append(values)
                counts.append(values.size // stride)
            elif name not in ("input", "extra"):
                raise Unsupported(f"<{name}> in <polygons>")
        if not chunks:
            return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
        return np.concatenate(chunks), np.asarray(counts, dtype=np.int64)

    def source(self, url: str | None, width: int) -> np.ndarray:
        key = url or ""
        if key in self.sources:
            values = self.sources[key]
            if values.shape[1] != width:
                raise Unsupported("a source read with two widths")
            return values
        source = self.target(url, "source")
        array = source.find(self.tag("float_array"))
        technique = source.find(self.tag("technique_common"))
        accessor = technique.find(self.tag("accessor")) if technique is not None else None
        if array is None or accessor is None:
            raise Unsupported("a source without float_array and accessor")
        if accessor.get("source") != "#" + (array.get("id") or "\0"):
            raise Unsupported("an accessor of another array")
        params = accessor.findall(self.tag("param"))
        stride = _count(accessor.get("stride")) or 1
        count = _count(accessor.get("count"))
        offset = _count(accessor.get("offset")) or 0
        if offset or len(params) != stride or stride != width or any(p.get("name") is None for p in params):
            raise Unsupported("an accessor this reader does not map")
        values = _floats(_text(array))  # single precision, as pycollada
        declared = _count(array.get("count"))
        if declared is not None and declared != values.size:
            raise Unsupported("float_array count disagrees with its values")
        if count is None or count * stride > values.size:
            raise Unsupported("accessor count beyond its array")
        result = values[: count * stride].reshape(count, stride)
        self.sources[key] = result
        return result


def _fan(vcount: np.ndarray) -> np.ndarray:
    """Corner rows of the fan triangulation (first, k, k+1) of polygons of *vcount* corners."""
    starts = np.concatenate(([0], np.cumsum(vcount)[:-1]))
    triangles = vcount - 2
    first = np.repeat(starts, triangles)
    within = np.arange(int(triangles.sum())) - np.repeat(np.cumsum(triangles) - triangles, triangles)
    rows = np.stack((first, first + within + 1, first + within + 2), axis=1)
    return rows.reshape(-1)


def _take(values: np.ndarray, index: np.ndarray) -> np.ndarray:
    if index.size and (index.min() < 0 or index.max() >= len(values)):
        raise Unsupported("an index beyond its source")
    taken: np.ndarray = values[index]
    return taken


def _text(element: etree._Element | None) -> str:
    if element is None:
        raise Unsupported("a missing index or value list")
    return element.text or ""


def _floats(text: str) -> np.ndarray:
    """Single-precision values, as pycollada reads them (so the results match trimesh's)."""
    return _numbers(text, np.float32)


def _ints(text: str) -> np.ndarray:
    return _numbers(text, np.int64)


def _numbers(text: str, dtype: type) -> np.ndarray:
    if not text.strip():
        return np.zeros(0, dtype=dtype)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            values: np.ndarray = np.fromstring(text, dtype=dtype, sep=" ")
            return values
    except (ValueError, DeprecationWarning) as exc:
        raise Unsupported("a list with non-numbers") from exc


def _count(value: str | None) -> int | None:
    if value is None:
        return None
    try:
        number = int(value)
    except ValueError as exc:
        raise Unsupported("a bad count") from exc
    if number < 0:
        raise Unsupported("a negative count")
    return number


def _transform(name: str, text: str | None) -> np.ndarray:
    """The 4×4 matrix of one transform element, in single precision as pycollada builds it."""
    values = _floats(text or "")
    out = np.identity(4, dtype=np.float32)
    if name == "matrix":
        if values.size != 16:
            raise Unsupported("a matrix without 16 values")
        return values.reshape(4, 4)
    if name == "translate":
        if values.size != 3:
            raise Unsupported("a translate without 3 values")
        out[:3, 3] = values
    elif name == "scale":
        if values.size != 3:
            raise Unsupported("a scale without 3 values")
        out[0, 0], out[1, 1], out[2, 2] = values
    else:  # rotate: axis and angle in degrees
        if values.size != 4:
            raise Unsupported("a rotate without 4 values")
        x, y, z, angle = values
        out = _rotation(x, y, z, angle * np.pi / 180.0)
    return out


def _rotation(x: Any, y: Any, z: Any, angle: Any) -> np.ndarray:
    """pycollada's rotation matrix (``collada.scene.makeRotationMatrix``: the axis as written)."""
    c = np.cos(angle)
    s = np.sin(angle)
    t = 1 - c
    return np.array(
        [
            [t * x * x + c, t * x * y - s * z, t * x * z + s * y, 0],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x, 0],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c, 0],
            [0, 0, 0, 1],
        ],
        dtype=np.float32,
    )
