"""The lean COLLADA reader against trimesh (pycollada): the same facts for every corpus file."""

from __future__ import annotations

import glob

import numpy as np
import pytest

from tests.conftest import ERD, SEEDS
from urdftool.backends import collada, collada_trimesh, meshes


def _dae_files() -> list[str]:
    found: list[str] = []
    if ERD is not None:
        found += glob.glob(str(ERD / "**" / "*.dae"), recursive=True)
    found += [
        p for p in glob.glob(str(SEEDS / "**" / "*"), recursive=True) if p.lower().endswith(".dae")
    ]
    return sorted(found)


FILES = _dae_files()
BATCHES = 6


def _close(a: object, b: object, rtol: float) -> bool:
    x, y = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    scale = max(float(np.abs(y).max(initial=0.0)), 1e-300)
    return bool(np.abs(x - y).max(initial=0.0) <= rtol * scale)


@pytest.mark.parametrize("batch", range(BATCHES))
def test_lean_reader_matches_trimesh(batch: int) -> None:
    assert len(FILES) > 250
    problems = []
    for path in FILES[batch::BATCHES]:
        assert collada_trimesh.lean_collada(path) is not None, f"the lean reader falls back on {path}"
        lean = meshes.read_facts(path, lean=True)
        full = meshes.read_facts(path, lean=False)
        if (lean.vertices, lean.faces, lean.watertight, lean.unit) != (
            full.vertices,
            full.faces,
            full.watertight,
            full.unit,
        ):
            problems.append((path, "counts", lean, full))
            continue
        if not (
            _close(lean.bounds_min, full.bounds_min, 1e-9)
            and _close(lean.bounds_max, full.bounds_max, 1e-9)
        ):
            problems.append((path, "bounds", lean, full))
        if full.watertight and not (
            _close(lean.volume, full.volume, 1e-6)
            and _close(lean.second_moment, full.second_moment, 1e-6)
            and _close(lean.center_mass, full.center_mass, 1e-6)
        ):
            problems.append((path, "mass", lean, full))
    assert not problems, problems[:3]


DOC = """<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="0.001"/></asset>
  <library_geometries><geometry id="g"><mesh>
    <source id="p"><float_array id="pa" count="12">0 0 0 1 0 0 1 1 0 0 1 0</float_array>
      <technique_common><accessor source="#pa" count="4" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <polygons count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2 3</p></polygons>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node>
    <translate>1 2 3</translate>NODE<instance_geometry url="#g"/>
  </node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>"""


def test_polygons_are_fans_placed_by_their_node() -> None:
    scene = collada.read_bytes(DOC.replace("NODE", "").encode())
    assert scene.unit == 0.001
    (part,) = scene.parts
    assert part.vertices.tolist() == [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 0, 0], [1, 1, 0], [0, 1, 0]]
    assert part.matrix[:3, 3].tolist() == [1, 2, 3]


@pytest.mark.parametrize(
    "change",
    [
        ("NODE", '<instance_node url="#n"/>'),
        ("NODE", "<skew>45 0 1 0 1 0 0</skew>"),
        ('<?xml version="1.0"?>', '<?xml version="1.0"?><!DOCTYPE c [<!ENTITY e "x">]>'),
        ('count="12"', 'count="11"'),
        ("0 1 2 3</p>", "0 1 2 9</p>"),
    ],
)
def test_what_it_does_not_handle_is_left_to_trimesh(change: tuple[str, str]) -> None:
    with pytest.raises(collada.Unsupported):
        collada.read_bytes(DOC.replace(*change).replace("NODE", "").encode())
