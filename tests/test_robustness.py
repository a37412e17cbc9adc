"""Hostile inputs end as findings or clear errors: numbers, special files, encodings,
deep chains, and outputs that would harm inputs (docs/robustness.md)."""

from __future__ import annotations

import contextlib
import dataclasses
import math
import os
import re
import tempfile
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

from tests.conftest import FIXTURES
from tests.scale_models import chain_urdf
from urdftool.api import check, load, to_mjcf
from urdftool.cli import main
from urdftool.export.write import OutputError
from urdftool.model.pose import Pose, matrix_to_quaternion, quaternion_to_matrix, rpy_to_matrix
from urdftool.parse.values import UNBOUNDED, parse_limit, parse_number
from urdftool.safe_files import file_limits, parse_limits, parse_size

ARM = (FIXTURES / "robots" / "two_link_arm.urdf").read_text()
HOSTILE = ["nan", "NaN", "inf", "-inf", "1e309", "-1e309", "1e308", "9" * 400]


def _floats(value: Any, seen: set[int] | None = None) -> list[float]:
    """Every float held by a model object, recursively (dataclasses, tuples, lists, dicts)."""
    seen = seen if seen is not None else set()
    if id(value) in seen:
        return []
    seen.add(id(value))
    if isinstance(value, float):
        return [value]
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return [f for field in dataclasses.fields(value) for f in _floats(getattr(value, field.name), seen)]
    if isinstance(value, (tuple, list)):
        return [f for item in value for f in _floats(item, seen)]
    if isinstance(value, dict):
        return [f for item in value.values() for f in _floats(item, seen)]
    return []


# -- numbers -------------------------------------------------------------------------


@pytest.mark.parametrize("text", HOSTILE)
def test_number_gate_refuses_non_finite_and_out_of_range(text: str) -> None:
    assert parse_number(text) is None


def test_number_gate_keeps_ordinary_numbers() -> None:
    assert parse_number(" -1.5e3 ") == -1500.0
    assert parse_number("1e50") == 1e50


#: (what the first match is replaced by, with {v} the hostile value)
EDITS = {
    "origin-rpy": (r'<origin xyz="0 0 0.25"/>', '<origin xyz="0 0 0.25" rpy="0 {v} 0"/>'),
    "origin-xyz": (r'<origin xyz="0 0 0.5"/>', '<origin xyz="0 {v} 0.5"/>'),
    "mass": (r'<mass value="[^"]*"', '<mass value="{v}"'),
    "inertia": (r'ixx="[^"]*"', 'ixx="{v}"'),
    "box": (r'size="[^"]*"', 'size="0.1 {v} 0.1"'),
    "limit": (r'upper="[^"]*"', 'upper="{v}"'),
}


@pytest.mark.parametrize("edit", sorted(EDITS))
@pytest.mark.parametrize("value", ["nan", "inf", "1e309", "-1e309", "1e300"])
def test_hostile_numbers_are_invalid_number_at_the_attribute(tmp_path: Path, edit: str, value: str) -> None:
    pattern, replacement = EDITS[edit]
    text, count = re.subn(pattern, replacement.replace("{v}", value), ARM, count=1)
    assert count == 1, pattern
    path = tmp_path / "arm.urdf"
    path.write_text(text)
    report = check(path, ignore=["D"])
    codes = [d.code for d in report.diagnostics]
    assert "S000" not in codes
    invalid = [d for d in report.diagnostics if d.name == "invalid-number"]
    assert invalid, codes
    assert invalid[0].location is not None and invalid[0].location.line is not None
    robot = load(path)
    assert all(math.isfinite(f) for f in _floats(robot.links) + _floats(robot.joints))


def test_sdf_infinite_limits_are_unbounded(tmp_path: Path) -> None:
    sdf = """<?xml version="1.0"?>
<sdf version="1.7"><model name="m">
  <link name="a"/><link name="b"/>
  <joint name="j" type="revolute"><parent>a</parent><child>b</child>
    <axis><xyz>0 0 1</xyz><limit><lower>-inf</lower><upper>inf</upper>
    <effort>1e400</effort><velocity>inf</velocity></limit></axis></joint>
</model></sdf>
"""
    path = tmp_path / "m.sdf"
    path.write_text(sdf)
    robot = load(path)
    joint = robot.joint("j")
    assert joint is not None and joint.limit is not None
    assert (joint.limit.lower, joint.limit.upper, joint.limit.effort, joint.limit.velocity) == (None,) * 4
    assert joint.type.value == "continuous"
    names = [d.name for d in check(path, ignore=["D"]).diagnostics]
    assert "invalid-number" not in names and "internal-error" not in names
    assert parse_limit("-inf") is UNBOUNDED and parse_limit("1e400") is UNBOUNDED and parse_limit("x") is None


