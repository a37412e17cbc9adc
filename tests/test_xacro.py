"""xacro without ROS: source mapping, arguments, package resolution, located errors,
and the seed corpus."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

import urdftool
from tests.conftest import SEEDS
from urdftool.cli import main
from urdftool.diagnostics import Diagnostic
from urdftool.parse.packages import PackageResolver
from urdftool.pipeline.check import CheckOptions, check_file
from urdftool.pipeline.discover import expand_paths

#: Each test names its package after its own tmp folder: the ancestor scan from one test's
#: folder reaches its sibling tests' folders, and must not find their packages.
PKG = "urdftool_test_wheel_description"

PACKAGE_XML = """<?xml version="1.0"?>
<package format="3">
  <name>{name}</name>
  <version>0.1.0</version>
  <description>wheels for urdftool's tests</description>
  <maintainer email="urdftool@example.org">urdftool</maintainer>
  <license>BSD-3-Clause</license>
</package>
"""

# Line numbers matter: the tests below point at lines of this file.
WHEEL_XACRO = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="wheel" params="side y">
    <link name="{link}">
      <inertial>
        <mass value="0.5"/>
        <inertia ixx="0.0013" ixy="0" ixz="0" iyy="0.0013" iyz="0" izz="0.0025"/>
      </inertial>
    </link>
    <joint name="${{side}}_wheel_joint" type="continuous">
      <parent link="base"/>
      <child link="{link}"/>
      <origin xyz="0 ${{y}} 0" rpy="0 0 0 0"/>
      <axis xyz="0 1 0"/>
    </joint>
  </xacro:macro>
</robot>
"""
WHEEL_LINK_LINE = 4
WHEEL_ORIGIN_LINE = 13

CART_XACRO = """<?xml version="1.0"?>
<robot name="cart" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="$(find {pkg})/urdf/wheel.xacro"/>
  <link name="base">
    <inertial>
      <mass value="2.0"/>
      <inertia ixx="0.0067" ixy="0" ixz="0" iyy="0.0067" iyz="0" izz="0.01"/>
    </inertial>
  </link>
  <xacro:wheel side="left" y="0.2"/>
  <xacro:wheel side="right" y="-0.2"/>
</robot>
"""


def make_package(root: Path, name: str, link: str = "${side}_wheel") -> Path:
    """A ROS package folder *root*/*name* with package.xml and urdf/wheel.xacro."""
    folder = root / name
    (folder / "urdf").mkdir(parents=True)
    (folder / "package.xml").write_text(PACKAGE_XML.format(name=name), encoding="utf-8")
    (folder / "urdf" / "wheel.xacro").write_text(WHEEL_XACRO.format(link=link), encoding="utf-8")
    return folder


