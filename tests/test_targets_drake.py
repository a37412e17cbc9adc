"""Drake's consumer table cannot drift from Drake: every ``--target drake`` finding is measured in pydrake.

Each fixture of fixtures/targets/ is checked with ``--target drake`` and loaded
the way Drake's own examples load a URDF (``Parser(plant).AddModels`` into a
MultibodyPlant with a SceneGraph), and each finding's predicted effect is
measured: the file refused for an STL collision mesh (T006), the zero mass and
the stopped simulation of a link without ``<inertial>`` (T001), a ball in the
open volume of a concave collision mesh touching its hull (T003), the mimic
coupler constraint in discrete, TAMSI and continuous plants (T004), a floating
joint dropped for a free body (T005). The mesh formats of the table are tried
one by one, and links on fixed joints stay bodies (no T002 for Drake). That
every kind of finding is measured is checked with the other engines'
(``test_every_engine_effect_is_measured`` in tests/test_targets_engines.py).
"""

from __future__ import annotations

import logging
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.conftest import FIXTURES
from urdftool.pipeline.check import CheckOptions, check_file
from urdftool.targets import TARGETS

pytestmark = pytest.mark.slow

pytest.importorskip("pydrake")

from pydrake.geometry import Sphere  # noqa: E402
from pydrake.math import RigidTransform  # noqa: E402
from pydrake.multibody.parsing import Parser  # noqa: E402
from pydrake.multibody.plant import (  # noqa: E402
    AddMultibodyPlantSceneGraph,
    CoulombFriction,
    DiscreteContactApproximation,
    MultibodyPlant,
)
from pydrake.systems.analysis import Simulator  # noqa: E402
from pydrake.systems.framework import DiagramBuilder  # noqa: E402

TARGET_FIXTURES = sorted((FIXTURES / "targets").glob("*.urdf"))
#: Inside the open volume of the concave fixtures, well clear of the mesh surface.
PROBES = {"tray.urdf": (0.0, 0.0, 0.05)}


def findings(path: Path) -> list[Any]:
    options = CheckOptions(select=("T",), rule_options={"targets": ("drake",)})
    return [d for r in check_file(str(path), options) for d in r.diagnostics]


class Loaded:
    """A fixture parsed into a plant with a SceneGraph, as Drake's examples do (time_step 0: continuous)."""

    def __init__(self, path: Path, time_step: float = 1e-3, approximation: Any = None,
                 probe: tuple[float, float, float] | None = None) -> None:
        builder = DiagramBuilder()
        self.plant, self.scene_graph = AddMultibodyPlantSceneGraph(builder, time_step)
        if approximation is not None:
            self.plant.set_discrete_contact_approximation(approximation)
        Parser(self.plant).AddModels(str(path))
        if probe is not None:  # a 1 cm ball fixed in the world
            self.plant.RegisterCollisionGeometry(
                self.plant.world_body(), RigidTransform(np.array(probe)), Sphere(0.01), "probe",
                CoulombFriction(1.0, 1.0),
            )
        self.plant.Finalize()
        self.diagram = builder.Build()
        self.context = self.diagram.CreateDefaultContext()
        self.plant_context = self.plant.GetMyMutableContextFromRoot(self.context)

    def step(self, seconds: float = 1e-3) -> None:
        Simulator(self.diagram, self.context).AdvanceTo(seconds)

    def query(self) -> Any:
        context = self.scene_graph.GetMyContextFromRoot(self.context)
        return self.scene_graph.get_query_output_port().Eval(context)


@pytest.mark.parametrize("path", TARGET_FIXTURES, ids=lambda p: p.stem)
def test_drake_predictions(path: Path, caplog: pytest.LogCaptureFixture) -> None:
    found = findings(path)
    refused = [d for d in found if d.code == "T006" and d.data["refused"]]
    if refused:
        # The parser stops at the first such mesh; without a SceneGraph (no collision geometry) it loads.
        with pytest.raises(RuntimeError, match=r"MakeConvexHull only applies to \.obj, \.vtk, and \.gltf"):
            Loaded(path)
        bare = MultibodyPlant(0.0)
        Parser(bare).AddModels(str(path))
        assert {d.code for d in found} == {"T006"}, "nothing else to measure in a file Drake refuses"
        return
    with caplog.at_level(logging.WARNING):
        loaded = Loaded(path)
    plant = loaded.plant
    for d in found:
        if d.code == "T001":
            _massless(loaded, d)
        elif d.code == "T003":
            assert _hull_touches_probe(path), d.message
        elif d.code == "T004":
            _mimic(path, loaded, d)
        elif d.code == "T005":
            assert d.data["effect"] == "free"
            body = plant.GetBodyByName(d.data["child"])
            assert not plant.HasJointNamed(d.data["joint"]), d.message
            assert body.is_floating_base_body(), d.message
            at = plant.EvalBodyPoseInWorld(loaded.plant_context, body).translation()
            assert np.allclose(at, 0.0), "a free body at the world origin, not at the joint's origin"
            warning = f"Joint '{d.data['joint']}' specified as type floating which is not supported"
            assert warning in caplog.text, d.message
        else:
            pytest.fail(f"no engine measure for {d.code}: {d.message}")
    # Drake welds fixed joints and keeps their children as bodies (no T002 for Drake).
    for joint in ET.parse(path).getroot().iter("joint"):
        if joint.get("type") == "fixed":
            child = joint.find("child")
            assert child is not None and plant.HasBodyNamed(child.get("link") or "")
            assert plant.GetJointByName(joint.get("name") or "").type_name() == "weld"
    # Where no finding says a simulation stops, it does not.
    if not any(d.data.get("stops") for d in found):
        Loaded(path).step()