def test_pose_math_is_total() -> None:
    assert all(math.isfinite(v) for v in rpy_to_matrix((math.inf, math.nan, 1e309)).ravel())
    assert all(math.isfinite(v) for v in quaternion_to_matrix((math.nan, 0.0, 0.0, 0.0)).ravel())
    assert matrix_to_quaternion(rpy_to_matrix((0.0, 0.0, 0.0)) * math.nan) == (1.0, 0.0, 0.0, 0.0)
    pose = Pose((1e308, 1e308, 0.0), (0.0, 0.0, 1.0))
    composed = pose.compose(pose)
    assert all(math.isfinite(v) for v in (*composed.xyz, *composed.rpy))
    assert all(math.isfinite(v) for v in (*pose.inverse().xyz, *pose.inverse().rpy))


# -- special files, size caps --------------------------------------------------------


def _run(*args: str) -> Any:
    return CliRunner().invoke(main, list(args))


def test_device_as_input_is_a_clear_error() -> None:
    result = _run("check", "/dev/zero")
    assert result.exit_code == 2
    assert "character device" in result.output


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs")
def test_fifo_as_input_is_a_clear_error(tmp_path: Path) -> None:
    fifo = tmp_path / "robot.urdf"
    os.mkfifo(fifo)
    result = _run("check", str(fifo))
    assert result.exit_code == 2
    assert "FIFO" in result.output


@pytest.mark.parametrize("special", ["/dev/zero", "fifo"])
def test_special_file_as_mesh_is_located(tmp_path: Path, special: str) -> None:
    if special == "fifo":
        os.mkfifo(tmp_path / "part.stl")
        special = str(tmp_path / "part.stl")
    path = tmp_path / "arm.urdf"
    path.write_text(re.sub(r'<box size="[^"]*"/>', f'<mesh filename="{special}"/>', ARM, count=1))
    report = check(path, ignore=["D"])
    found = [d for d in report.diagnostics if "not a regular file" in d.message]
    assert found and found[0].location is not None and found[0].location.line is not None
    text = to_mjcf(path)  # the mesh is left out, nothing hangs
    assert "<mujoco" in text


def test_special_file_as_xacro_include_is_located(tmp_path: Path) -> None:
    path = tmp_path / "arm.urdf.xacro"
    path.write_text(
        '<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:include filename="/dev/zero"/>\n  <link name="base"/>\n</robot>\n'
    )
    report = check(path, ignore=["D"])
    errors = [d for d in report.diagnostics if d.name == "xacro-error"]
    assert errors and "character device" in errors[0].message
    assert errors[0].location is not None and errors[0].location.path == str(path)


def test_size_caps_per_kind(tmp_path: Path) -> None:
    path = tmp_path / "arm.urdf"
    path.write_text(ARM)
    with file_limits({"model": 100}):
        report = check(path)
    assert [d.name for d in report.diagnostics] == ["xml-syntax"]
    assert "--max-file-size model=" in (report.diagnostics[0].help or "")
    assert parse_size("64M") == 64 * 1024 * 1024 and parse_size("1G") == 1 << 30
    assert parse_limits(["mesh=1k", "2k"]) == {"model": 2048, "include": 2048, "mesh": 2048}
    assert parse_limits(["mesh=1k"]) == {"mesh": 1024}
    with pytest.raises(ValueError):
        parse_limits(["texture=1M"])


def test_max_file_size_flag(tmp_path: Path) -> None:
    path = tmp_path / "arm.urdf"
    path.write_text(ARM)
    small = _run("check", "--no-dynamics", "--max-file-size", "model=100", str(path))
    assert small.exit_code == 1 and "cap" in small.output
    assert _run("check", "--no-dynamics", "--max-file-size", "1M", str(path)).exit_code == 0
    assert _run("check", "--max-file-size", "lots", str(path)).exit_code == 2


# -- encodings -----------------------------------------------------------------------

BOMB = """<!DOCTYPE robot [
  <!ENTITY a "aaaaaaaaaa">
  <!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">
  <!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;">
]>
<robot name="&c;"><link name="base"/></robot>
"""


