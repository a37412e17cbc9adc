"""False errors found on real robot descriptions (docs/realworld.md), each as a minimal reproduction.

A CI gate must not fail valid models: each test here is a model that a real
consumer accepts and on which urdftool once reported an error.
"""

from __future__ import annotations

from pathlib import Path

import pytest

import urdftool
from tests.conftest import FIXTURES
from urdftool.diagnostics import Severity

RULES = FIXTURES / "rules"


def errors(path: Path) -> list[str]:
    return [f"{d.code} {d.message}" for d in urdftool.check(path).errors]


def test_pr2_style_sdf_link_in_a_gazebo_block_is_a_valid_reference() -> None:
    assert errors(RULES / "G001" / "good_sdf_link_in_gazebo.urdf") == []


def test_fuel_url_include_is_information_not_an_error() -> None:
    report = urdftool.check(FIXTURES / "precision" / "fuel_url.world")
    assert report.ok
    found = [d for d in report.diagnostics if d.code == "S103"]
    assert [d.severity for d in found] == [Severity.INFO]
    assert found[0].data["remote"] is True


def test_repeated_material_in_a_visual_is_a_warning_and_converts(tmp_path: Path) -> None:
    source = tmp_path / "cad.urdf"
    source.write_text(
        '<robot name="cad"><link name="base"><visual><geometry><box size="0.1 0.1 0.1"/></geometry>'
        '<material name="a"><color rgba="1 0 0 1"/></material>'
        '<material name="b"><color rgba="0 1 0 1"/></material></visual>'
        '<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>'
        "</inertial></link></robot>"
    )
    report = urdftool.check(source)
    repeated = [d for d in report.diagnostics if d.code == "S007"]
    assert [d.severity for d in repeated] == [Severity.WARNING] and report.ok
    assert "<mujoco" in urdftool.to_mjcf(source)
    # A repeated <axis> still changes the robot between loaders: an error that refuses the export.
    source.write_text(source.read_text().replace(
        "</link></robot>",
        '</link><link name="b"/><joint name="j" type="continuous"><parent link="base"/>'
        '<child link="b"/><axis xyz="1 0 0"/><axis xyz="0 1 0"/></joint></robot>'))
    assert any(d.code == "S007" and d.severity is Severity.ERROR for d in urdftool.check(source).errors)


def test_kinematics_only_model_gets_one_finding_and_one_refusal() -> None:
    path = RULES / "I011" / "bad.urdf"
    report = urdftool.check(path)
    assert report.ok, errors(path)
    codes = [d.code for d in report.diagnostics]
    assert codes.count("I011") == 1
    assert not {"I001", "D001", "D004"} & set(codes)
    with pytest.raises(urdftool.ConversionRefused) as refused:
        urdftool.to_mjcf(path)
    assert [d.code for d in refused.value.diagnostics] == ["C003"]
    assert "kinematic model" in refused.value.diagnostics[0].message
    assert "<mujoco" in urdftool.to_mjcf(path, repair_inertia=True)


def test_a_model_with_some_inertia_still_reports_each_missing_link() -> None:
    report = urdftool.check(RULES / "I011" / "good.urdf")
    assert [d.element for d in report.diagnostics if d.code == "I001"] == ["link[link_2]"]
