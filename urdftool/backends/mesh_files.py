"""trimesh reading a mesh file and the files it names, with urdftool's file rules.

A mesh names other files: an OBJ its ``.mtl`` library (``mtllib``), a COLLADA file its
textures. trimesh reads them through a resolver that keeps names inside the mesh's folder but
opens whatever it finds there and reads it whole: a FIFO named like the OBJ's ``.mtl`` made
every check of the robot wait forever. Every trimesh load of a mesh file in urdftool goes
through :func:`load` (or, for a load from bytes, :func:`resolver`), whose resolver reads only
regular files, within the mesh size cap (:mod:`urdftool.safe_files`), as urdftool reads the
mesh itself; a refused file is, to trimesh, a file it could not read (the OBJ loads without
its materials).
"""

from __future__ import annotations

import functools
import os
from typing import Any

from urdftool.safe_files import read_regular


def load(path: str, **options: Any) -> Any:
    """``trimesh.load(path, **options)``, with the files the mesh names read as urdftool reads
    files. Raises what trimesh raises."""
    import trimesh

    return trimesh.load(path, resolver=resolver(path), **options)


def resolver(path: str) -> Any:
    """A trimesh resolver for the files named by the mesh at *path* (for loads from bytes)."""
    return _resolver_class()(path)


@functools.cache
def _resolver_class() -> type:
    """trimesh's own resolver for files beside the mesh, reading through :func:`read_regular`
    (a class made on first use: trimesh is imported only by the runs that read meshes)."""
    import trimesh

    class RegularFilesResolver(trimesh.resolvers.FilePathResolver):
        def get(self, name: str) -> bytes:
            # The names trimesh tries, in its order (FilePathResolver.get), each kept inside
            # the mesh's folder by its `absolute`; the first that exists is read.
            for candidate in (name.strip(), name.strip().lstrip("/"), os.path.split(name)[-1]):
                try:
                    path = self.absolute(candidate)
                except ValueError:
                    continue
                if path.exists():
                    return read_regular(path, "mesh")
            data: bytes = super().get(name)  # raises trimesh's own error for a missing file
            return data

    return RegularFilesResolver