@pytest.mark.parametrize("encoding", ["utf-16-be", "utf-16-le", "utf-16", "utf-32-be", "utf-32-le", "utf-32"])
@pytest.mark.parametrize("suffix", [".urdf", ".urdf.xacro"])
def test_entity_guard_sees_through_encodings(tmp_path: Path, encoding: str, suffix: str) -> None:
    path = tmp_path / f"bomb{suffix}"
    path.write_bytes(BOMB.encode(encoding))
    report = check(path)
    assert [d.name for d in report.diagnostics] == ["xml-syntax"]
    assert "entity" in report.diagnostics[0].message


@pytest.mark.parametrize("encoding", ["utf-16-be", "utf-16", "utf-32-le"])
def test_utf16_and_utf32_descriptions_load(tmp_path: Path, encoding: str) -> None:
    path = tmp_path / "arm.urdf"
    path.write_bytes(ARM.encode(encoding))
    assert len(load(path).links) == len(load(FIXTURES / "robots" / "two_link_arm.urdf").links)


def test_declared_encoding_that_hides_markup_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "arm.urdf"
    path.write_bytes(b'<?xml version="1.0" encoding="UTF-7"?>\n' + BOMB.replace("<", "+ADw-").encode("ascii"))
    report = check(path)
    assert [d.name for d in report.diagnostics] == ["xml-syntax"]
    assert "entity" in report.diagnostics[0].message


# -- deep chains ---------------------------------------------------------------------