def _massless(loaded: Loaded, d: Any) -> None:
    body = loaded.plant.GetBodyByName(d.data["link"])
    assert body.default_mass() == 0.0, d.message
    assert not body.default_rotational_inertia().CopyToFullMatrix3().any(), d.message
    assert body.is_floating_base_body() == d.data["floats"], d.message
    if d.data["stops"]:
        with pytest.raises(RuntimeError, match=rf"not positive-definite.*body {d.data['link']}"):
            loaded.step()


def _hull_touches_probe(path: Path) -> bool:
    """A ball in the open volume touches the mesh: point contact and signed distance use the hull."""
    loaded = Loaded(path, probe=PROBES[path.name])
    query = loaded.query()
    inspector = query.inspector()
    contacts = {frozenset((inspector.GetName(p.id_A), inspector.GetName(p.id_B)))
                for p in query.ComputePointPairPenetration()}
    distances = [s.distance for s in query.ComputeSignedDistancePairwiseClosestPoints(1.0)
                 if "probe" in (inspector.GetName(s.id_A), inspector.GetName(s.id_B))]
    hit = any("probe" in pair for pair in contacts)
    assert hit == (min(distances) < 0)
    return hit


def _mimic(path: Path, loaded: Loaded, d: Any) -> None:
    assert d.data["effect"] == "discrete-only"
    follower, leader = d.data["joint"], d.data["leader"]
    # The default discrete plant (SAP, approximation "lagged") couples the joints.
    plant = loaded.plant
    assert plant.get_discrete_contact_approximation() == DiscreteContactApproximation.kLagged
    assert plant.num_constraints() == 1, d.message
    plant.GetJointByName(leader).set_translation(loaded.plant_context, 0.02)
    loaded.step(0.01)
    ql = plant.GetJointByName(leader).get_translation(loaded.plant_context)
    qf = plant.GetJointByName(follower).get_translation(loaded.plant_context)
    assert qf == pytest.approx(ql, abs=1e-4) and qf > 0.005, (ql, qf)
    # TAMSI leaves the <mimic> out; a continuous plant adds it and stops at the first step.
    assert Loaded(path, approximation=DiscreteContactApproximation.kTamsi).plant.num_constraints() == 0
    continuous = Loaded(path, time_step=0.0)
    assert continuous.plant.num_constraints() == 1
    with pytest.raises(RuntimeError, match="Continuous time does not support constraints"):
        continuous.step()


def test_drake_collision_formats(tmp_path: Path) -> None:
    """The formats of the table are the ones Drake reads; any other stops the load."""
    trimesh = pytest.importorskip("trimesh")
    tetra = trimesh.Trimesh(
        vertices=[(0, 0, 0), (0.1, 0, 0), (0, 0.1, 0), (0, 0, 0.1)],
        faces=[(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)],
    )
    (tmp_path / "tetra.vtk").write_text(
        "# vtk DataFile Version 2.0\ntetra\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n"
        "0 0 0\n0.1 0 0\n0 0.1 0\n0 0 0.1\nCELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n",
        encoding="utf-8",
    )
    read = set()
    for extension in (".obj", ".gltf", ".glb", ".stl", ".STL", ".dae", ".ply", ".vtk"):
        mesh = tmp_path / f"tetra{extension}"
        if extension == ".gltf":  # one file, its buffer embedded
            mesh.write_bytes(trimesh.exchange.gltf.export_gltf(tetra, embed_buffers=True)["model.gltf"])
        elif extension != ".vtk":
            exported = tetra.export(file_type=extension.lstrip(".").lower())
            mesh.write_bytes(exported if isinstance(exported, bytes) else exported.encode())
        urdf = tmp_path / "tetra.urdf"
        urdf.write_text(
            '<robot name="tetra"><link name="l"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" '
            f'iyy="1" iyz="0" izz="1"/></inertial><collision><geometry><mesh filename="{mesh.name}"/>'
            "</geometry></collision></link></robot>",
            encoding="utf-8",
        )
        try:
            Loaded(urdf)
        except RuntimeError as error:
            assert "MakeConvexHull only applies to" in str(error)
        else:
            read.add(extension.lower())
    assert read == set(TARGETS["drake"].collision_formats or ())


def test_drake_massless_welded_link_does_not_stop(tmp_path: Path) -> None:
    """A massless flange welded to a massive link (UR's tool0) has zero mass, and the plant still steps."""
    urdf = tmp_path / "flange.urdf"
    inertia = '<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>'
    urdf.write_text(
        f'<robot name="flange"><link name="base"><inertial><mass value="2"/>{inertia}</inertial></link>'
        f'<link name="arm"><inertial><mass value="1"/>{inertia}</inertial></link><link name="flange"/>'
        '<joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 1 0"/>'
        '<limit lower="-1" upper="1" effort="10" velocity="1"/></joint>'
        '<joint name="mount" type="fixed"><parent link="arm"/><child link="flange"/></joint></robot>',
        encoding="utf-8",
    )
    (d,) = findings(urdf)
    assert (d.code, d.data["link"], d.data["stops"]) == ("T001", "flange", False)
    loaded = Loaded(urdf)
    _massless(loaded, d)
    loaded.step(0.01)  # the root floats, the arm swings, the flange rides on it: nothing is singular