def make_cart(folder: Path, pkg: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    cart = folder / "cart.urdf.xacro"
    cart.write_text(CART_XACRO.format(pkg=pkg), encoding="utf-8")
    return cart


def findings(path: Path, **options) -> list[Diagnostic]:
    return [d for r in check_file(str(path), CheckOptions(**options)) for d in r.diagnostics]


def codes(found: list[Diagnostic]) -> set[str]:
    return {d.code for d in found}


@pytest.fixture
def pkg(tmp_path: Path) -> str:
    return PKG + "_" + re.sub(r"\W", "_", tmp_path.name)


@pytest.fixture
def no_ros_env(monkeypatch: pytest.MonkeyPatch) -> None:
    for name in ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH"):
        monkeypatch.delenv(name, raising=False)


# -- source mapping ------------------------------------------------------------------


def test_finding_in_macro_body_of_included_file_points_there(
    tmp_path: Path, pkg: str, no_ros_env: None
) -> None:
    package = make_package(tmp_path / "ws" / "src" / "a" / "b", pkg)
    cart = make_cart(tmp_path / "robot", pkg)
    found = findings(cart, packages={pkg: str(package)})
    wheel = (package / "urdf" / "wheel.xacro").resolve()
    lengths = [d for d in found if d.name == "wrong-vector-length"]
    # one per macro call, both at the rpy attribute of the macro body
    assert lengths and all(Path(d.location.path).resolve() == wheel for d in lengths)
    assert {(d.location.line, d.location.column) for d in lengths} == {(WHEEL_ORIGIN_LINE, 30)}
    assert {d.element for d in lengths} == {
        "joint[left_wheel_joint]/origin",
        "joint[right_wheel_joint]/origin",
    }


def test_model_rule_finding_from_macro_points_at_macro_body(
    tmp_path: Path, pkg: str, no_ros_env: None
) -> None:
    """Both wheels get the same link name; duplicate-link-name points at the macro's <link>."""
    package = make_package(tmp_path / "pkgs", pkg, link="wheel")
    cart = make_cart(tmp_path / "robot", pkg)
    found = [
        d for d in findings(cart, packages={pkg: str(package)}) if d.name == "duplicate-link-name"
    ]
    assert len(found) == 1
    assert Path(found[0].location.path).resolve() == (package / "urdf" / "wheel.xacro").resolve()
    assert found[0].location.line == WHEEL_LINK_LINE


def test_element_written_in_the_top_file_points_at_the_top_file(
    tmp_path: Path, pkg: str, no_ros_env: None
) -> None:
    package = make_package(tmp_path / "pkgs", pkg)
    cart = make_cart(tmp_path / "robot", pkg)
    robot = urdftool.load(cart, packages={pkg: package})
    base = robot.link("base")
    assert base is not None and base.span is not None
    assert (Path(base.span.path).resolve(), base.span.line, base.span.column) == (
        cart.resolve(),
        4,
        3,
    )
    left = robot.link("left_wheel")
    assert left is not None and left.span is not None
    assert Path(left.span.path).name == "wheel.xacro" and left.span.line == WHEEL_LINK_LINE


# -- arguments ---------------------------------------------------------------------------

ARG_XACRO = """<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="prefix" default="left_"/>
  <link name="$(arg prefix)base">
    <inertial>
      <mass value="$(arg mass)"/>
      <inertia ixx="0.0067" ixy="0" ixz="0" iyy="0.0067" iyz="0" izz="0.01"/>
    </inertial>
  </link>
</robot>
"""


def test_xacro_args_reach_the_expansion(tmp_path: Path) -> None:
    path = tmp_path / "arm.urdf.xacro"
    path.write_text(ARG_XACRO, encoding="utf-8")
    robot = urdftool.load(path, xacro_args={"prefix": "right_", "mass": "2.5"})
    assert [link.name for link in robot.links] == ["right_base"]
    assert robot.links[0].inertial is not None and robot.links[0].inertial.mass == 2.5
    robot = urdftool.load(path, xacro_args={"mass": "1"})
    assert [link.name for link in robot.links] == ["left_base"]


def test_missing_xacro_arg_is_a_located_xacro_error(tmp_path: Path) -> None:
    path = tmp_path / "arm.urdf.xacro"
    path.write_text(ARG_XACRO, encoding="utf-8")
    found = [d for d in findings(path) if d.name == "xacro-error"]
    assert len(found) == 1 and "mass" in found[0].message
    assert Path(found[0].location.path) == path and found[0].location.line == 6


@pytest.mark.parametrize("flag", ["-a", "--xacro-arg"])
def test_cli_xacro_arg(tmp_path: Path, flag: str) -> None:
    path = tmp_path / "arm.urdf.xacro"
    path.write_text(ARG_XACRO, encoding="utf-8")
    result = CliRunner().invoke(
        main, ["info", "--format", "json", str(path), flag, "mass:=3", flag, "prefix:=r_"]
    )
    assert result.exit_code == 0, result.output
    summary = json.loads(result.output)
    assert summary["total_mass"] == 3.0 and summary["root"] == "r_base"
    bad = CliRunner().invoke(main, ["check", str(path), flag, "mass=3"])
    assert bad.exit_code == 2 and "NAME:=VALUE" in bad.output


# -- package resolution ------------------------------------------------------------------


def _layout(tmp_path: Path, pkg: str) -> tuple[Path, Path]:
    """The package four levels below tmp_path (out of reach of the ancestor scan from the
    robot's folder) and the robot in a sibling folder."""
    src = tmp_path / "ws" / "src" / "drivers"
    package = make_package(src, pkg)
    return package, make_cart(tmp_path / "robot", pkg)


def _resolved(found: list[Diagnostic]) -> bool:
    assert "xacro-error" not in {d.name for d in found}, found
    return "package-not-found" not in {d.name for d in found}


def test_unknown_package_is_reported_with_where_it_looked(
    tmp_path: Path, pkg: str, no_ros_env: None
) -> None:
    _, cart = _layout(tmp_path, pkg)
    (found,) = [d for d in findings(cart) if d.name == "package-not-found"]
    assert found.location is not None
    assert (Path(found.location.path).resolve(), found.location.line) == (cart.resolve(), 3)
    assert found.data["package"] == pkg and found.data["searched"]
    assert "--package" in (found.help or "")


def test_package_option(tmp_path: Path, pkg: str, no_ros_env: None) -> None:
    package, cart = _layout(tmp_path, pkg)
    assert _resolved(findings(cart, packages={pkg: str(package)}))


def test_package_path_option(tmp_path: Path, pkg: str, no_ros_env: None) -> None:
    _, cart = _layout(tmp_path, pkg)
    assert _resolved(findings(cart, package_paths=(str(tmp_path / "ws" / "src"),)))


def test_ros_package_path(
    tmp_path: Path, pkg: str, no_ros_env: None, monkeypatch: pytest.MonkeyPatch
) -> None:
    _, cart = _layout(tmp_path, pkg)
    monkeypatch.setenv("ROS_PACKAGE_PATH", f"/nonexistent:{tmp_path / 'ws' / 'src'}")
    assert _resolved(findings(cart))


def test_ament_prefix_path(
    tmp_path: Path, pkg: str, no_ros_env: None, monkeypatch: pytest.MonkeyPatch
) -> None:
    cart = make_cart(tmp_path / "robot", pkg)
    prefix = tmp_path / "install" / "prefix" / "here"
    make_package(prefix / "share", pkg)
    index = prefix / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True)
    (index / pkg).write_text("", encoding="utf-8")
    monkeypatch.setenv("AMENT_PREFIX_PATH", str(prefix))
    assert _resolved(findings(cart))