@pytest.fixture(scope="module", params=["fixed", "revolute"])
def deep_chain(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("deep") / f"chain_{request.param}.urdf"
    path.write_text(chain_urdf(5000, request.param))
    return path


@pytest.mark.slow
def test_deep_chain_checks(deep_chain: Path) -> None:
    result = _run("check", "--no-dynamics", "--format", "json", str(deep_chain))
    assert result.exit_code == 0, result.output[-2000:]
    assert '"S000"' not in result.output


@pytest.mark.slow
@pytest.mark.parametrize("suffix", [".xml", ".urdf", ".sdf", ".dot"])
def test_deep_chain_converts(deep_chain: Path, tmp_path: Path, suffix: str) -> None:
    out = tmp_path / f"out{suffix}"
    result = _run("convert", str(deep_chain), "-o", str(out))
    assert result.exit_code == 0, result.output[-2000:]
    assert out.stat().st_size > 0


def test_deep_chain_forward_kinematics(deep_chain: Path) -> None:
    from urdftool.model import KinematicTree

    robot = load(deep_chain)
    poses = KinematicTree.of(robot).forward_kinematics()
    assert len(poses) == 5000


# -- outputs never harm inputs -------------------------------------------------------


def _arm_with_mesh(tmp_path: Path) -> tuple[Path, Path]:
    mesh = tmp_path / "part.stl"
    mesh.write_bytes((FIXTURES / "rules" / "C005" / "triangle.stl").read_bytes())
    path = tmp_path / "arm.urdf"
    path.write_text(re.sub(r'<box size="[^"]*"/>', '<mesh filename="part.stl"/>', ARM, count=1))
    return path, mesh


@pytest.mark.parametrize("which", ["model", "mesh", "include"])
def test_output_over_an_input_is_refused(tmp_path: Path, which: str) -> None:
    path, mesh = _arm_with_mesh(tmp_path)
    if which == "include":
        body = tmp_path / "body.xacro"
        body.write_text('<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="extra"/></robot>\n')
        top = tmp_path / "top.urdf.xacro"
        top.write_text('<robot name="t" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
                       '<xacro:include filename="body.xacro"/><link name="base"/></robot>\n')
        path, target = top, body
    else:
        target = path if which == "model" else mesh
    before = target.read_bytes()
    result = _run("convert", str(path), "-o", str(target), "--to", "mjcf")
    assert result.exit_code == 2
    assert "refusing" in result.output
    assert target.read_bytes() == before
    with pytest.raises(OutputError):
        to_mjcf(path, target)
    assert target.read_bytes() == before


@pytest.mark.parametrize("command", ["convert", "graph"])
def test_output_to_a_device_is_refused(tmp_path: Path, command: str) -> None:
    path = tmp_path / "arm.urdf"
    path.write_text(ARM)
    fifo = tmp_path / "out.dot"
    os.mkfifo(fifo)
    device = tmp_path / "full.dot"  # a name the graph command accepts, pointing at /dev/full
    device.symlink_to("/dev/full")
    for out in ("/dev/full" if command == "convert" else str(device), str(fifo)):
        args = [command, str(path), "-o", out] + (["--to", "mjcf"] if command == "convert" else [])
        result = _run(*args)
        assert result.exit_code == 2, result.output
        assert "not a regular file" in result.output
    assert Path("/dev/full").is_char_device()
    assert fifo.is_fifo()


def test_fuzz_regressions_check_without_an_exception() -> None:
    """Every input a fuzz run crashed on (fixtures/fuzz-regressions/) now gets a report, and
    converts or is refused with a reason, as the fuzz harness asks."""
    import urdftool
    from tests.conftest import FIXTURES
    from urdftool.api import ConversionRefused, LoadError

    cases = sorted((FIXTURES / "fuzz-regressions").iterdir())
    assert cases
    for case in cases:
        report = urdftool.check(case)
        assert not [d for d in report.diagnostics if d.code == "S000"], case
        with tempfile.TemporaryDirectory() as out:
            for convert, name in ((urdftool.to_mjcf, "out.xml"), (urdftool.to_urdf, "out.urdf")):
                # refused with a reason is what the harness accepts; anything else fails the test
                with contextlib.suppress(ConversionRefused, LoadError):
                    convert(case, str(Path(out) / name))


def test_json_and_sarif_reports_hold_no_infinity() -> None:
    """JSON has no infinity or NaN: a non-finite number in a finding's data is written as null,
    never as ``Infinity``, which strict readers (jq, CI dashboards) refuse."""
    import json

    from urdftool.diagnostics import Diagnostic, FileReport, Report, Severity
    from urdftool.render.json import finite, render_json
    from urdftool.render.sarif import render_sarif
    from urdftool.source import Span

    assert finite({"a": [1.0, float("inf"), {"b": float("nan")}], "c": "inf"}) == {
        "a": [1.0, None, {"b": None}], "c": "inf"}
    finding = Diagnostic(code="I007", name="implausible-density", severity=Severity.WARNING,
                         message="m", location=Span("robot.urdf", 1, 1),
                         data={"density": float("inf"), "volume": 5e-324})
    report = Report((FileReport("robot.urdf", "urdf", "r", (finding,)),))

    def refuse(constant: str) -> None:
        raise ValueError(constant)

    for text in (render_json(report), render_sarif(report)):
        json.loads(text, parse_constant=refuse)


def test_many_unclosed_comments_are_read_in_bounded_time() -> None:
    """A text of unclosed comments holding `--` is refused, as libxml2 refuses it, without the
    mending of `--` going quadratic: a lazy match from each "<!--" to a "-->" that never comes
    took 2.7 s for 64 kB, and 45 s for the 256 kB here; one pass takes milliseconds. The bound
    is a guard against a hang (as the fuzz harness's budget is), not a speed goal."""
    import time

    from urdftool.parse.xmlio import parse_bytes

    data = b"<robot name='r'>" + b"<!-- -- " * 32_768 + b"</robot>"
    start = time.process_time()
    document, problems = parse_bytes(data, "r.urdf")
    assert document is None and [d.code for d in problems] == ["S001"]
    assert time.process_time() - start < 5.0


def test_a_vanishing_gearbox_ratio_is_reported_not_a_division_by_zero(tmp_path: Path) -> None:
    """An SDF gearbox ratio of 1e-200 squared underflows to 0; the MJCF export divided by it.
    Now the closure is reported as left open, like any gearbox it cannot write."""
    from urdftool.api import load
    from urdftool.export import ExportOptions
    from urdftool.export.mjcf import export

    sdf = tmp_path / "geared.sdf"
    inertial = ("<inertial><mass>1</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz>"
                "</inertia></inertial>")
    sdf.write_text(
        '<sdf version="1.7"><model name="g">'
        f'<link name="base">{inertial}</link><link name="rotor">{inertial}</link>'
        f'<link name="out">{inertial}</link>'
        '<joint name="rotor_joint" type="revolute"><parent>base</parent><child>rotor</child>'
        "<axis><xyz>0 0 1</xyz></axis></joint>"
        '<joint name="out_joint" type="revolute"><parent>base</parent><child>out</child>'
        "<axis><xyz>0 0 1</xyz></axis></joint>"
        '<joint name="gear" type="gearbox"><parent>rotor</parent><child>out</child>'
        "<gearbox_reference_body>base</gearbox_reference_body><gearbox_ratio>1e-200</gearbox_ratio>"
        "<axis><xyz>0 0 1</xyz></axis><axis2><xyz>0 0 1</xyz></axis2></joint>"
        "</model></sdf>")
    robot = load(sdf)
    assert any(c.joint.type.value == "gearbox" for c in robot.loop_closures)
    conversion = export(robot, tmp_path / "g.xml", ExportOptions())
    assert any("gearbox" in d.message and "open" in d.message for d in conversion.diagnostics)
