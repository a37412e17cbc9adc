"""The Python API: urdftool.load and urdftool.check; typed results, exceptions, no printing."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

import urdftool
from tests.conftest import ERD, FIXTURES, SEEDS
from urdftool import Diagnostic, LoadError, Report, Robot, Severity
from urdftool.cli import main

ARM = FIXTURES / "robots" / "two_link_arm.urdf"
NUMBERS = FIXTURES / "rules" / "S005" / "bad.urdf"
X002 = FIXTURES / "rules" / "X002"


@pytest.fixture(autouse=True)
def _nothing_printed(capsys: pytest.CaptureFixture[str]):
    """No API call may write to stdout or stderr (xacro's own chatter included)."""
    yield
    out, err = capsys.readouterr()
    assert out == "" and err == "", (out, err)


# -- load ---------------------------------------------------------------------------------


def test_load_urdf() -> None:
    robot = urdftool.load(ARM)
    assert isinstance(robot, Robot)
    assert robot.name == "two_link_arm" and robot.format == "urdf"
    assert [link.name for link in robot.links] == ["base", "upper_arm", "forearm"]
    assert robot.joint("elbow") is not None and robot.joint("elbow").limit.upper == 2.0
    assert robot.span is not None and robot.span.line == 3
    assert robot.diagnostics == ()


def test_load_accepts_str_and_pathlike() -> None:
    assert urdftool.load(str(ARM)) == urdftool.load(ARM)


def test_load_keeps_reader_findings_on_the_robot() -> None:
    robot = urdftool.load(NUMBERS)
    assert {d.code for d in robot.diagnostics} == {"S005"}
    # the malformed mass is read as unwritten
    assert robot.link("base").inertial.mass == 0.0


def test_load_xacro_with_args_and_packages(tmp_path: Path) -> None:
    # A package name of this test's own, four levels down: no ancestor scan finds it.
    name = "urdftool_api_test_" + tmp_path.name.replace("-", "_")
    package = tmp_path / "src" / "a" / "b" / name
    package.mkdir(parents=True)
    (package / "package.xml").write_text(
        f"<package><name>{name}</name></package>", encoding="utf-8"
    )
    shutil.copy(X002 / "wheel.xacro", package / "wheel.xacro")
    top = tmp_path / "cart.urdf.xacro"
    top.write_text(
        '<?xml version="1.0"?>\n<robot name="cart" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:arg name="side" default="left"/>\n'
        f'  <xacro:include filename="$(find {name})/wheel.xacro"/>\n'
        '  <link name="base"/>\n'
        '  <xacro:wheel side="$(arg side)" y="0.2"/>\n</robot>\n',
        encoding="utf-8",
    )
    robot = urdftool.load(top, xacro_args={"side": "right"}, packages={name: package})
    assert robot.format == "xacro"
    assert {link.name for link in robot.links} == {"base", "right_wheel"}
    wheel = robot.link("right_wheel")
    assert wheel.span is not None and wheel.span.path == str(package / "wheel.xacro")
    assert urdftool.load(top, package_paths=[tmp_path / "src"]).link("left_wheel") is not None
    with pytest.raises(LoadError) as failure:
        urdftool.load(top)
    assert [d.name for d in failure.value.diagnostics] == ["package-not-found"]


def test_load_example_robot_data_package_uri() -> None:
    assert ERD is not None
    robot = urdftool.load(ERD / "ur_description" / "urdf" / "ur5_robot.urdf")
    meshes = [
        v.geometry for link in robot.links for v in link.visuals if hasattr(v.geometry, "resolved")
    ]
    assert meshes and all(m.resolved and Path(m.resolved).is_file() for m in meshes)


@pytest.mark.parametrize(
    "content, code",
    [(b"\x00\x01\x02 garbage", "S001"), (b"<mujoco model='m'/>", "S002"), (b"<robot", "S001")],
    ids=["binary", "not-a-robot", "truncated"],
)
def test_load_garbage_raises_load_error_with_diagnostics(
    tmp_path: Path, content: bytes, code: str
) -> None:
    path = tmp_path / "broken.urdf"
    path.write_bytes(content)
    with pytest.raises(LoadError) as failure:
        urdftool.load(path)
    found = failure.value.diagnostics
    assert found and all(isinstance(d, Diagnostic) for d in found)
    assert found[0].code == code and found[0].location.path == str(path)
    assert str(path) in str(failure.value)


def test_load_missing_file_raises_file_not_found(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError):
        urdftool.load(tmp_path / "nowhere.urdf")


def test_load_unknown_format_raises_value_error(tmp_path: Path) -> None:
    path = tmp_path / "notes.txt"
    path.write_text("hello", encoding="utf-8")
    with pytest.raises(ValueError, match="unknown format"):
        urdftool.load(path)


def test_load_macro_library_is_a_robot_without_links() -> None:
    robot = urdftool.load(SEEDS / "uos_tools/uos_common_urdf/urdf/sick_s300.urdf.xacro")
    assert robot.links == () and sorted(d.name for d in robot.diagnostics) == [
        "include-not-at-path",
        "macros-only",
    ]


# -- check --------------------------------------------------------------------------------


def test_check_path() -> None:
    report = urdftool.check(NUMBERS, select=["S"])
    assert isinstance(report, Report)
    assert not report.ok
    assert len(report.errors) == 4 and all(d.severity is Severity.ERROR for d in report.errors)
    assert report.diagnostics == report.files[0].diagnostics
    assert report.files[0].robot == "two_link_arm"


def test_check_clean_robot_is_ok() -> None:
    report = urdftool.check(ARM, select=["S", "X"])
    assert report.ok and report.diagnostics == ()


def test_check_loaded_robot_gives_the_same_findings_as_the_path() -> None:
    robot = urdftool.load(NUMBERS)
    by_robot = urdftool.check(robot, select=["S"])
    by_path = urdftool.check(NUMBERS, select=["S"])
    assert by_robot.diagnostics == by_path.diagnostics


@pytest.mark.parametrize("ignore", [["S005"], ["invalid-number"], ["S00"], ["S"]])
def test_check_ignore(ignore: list[str]) -> None:
    report = urdftool.check(NUMBERS, select=["S"], ignore=ignore)
    assert report.ok and not report.diagnostics


def test_check_select_by_name() -> None:
    report = urdftool.check(
        FIXTURES / "rules" / "S011" / "bad.urdf", select=["duplicate-link-name"]
    )
    assert [d.code for d in report.diagnostics] == ["S011"]


def test_check_model_rules_on_a_robot() -> None:
    robot = urdftool.load(FIXTURES / "rules" / "S019" / "bad.urdf")
    report = urdftool.check(robot, select=["self-loop-joint"])
    (finding,) = report.diagnostics
    assert finding.element == "joint[base_mount]" and finding.location.line == 22


def test_check_xacro_options(tmp_path: Path) -> None:
    report = urdftool.check(
        X002 / "good.urdf.xacro", select=["X"], packages={"x002_cart_description": X002}
    )
    assert report.ok


def test_check_unknown_selector_raises_value_error() -> None:
    with pytest.raises(ValueError, match="matches no rule"):
        urdftool.check(ARM, select=["nonsense-rule"])


def test_check_missing_file_raises_file_not_found(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError):
        urdftool.check(tmp_path / "nowhere.urdf")


def test_check_unreadable_xml_is_a_report_not_an_exception(tmp_path: Path) -> None:
    path = tmp_path / "empty.urdf"
    path.write_bytes(b"")
    report = urdftool.check(path)
    assert not report.ok and [d.name for d in report.errors] == ["xml-syntax"]
    assert report.files[0].robot is None


def test_xacro_warnings_are_findings_not_stderr() -> None:
    report = urdftool.check(FIXTURES / "rules" / "X004" / "bad.urdf.xacro", select=["X004"])
    assert [d.location.line for d in report.diagnostics] == [4, 5]


def test_the_simulate_function_is_not_shadowed_by_a_subpackage() -> None:
    import urdftool.pipeline.simulate

    assert callable(urdftool.simulate) and callable(urdftool.check_many)


def test_public_names() -> None:
    for name in ("load", "check", "Report", "Diagnostic", "LoadError", "Robot", "Severity", "Span"):
        assert name in urdftool.__all__, name
    assert (Path(urdftool.__file__).parent / "py.typed").exists()


COLLADA = FIXTURES / "newuser" / "collada_lidar.urdf"


def test_to_mjcf_without_out_keeps_converted_meshes_where_the_text_points(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The README's ``urdftool.to_mjcf(robot)`` on a robot with a COLLADA mesh: the text loads in
    MuJoCo from a string, anywhere (new-user report of 2026-11-26, problem 6)."""
    import mujoco
    from lxml import etree

    monkeypatch.setenv("URDFTOOL_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.chdir(tmp_path)
    text = urdftool.to_mjcf(urdftool.load(COLLADA))
    files = [m.get("file") for m in etree.fromstring(text.encode()).iter("mesh")]
    assert files and all(Path(f).is_absolute() and Path(f).is_file() for f in files)
    assert all(str(tmp_path / "cache") in f for f in files)
    model = mujoco.MjModel.from_xml_string(text)
    assert model.nmesh == len(files)
    assert not (tmp_path / "assets").exists()  # nothing written in the working directory


def test_pybullet_urdf_without_out_loads_from_anywhere(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import pybullet

    monkeypatch.setenv("URDFTOOL_CACHE_DIR", str(tmp_path / "cache"))
    text = urdftool.to_urdf(COLLADA, flavor="pybullet")
    elsewhere = tmp_path / "elsewhere" / "lidar.urdf"
    elsewhere.parent.mkdir()
    elsewhere.write_text(text)
    client = pybullet.connect(pybullet.DIRECT)
    try:
        body = pybullet.loadURDF(str(elsewhere), physicsClientId=client)
        shapes = pybullet.getVisualShapeData(body, physicsClientId=client)
        meshes = [s[4].decode() for s in shapes if s[2] == pybullet.GEOM_MESH]
        assert meshes and all(Path(m).is_file() and str(tmp_path / "cache") in m for m in meshes)
    finally:
        pybullet.disconnect(client)


def test_to_mjcf_without_out_and_without_a_cache_refuses_clearly(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("URDFTOOL_NO_CACHE", "1")
    with pytest.raises(urdftool.ConversionRefused, match="pass out=PATH"):
        urdftool.to_mjcf(COLLADA)
    # a robot whose meshes MuJoCo reads as they are needs no folder
    assert "<mujoco" in urdftool.to_mjcf(ARM)


def test_a_world_of_several_models_asks_which_one(tmp_path: Path) -> None:
    """A world read with no model named is an error that lists its models, in the API and in every
    command that works on one model (new-user report of 2026-11-26: collisions, diff and the API
    took the first model without saying so)."""
    world = FIXTURES / "robots" / "sdf" / "static_world.world"
    asks = r"holds 2 models \(shelf, cart\): choose one with --model"
    with pytest.raises(urdftool.LoadError, match=asks) as asked:
        urdftool.load(world)
    assert asked.value.models == ("shelf", "cart")  # a script picks one without reading the message
    assert urdftool.load(world, model=asked.value.models[1]).name == "cart"
    with pytest.raises(urdftool.LoadError, match="has no model named 'crate'") as unknown:
        urdftool.load(world, model="crate")
    assert unknown.value.models == ("shelf", "cart")
    for command in (["collisions", str(world), "-o", str(tmp_path / "w.srdf")],
                    ["diff", str(world), str(world)]):
        result = CliRunner().invoke(main, command)
        assert result.exit_code == 2, (command, result.output)
        assert "holds 2 models (shelf, cart)" in result.output