def test_ancestor_folders(tmp_path: Path, pkg: str, no_ros_env: None) -> None:
    """A robot inside a workspace finds a sibling package with no flag at all."""
    make_package(tmp_path / "ws" / "src", pkg)
    cart = make_cart(tmp_path / "ws" / "src" / "cart_description" / "urdf", pkg)
    assert _resolved(findings(cart))


def test_cli_package_flags(tmp_path: Path, pkg: str, no_ros_env: None) -> None:
    package, cart = _layout(tmp_path, pkg)
    runner = CliRunner()
    missing = runner.invoke(main, ["check", "--select", "X", str(cart)])
    assert missing.exit_code == 1 and "package-not-found" in missing.output
    for flags in (["--package", f"{pkg}={package}"], ["--package-path", str(tmp_path / "ws")]):
        result = runner.invoke(main, ["check", "--select", "X", *flags, str(cart)])
        assert result.exit_code == 0, result.output


def test_resolution_order(
    tmp_path: Path, pkg: str, no_ros_env: None, monkeypatch: pytest.MonkeyPatch
) -> None:
    """--package beats --package-path, which beats ROS_PACKAGE_PATH, which beats ancestors."""
    sources = {}
    for origin in ("option", "path", "env", "near"):
        sources[origin] = make_package(tmp_path / origin, pkg, link=f"{origin}_${{side}}_wheel")
    cart = make_cart(tmp_path / "near" / "robot", pkg)
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "env"))

    def wheel_links(**kw) -> set[str]:
        robot = urdftool.load(cart, **kw)
        return {link.name for link in robot.links} - {"base"}

    assert wheel_links(packages={pkg: sources["option"]}, package_paths=[tmp_path / "path"]) == {
        "option_left_wheel",
        "option_right_wheel",
    }
    assert wheel_links(package_paths=[tmp_path / "path"]) == {"path_left_wheel", "path_right_wheel"}
    assert wheel_links() == {"env_left_wheel", "env_right_wheel"}
    monkeypatch.delenv("ROS_PACKAGE_PATH")
    assert wheel_links() == {"near_left_wheel", "near_right_wheel"}


def test_package_uri_of_a_mesh_resolves_with_the_same_resolver(
    tmp_path: Path, pkg: str, no_ros_env: None
) -> None:
    package = make_package(tmp_path / "pkgs", pkg)
    (package / "meshes").mkdir()
    (package / "meshes" / "base.stl").write_bytes(b"solid base\nendsolid base\n")
    robot_file = tmp_path / "robot" / "base.urdf"
    robot_file.parent.mkdir()
    robot_file.write_text(
        f'<robot name="b"><link name="base"><visual><geometry>'
        f'<mesh filename="package://{pkg}/meshes/base.stl"/></geometry></visual></link></robot>',
        encoding="utf-8",
    )
    robot = urdftool.load(robot_file, packages={pkg: package})
    mesh = robot.links[0].visuals[0].geometry
    assert (
        mesh.resolved is not None
        and Path(mesh.resolved).resolve() == (package / "meshes" / "base.stl").resolve()
    )


# -- located xacro errors --------------------------------------------------------------


def test_undefined_property_in_included_macro_is_located_there(
    tmp_path: Path, pkg: str, no_ros_env: None
) -> None:
    package = make_package(tmp_path / "pkgs", pkg, link="${side}_wheel_${wheel_typo}")
    cart = make_cart(tmp_path / "robot", pkg)
    (found,) = [d for d in findings(cart, packages={pkg: str(package)}) if d.name == "xacro-error"]
    assert "wheel_typo" in found.message
    assert (
        Path(found.location.path).name == "wheel.xacro" and found.location.line == WHEEL_LINK_LINE
    )


