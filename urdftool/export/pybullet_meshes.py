"""Meshes for PyBullet: paths it can open from anywhere, in formats it reads well.

PyBullet resolves a mesh ``filename`` against the URDF's folder; it has no
notion of ROS packages, so ``package://`` paths work only from some working
directories. Every mesh is therefore written as a path relative to OUT (or an
asset beside it with ``--copy-assets``).

PyBullet reads OBJ and binary STL well. Its COLLADA reader loads some DAE
files partly (no transforms, no units) and fails the whole load on others,
and ASCII STL gives an empty shape; those, and every other format trimesh
reads, are converted to OBJ in ``assets/``. A DAE file carries its colours;
an OBJ without a material file does not, so the converted visual gets the
mesh's dominant colour (by face count) as its ``<material>`` unless the
source already gives it one.
"""

from __future__ import annotations

import dataclasses
from dataclasses import field
from pathlib import Path
from typing import cast

from urdftool.backends import mesh_files
from urdftool.backends.meshes import MeshError, load_trimesh
from urdftool.catalogue.conversion import MeshNotExportable
from urdftool.diagnostics import Diagnostic
from urdftool.export.assets import MeshFiles, MeshUnavailable, is_binary_stl
from urdftool.model import Collision, Link, Material, Mesh, Robot, Visual
from urdftool.records import record
from urdftool.safe_files import check_regular

RGBA = tuple[float, float, float, float]


def reads_natively(path: str, data: bytes) -> bool:
    """OBJ, and STL in its binary form: what PyBullet loads without loss."""
    suffix = Path(path).suffix.lower()
    return suffix == ".obj" or (suffix == ".stl" and is_binary_stl(data))


def convert_to_obj(path: str) -> bytes:
    """The mesh at *path* (scenes flattened with their transforms) as deterministic OBJ text."""
    from trimesh.exchange.obj import export_obj

    try:
        mesh = load_trimesh(path)
    except MeshError as exc:
        raise MeshUnavailable(f"trimesh cannot read it ({exc})") from exc
    text: str = export_obj(
        mesh, include_normals=False, include_color=False, include_texture=False, header=None
    )
    return text.encode("utf-8")


def dominant_colour(path: str) -> RGBA | None:
    """The colour (RGBA, 0..1) covering the most faces of the mesh file, if it has colours."""
    import numpy as np
    import trimesh

    try:
        check_regular(path, "mesh")
        scene = cast(trimesh.Scene, mesh_files.load(path, force="scene"))
    except Exception:  # trimesh raises many kinds; a colour is optional
        return None
    votes: dict[RGBA, int] = {}
    for geometry in scene.geometry.values():
        rgba = _geometry_colour(geometry)
        if rgba is not None:
            votes[rgba] = votes.get(rgba, 0) + len(getattr(geometry, "faces", ()))
    if not votes:
        return None
    best = max(sorted(votes), key=lambda colour: votes[colour])
    return tuple(float(np.round(v, 6)) for v in best)  # type: ignore[return-value]


def _geometry_colour(geometry: object) -> RGBA | None:
    visual = getattr(geometry, "visual", None)
    material = getattr(visual, "material", None)
    raw = None
    if material is not None:
        raw = getattr(material, "baseColorFactor", None)
        if raw is None:
            raw = getattr(material, "diffuse", None)
    elif getattr(visual, "kind", None) in ("face", "vertex"):
        raw = visual.main_color  # type: ignore[union-attr]
    if raw is None or len(raw) < 3:
        return None
    values = [float(v) / 255.0 for v in raw][:4]
    return (values[0], values[1], values[2], values[3] if len(values) == 4 else 1.0)


@record(frozen=False)
class MeshPlan:
    """Every mesh of a robot carried for PyBullet: written filenames, asset files, colours, refusals."""

    files: MeshFiles
    #: :func:`mesh_key` -> filename written in the URDF
    filenames: dict[str, str] = field(default_factory=dict)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    _colours: dict[str, RGBA | None] = field(default_factory=dict)

    @classmethod
    def create(cls, out_dir: Path | None, copy: bool, absolute: bool = False) -> MeshPlan:
        return cls(MeshFiles(out_dir, reads_natively, convert_to_obj, ".obj", copy=copy, absolute=absolute))

    def carry(self, robot: Robot) -> Robot:
        """*robot* with every visual of a converted mesh coloured; filenames and refusals recorded."""
        source_dir = Path(robot.path).resolve().parent if robot.path else None
        links = tuple(self._link(link, source_dir) for link in robot.links)
        return dataclasses.replace(robot, links=links)

    def _link(self, link: Link, source_dir: Path | None) -> Link:
        """*link* without the elements whose mesh cannot be carried, converted visuals coloured."""

        def kept(element: Visual | Collision) -> bool:
            mesh = element.geometry
            return not isinstance(mesh, Mesh) or self._plan(mesh, link, source_dir)

        visuals = tuple(self._coloured(v) for v in link.visuals if kept(v))
        collisions = tuple(c for c in link.collisions if kept(c))
        if visuals == link.visuals and collisions == link.collisions:
            return link
        return dataclasses.replace(link, visuals=visuals, collisions=collisions)

    def _plan(self, mesh: Mesh, link: Link, source_dir: Path | None) -> bool:
        """Plan the file of *mesh*; ``False`` (and a warning) when it cannot be carried."""
        where = f"link[{link.name}]/mesh[{mesh.filename}]"
        path = mesh.resolved or pybullet_lookup(mesh.filename, source_dir)
        try:
            if path is None:
                raise MeshUnavailable(f"'{mesh.filename}' did not resolve to a file")
            planned = self.files.carry(path)
        except MeshUnavailable as exc:
            self.diagnostics.append(
                MeshNotExportable.diagnostic(
                    f"link '{link.name}': mesh {exc}; the element is left out (PyBullet would refuse "
                    "the whole file)",
                    mesh.span,
                    element=where,
                    help="make the path resolve (--package NAME=DIR, --package-path DIR) or convert "
                    "the file to OBJ or binary STL",
                    data={"link": link.name, "filename": mesh.filename},
                )
            )
            return False
        key = mesh_key(mesh)
        self.filenames[key] = planned.reference
        if planned.converted and key not in self._colours:
            self._colours[key] = dominant_colour(path)
        return True

    def _coloured(self, visual: Visual) -> Visual:
        mesh = visual.geometry
        if not isinstance(mesh, Mesh):
            return visual
        colour = self._colours.get(mesh_key(mesh))
        if colour is None or visual.material is not None:
            return visual
        return dataclasses.replace(visual, material=Material(None, colour))


def mesh_key(mesh: Mesh) -> str:
    """The key of a mesh in :attr:`MeshPlan.filenames`: its resolved path, else its filename."""
    return mesh.resolved or mesh.filename


def pybullet_lookup(filename: str, source_dir: Path | None) -> str | None:
    """Where PyBullet itself finds a mesh that urdftool's package resolver did not.

    PyBullet drops a leading ``package://`` and tries the rest relative to the
    URDF's folder, its parent and its grandparent. Files written for PyBullet
    (pybullet_data's) rely on this, so the export finds them the same way.
    """
    if source_dir is None or "://" in filename.removeprefix("package://"):
        return None
    relative = filename.removeprefix("package://")
    for folder in (source_dir, source_dir.parent, source_dir.parent.parent):
        candidate = folder / relative
        if candidate.is_file():
            return str(candidate)
    return None
