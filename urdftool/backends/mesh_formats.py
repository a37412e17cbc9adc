"""Which mesh files which engines can read, decided from the file's name and first bytes.

No mesh library is imported here: the format of a file is sniffed from its
extension and header (a binary STL's size is fixed by its triangle count), so
``mesh-format-unsupported`` costs one small read per file.

The support table was established by loading one small mesh of each kind in
the engines urdftool exports to (MuJoCo 3-4 and PyBullet 3.2); the test suite
re-checks it against the installed engines (``tests/test_meshes_engines.py``):

=============  ======================  ====================================
format         MuJoCo                  PyBullet
=============  ======================  ====================================
binary STL     yes, up to 200000 faces yes
ASCII STL      no ("number of faces")  no (silently loads no shape)
OBJ            yes                     yes
COLLADA (DAE)  no ("no decoder")       yes (applies ``<unit meter>``)
others         no                      no (refuses the whole URDF)
=============  ======================  ====================================
"""

from __future__ import annotations

import os
import struct

from urdftool.records import record
from urdftool.safe_files import read_head

#: MuJoCo's STL decoder refuses files with more triangles than this.
MUJOCO_MAX_STL_FACES = 200_000

#: Extensions trimesh reads (its loaders for these need no optional packages beyond
#: what urdftool installs); anything else is reported as unsupported, not unreadable.
TRIMESH_EXTENSIONS = frozenset({".stl", ".obj", ".dae", ".ply", ".off", ".glb", ".gltf", ".3mf"})

ENGINE_NAMES = {"mujoco": "MuJoCo", "pybullet": "PyBullet"}


@record
class MeshFormat:
    """What kind of mesh file this is.

    ``kind`` is ``stl-binary``, ``stl-ascii``, ``obj``, ``dae`` or the lower-case
    extension without its dot for anything else; ``faces`` is the triangle count
    where the header gives it (binary STL), else ``None``.
    """

    kind: str
    extension: str
    faces: int | None = None

    @property
    def label(self) -> str:
        """The format in words, to follow "is": "an ASCII STL file", "a COLLADA (.dae) file"."""
        return {
            "stl-binary": "a binary STL file",
            "stl-ascii": "an ASCII STL file",
            "obj": "an OBJ file",
            "dae": "a COLLADA (.dae) file",
        }.get(self.kind, f"a {self.extension or 'extension-less'} file")

    @property
    def trimesh_reads(self) -> bool:
        return self.extension in TRIMESH_EXTENSIONS


#: (path, size, mtime, inode) -> the format sniffed from an STL file's header: each file is read
#: once per process, as :func:`urdftool.backends.meshes.content_key` hashes it once
_STL_FORMATS: dict[tuple[str, int, int, int], MeshFormat] = {}


def sniff(path: str, status: os.stat_result | None = None) -> MeshFormat:
    """The format of the mesh at *path* (which must exist). Raises ``OSError``.

    *status*, the file's ``os.stat`` when the caller has it, saves asking again; then an STL
    file's header is read once per process, for as long as its size, time and inode stay.
    """
    extension = os.path.splitext(path)[1].lower()
    if extension != ".stl":
        kind = {".obj": "obj", ".dae": "dae"}.get(extension, extension.lstrip(".") or "none")
        return MeshFormat(kind, extension)
    if status is None:
        return _sniff_stl(path, extension, os.path.getsize(path))
    memo = (path, status.st_size, status.st_mtime_ns, status.st_ino)
    found = _STL_FORMATS.get(memo)
    if found is None:
        found = _STL_FORMATS[memo] = _sniff_stl(path, extension, status.st_size)
    return found


def _sniff_stl(path: str, extension: str, size: int) -> MeshFormat:
    head = read_head(path, 84)
    if len(head) == 84:
        (count,) = struct.unpack("<I", head[80:84])
        # Binary STL: an 80-byte header, a count, then 50 bytes per triangle. Many
        # CAD exporters start the header with "solid", so the size decides.
        if size == 84 + 50 * count:
            return MeshFormat("stl-binary", extension, count)
    if head.lstrip().lower().startswith(b"solid"):
        return MeshFormat("stl-ascii", extension)
    return MeshFormat("stl-binary", extension, None)


def engines_refusing(fmt: MeshFormat) -> dict[str, str]:
    """Engine key -> why that engine cannot use a mesh of format *fmt* (empty when all can)."""
    out: dict[str, str] = {}
    if fmt.kind == "stl-ascii":
        out["mujoco"] = "reads binary STL only"
        out["pybullet"] = "reads binary STL only (an ASCII STL silently loads as no shape)"
    elif fmt.kind == "dae":
        out["mujoco"] = "has no COLLADA reader"
    elif fmt.kind == "stl-binary":
        if fmt.faces is not None and fmt.faces > MUJOCO_MAX_STL_FACES:
            out["mujoco"] = f"reads STL files of at most {MUJOCO_MAX_STL_FACES} triangles"
    elif fmt.kind != "obj":
        out["mujoco"] = f"reads STL and OBJ, not {fmt.extension or 'extension-less'} files"
        out["pybullet"] = f"reads STL, OBJ and DAE, not {fmt.extension or 'extension-less'} files"
    return out