def test_missing_include_is_located_at_the_include(tmp_path: Path) -> None:
    top = tmp_path / "cart.urdf.xacro"
    top.write_text(
        '<?xml version="1.0"?>\n<robot name="c" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <link name="base"/>\n  <xacro:include filename="sensors/lidar.xacro"/>\n</robot>\n',
        encoding="utf-8",
    )
    (found,) = [d for d in findings(top) if d.name == "xacro-error"]
    assert (Path(found.location.path), found.location.line) == (top, 4)
    assert "lidar.xacro" in found.message


def test_unknown_macro_is_located_at_the_call(tmp_path: Path) -> None:
    top = tmp_path / "cart.urdf.xacro"
    top.write_text(
        '<?xml version="1.0"?>\n<robot name="c" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <link name="base"/>\n\n  <xacro:caster side="left"/>\n</robot>\n',
        encoding="utf-8",
    )
    (found,) = [d for d in findings(top) if d.name == "xacro-error"]
    assert (Path(found.location.path), found.location.line) == (top, 5)



def test_property_without_the_xacro_prefix_is_named_in_the_help(tmp_path: Path) -> None:
    # reduced from Kinovarobotics/kinova-movo jaco_7dof.urdf.xacro (BSD-3): Kinetic's xacro read
    # <property> with a deprecation warning; Noetic and ROS 2 leave it as plain XML
    top = tmp_path / "arm.urdf.xacro"
    top.write_text(
        '<?xml version="1.0"?>\n<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <property name="shoulder_rpy" value="0 3.14 0"/>\n  <link name="base"/>\n'
        '  <link name="shoulder"/>\n  <joint name="j" type="fixed"><parent link="base"/>'
        '<child link="shoulder"/><origin rpy="${shoulder_rpy}"/></joint>\n</robot>\n',
        encoding="utf-8",
    )
    (found,) = [d for d in findings(top) if d.name == "xacro-error"]
    assert "name 'shoulder_rpy' is not defined" in found.message
    assert found.help == ("'shoulder_rpy' is written <property> (arm.urdf.xacro:3), without the xacro: "
                          "prefix, which xacro reads only before ROS Noetic: write <xacro:property>")


def test_property_defined_after_its_use_is_named_in_the_help(tmp_path: Path) -> None:
    # reduced from OrebroUniversity/yumi yumi.urdf.xacro (BSD-2): the whole-document xacro of
    # Indigo collected properties first; in-order xacro (Melodic and later) stops at the use
    top = tmp_path / "dual.urdf.xacro"
    top.write_text(
        '<?xml version="1.0"?>\n<robot name="dual" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <link name="${parent_link}"/>\n  <xacro:property name="parent_link" value="world"/>\n'
        "</robot>\n",
        encoding="utf-8",
    )
    (found,) = [d for d in findings(top) if d.name == "xacro-error"]
    assert (Path(found.location.path), found.location.line) == (top, 3)
    assert found.help is not None and found.help.startswith(
        "'parent_link' is defined at dual.urdf.xacro:4, after its use or in another macro's scope")


# -- the seed corpus ---------------------------------------------------------------------

KINECT = "uos_tools/uos_common_urdf/urdf/kinect.urdf.xacro"
MACRO_LIBRARIES = {
    f"uos_tools/uos_common_urdf/urdf/{name}"
    for name in (
        "imu.gazebo.urdf.xacro",
        "inras_radar.urdf.xacro",
        "sick_lms100.urdf.xacro",
        "sick_lms200.urdf.xacro",
        "sick_s300.urdf.xacro",
    )
}


def standalone_seed_xacros() -> list[str]:
    files = expand_paths([str(SEEDS)], PackageResolver.create())
    return sorted(str(Path(f).relative_to(SEEDS)) for f in files if f.endswith(".xacro"))


def test_sixteen_standalone_seed_xacros() -> None:
    found = standalone_seed_xacros()
    assert len(found) == 16, found
    assert KINECT in found and set(found) >= MACRO_LIBRARIES
    for fragment in (
        "learning_ros/mobot_urdf/urdf/casters.xacro",
        "uos_tools/uos_common_urdf/urdf/common.xacro",
        "gazebo_ros_demos/rrbot_description/urdf/materials.xacro",
    ):
        assert fragment not in found


