"""`model://` URIs into Gazebo Classic's online model database (urdftool/targets/gazebo_classic_models.py).

Gazebo Classic downloads such a model on first load, so in a world Classic reads they are not
missing: urdftool reports them as an info (it reads no network). In a gz-sim world, which does not
download `model://`, and for a model the database does not hold, they stay errors."""

from __future__ import annotations

import collections
from pathlib import Path

import pytest
from lxml import etree

from tests.conftest import FIXTURES
from urdftool.pipeline.check import CheckOptions, check_file
from urdftool.targets.gazebo_classic_models import MODEL_DATABASE, database_model, read_by_classic

CHAMP = FIXTURES / "gazebo_classic" / "champ_outdoor.world"
OPTIONS = CheckOptions(rule_options={"dynamics": False})


def _codes(path: Path) -> collections.Counter[tuple[str, str]]:
    return collections.Counter((d.code, d.severity.value) for r in check_file(str(path), OPTIONS)
                               for d in r.diagnostics)


def test_a_classic_world_of_database_models_checks_without_errors() -> None:
    found = _codes(CHAMP)
    assert found[("M001", "info")] == 40  # one per model of the world
    assert not [key for key in found if key[1] == "error"], found


def test_a_gz_sim_world_does_not_download_model_uris(tmp_path: Path) -> None:
    """The same world as SDFormat 1.8 (gz-sim's), or with a gz-sim system: the meshes are missing."""
    text = CHAMP.read_text()
    newer = tmp_path / "newer.world"
    newer.write_text(text.replace("<sdf version='1.6'>", "<sdf version='1.8'>", 1))
    assert _codes(newer)[("M001", "error")] == 40
    systems = tmp_path / "systems.world"
    systems.write_text(text.replace("<world name='default'>", "<world name='default'><plugin "
                                    "filename='gz-sim-physics-system' name='gz::sim::systems::Physics'/>", 1))
    assert _codes(systems)[("M001", "error")] == 40


def test_a_model_the_database_does_not_hold_is_still_missing(tmp_path: Path) -> None:
    world = tmp_path / "own.world"
    world.write_text(CHAMP.read_text().replace("model://construction_cone/", "model://our_cone/"))
    found = _codes(world)
    assert found[("M001", "error")] >= 1 and found[("M001", "info")] < 40


@pytest.mark.parametrize("version, severity", [("1.6", "info"), ("1.9", "error")])
def test_an_included_database_model(tmp_path: Path, version: str, severity: str) -> None:
    world = tmp_path / "cones.world"
    world.write_text(f'<sdf version="{version}"><world name="w"><include><uri>model://construction_cone'
                     '</uri><pose>1 0 0 0 0 0</pose></include></world></sdf>')
    findings = [(d.code, d.severity.value) for r in check_file(str(world), OPTIONS) for d in r.diagnostics]
    assert ("S103", severity) in findings
    assert not [f for f in findings if f[1] == "error" and f[0] != "S103"]


def test_the_table() -> None:
    assert len(MODEL_DATABASE) == 256
    assert database_model("model://construction_cone/meshes/construction_cone.dae") == "construction_cone"
    assert database_model("model://suv") == "suv"
    assert database_model("model://my_robot/meshes/base.stl") is None
    assert database_model("package://suv/meshes/suv.dae") is None

    def world(version: str | None, plugin: str = "") -> etree._Element:
        written = f' version="{version}"' if version is not None else ""
        inside = f'<plugin filename="{plugin}" name="p"/>' if plugin else ""
        return etree.fromstring(f"<sdf{written}><world name='w'>{inside}</world></sdf>")[0]

    assert read_by_classic(world("1.6", "libgazebo_ros_diff_drive.so"))
    assert read_by_classic(world("1.7"))
    assert not read_by_classic(world("1.8"))
    assert not read_by_classic(world("1.6", "ignition-gazebo-physics-system"))
    assert not read_by_classic(world(None)) and not read_by_classic(world("one"))