@pytest.mark.parametrize("rel", standalone_seed_xacros())
def test_seed_xacro_expands_without_flags(rel: str, no_ros_env: None) -> None:
    found = findings(SEEDS / rel)
    failures = [d for d in found if d.name in ("xacro-error", "package-not-found")]
    if rel == KINECT:
        # name="${camera}" on <robot>, outside any macro: real xacro rejects it too.
        assert [(d.name, d.location.line) for d in failures] == [("xacro-error", 7)]
        assert "camera" in failures[0].message
        return
    assert not failures, [f"{d.location}: {d.message}" for d in failures]
    names = {d.name for d in found}
    if rel in MACRO_LIBRARIES:
        assert [d.name for d in found].count("macros-only") == 1
        assert not names & {"robot-name-missing", "empty-robot"}
    else:
        assert "macros-only" not in names
        assert urdftool.load(SEEDS / rel).links


def test_directory_check_of_the_seeds_skips_fragments(tmp_path: Path) -> None:
    # A copy without SDF worlds and meshes: this test is about which xacro files are read.
    copy = tmp_path / "seeds"
    shutil.copytree(
        SEEDS, copy, ignore=shutil.ignore_patterns("*.sdf", "*.world", "*.stl", "*.STL", "*.dae")
    )
    result = CliRunner().invoke(main, ["check", "--format", "json", "--select", "X,S", str(copy)])
    assert result.exit_code == 1, result.output  # kinect.urdf.xacro's xacro-error
    report = json.loads(result.output)
    checked = sorted(str(Path(f["path"]).relative_to(copy)) for f in report["files"])
    assert [p for p in checked if p.endswith(".xacro")] == standalone_seed_xacros()
    failures = [
        (f["path"], d["name"])
        for f in report["files"]
        for d in f["diagnostics"]
        if d["name"] in ("xacro-error", "package-not-found")
    ]
    assert failures == [(str(copy / KINECT), "xacro-error")]


def test_fragment_named_explicitly_is_checked(no_ros_env: None) -> None:
    """Fragments are skipped only in directory walks; named on the command line they are read."""
    files = expand_paths(
        [str(SEEDS / "learning_ros/mobot_urdf/urdf/casters.xacro")], PackageResolver.create()
    )
    assert len(files) == 1


@pytest.mark.parametrize("robot", ["burger", "waffle", "waffle_pi"])
def test_turtlebot3_urdf_files_are_xacro_and_are_expanded(robot: str, no_ros_env: None) -> None:
    """turtlebot3 ships xacro under .urdf names; they are read through xacro and said so."""
    path = SEEDS / "turtlebot3" / "turtlebot3_description" / "urdf" / f"turtlebot3_{robot}.urdf"
    found = findings(path)
    lines = path.read_text(encoding="utf-8").splitlines()
    first = next(n for n, text in enumerate(lines, 1) if text.strip().startswith("<xacro:arg"))
    assert [(d.name, d.location.line) for d in found if d.code.startswith(("X", "S0"))] == [
        ("xacro-in-urdf", first)
    ]
    loaded = urdftool.load(path)
    assert loaded.format == "xacro" and loaded.name == f"turtlebot3_{robot}"
    assert loaded.link("base_link") is not None


def test_a_urdf_with_a_stray_macro_call_is_checked_as_loaders_read_it(tmp_path: Path) -> None:
    """NASA's valkyrie_sim.urdf: a plain URDF with one macro call left from an old include. xacro
    fails on it; urdfdom, PyBullet and MuJoCo read the .urdf directly and skip the element. It is
    checked as they read it, the xacro failure a warning. With a ${…} in it, nothing reads it
    directly, and the failure stays an error."""
    body = ('<link name="base"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" '
            'iyy="0.01" iyz="0" izz="0.01"/></inertial></link>'
            '<joint name="j" type="fixed"><parent link="base"/><child link="arm"/></joint>'
            '<link name="arm"/>')
    stray = tmp_path / "stray.urdf"
    stray.write_text('<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
                     f'{body}<xacro:pelvis_sensors port="none"/></robot>')
    assert [link.name for link in urdftool.load(stray).links] == ["base", "arm"]
    report = urdftool.check(stray, select=["S", "X"])
    found = {(d.code, d.severity.value) for d in report.diagnostics}
    assert ("X001", "warning") in found and ("X006", "warning") in found
    assert not [d for d in report.diagnostics if d.severity.value == "error"]
    substituted = tmp_path / "substituted.urdf"
    substituted.write_text('<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
                           f'{body.replace("0.01", "${i}", 1)}<xacro:pelvis_sensors/></robot>')
    assert ("X001", "error") in {(d.code, d.severity.value) for d in urdftool.check(substituted).diagnostics}
