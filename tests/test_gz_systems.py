"""gz-sim systems (G301–G306) and ros2_control sensors (G107, G108) beyond their rule fixtures:
world plugins read once per world, the library and class tables, topic rewriting as gz-transport
does it, and the cases that must stay quiet (fragments, custom systems, classic plugins)."""

from __future__ import annotations

from pathlib import Path

import pytest

from urdftool.pipeline.check import CheckOptions, check_file
from urdftool.rules import gz_systems_known as known

WORLD = """<?xml version="1.0"?>
<sdf version="1.9">
  <world name="w">
    <plugin filename="gz-sim-sensors-system" name="gz::sim::systems::Sensors">
      <render_engine>Ogre2</render_engine>
    </plugin>
    <model name="a"><static>true</static><link name="l"/></model>
    <model name="b"><static>true</static><link name="l"/></model>
  </world>
</sdf>
"""


def _codes(path: Path, select: str = "G") -> list[tuple[str, int | None]]:
    options = CheckOptions(select=(select,))
    found = [d for r in check_file(str(path), options) for d in r.diagnostics]
    return [(d.code, d.location.line if d.location else None) for d in found]


def test_world_plugins_are_checked_once_per_world(tmp_path: Path) -> None:
    path = tmp_path / "w.sdf"
    path.write_text(WORLD)
    assert _codes(path, "G305") == [("G305", 5)]


def test_world_plugins_sit_on_the_first_model_only(tmp_path: Path) -> None:
    from urdftool.parse.packages import PackageResolver
    from urdftool.parse.sdf import read_sdf

    path = tmp_path / "w.sdf"
    path.write_text(WORLD)
    models = read_sdf(str(path), PackageResolver())
    assert [len(m.robot.world_plugins) for m in models if m.robot] == [1, 0]


@pytest.mark.parametrize(
    ("filename", "name", "stem", "cls"),
    [
        ("gz-sim-diff-drive-system", "gz::sim::systems::DiffDrive", "diff-drive", "DiffDrive"),
        ("libignition-gazebo-imu-system.so", "ignition::gazebo::systems::Imu", "imu", "Imu"),
        ("gz-sim8-log-system", "gz::sim::v8::systems::LogRecord", "log", "LogRecord"),
        ("libgazebo_ros_diff_drive.so", "diff_drive", None, None),
    ],
)
def test_systems_are_read_from_file_and_class_names(filename, name, stem, cls) -> None:
    from lxml import etree

    system = known.read_system(etree.fromstring(f'<plugin filename="{filename}" name="{name}"/>'))
    read = (system.stem, system.cls) if system is not None else (None, None)
    assert read == (stem, cls)


@pytest.mark.parametrize(
    ("topic", "used"),
    [
        ("cmd_vel", "cmd_vel"),
        ("/model/a/cmd_vel/", "/model/a/cmd_vel/"),
        ("~/cmd_vel", "/cmd_vel"),
        ("a b", "a_b"),
        ("/a//b", "/ab"),
        ("@", ""),
        ("/", ""),
    ],
)
def test_topics_are_rewritten_as_gz_transport_does(topic: str, used: str) -> None:
    assert known.valid_topic(topic) == used


def test_every_parameter_table_names_a_known_class() -> None:
    assert set(known.PARAMS) <= set(known.CLASSES)


def test_a_xacro_fragment_with_only_the_plugin_is_not_judged(tmp_path: Path) -> None:
    path = tmp_path / "robot.gazebo.urdf"
    path.write_text(
        '<robot name="r"><gazebo><plugin filename="gz_ros2_control-system" '
        'name="gz_ros2_control::GazeboSimROS2ControlPlugin"/></gazebo></robot>'
    )
    assert not _codes(path, "G306")


def test_classic_hardware_under_both_plugins_is_not_reported(tmp_path: Path) -> None:
    path = tmp_path / "r.urdf"
    path.write_text(
        """<robot name="r"><link name="a"/><link name="b"/>
  <joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint>
  <ros2_control name="S" type="system"><hardware><plugin>gazebo_ros2_control/GazeboSystem</plugin></hardware>
    <joint name="j"><command_interface name="velocity"/></joint></ros2_control>
  <gazebo><plugin filename="libgazebo_ros2_control.so" name="gazebo_ros2_control"/>
    <plugin filename="gz_ros2_control-system" name="gz_ros2_control::GazeboSimROS2ControlPlugin"/></gazebo>
</robot>"""
    )
    assert not _codes(path, "G306")


PACKAGES = Path(__file__).resolve().parents[1] / "fixtures" / "ros2_control"
DIFFBOT = "diffbot_control/urdf/diffbot.urdf.xacro"
DIFFBOT_MACRO = "diffbot_control/urdf/diffbot.ros2_control.xacro"


@pytest.mark.parametrize(
    ("old", "new", "code", "anchor"),
    [
        (
            "<plugin>gz_ros2_control/GazeboSimSystem</plugin>",
            "<plugin>gazebo_ros2_control/GazeboSystem</plugin>",
            "G306",
            "<hardware>",
        ),
        (
            "    </ros2_control>",
            '      <sensor name="imu"><state_interface name="orientation.x"/></sensor>\n    </ros2_control>',
            "G107",
            "    </ros2_control>",
        ),
    ],
    ids=["hardware-of-classic-gazebo", "sensor-without-gz-sensor"],
)
def test_breakage_in_a_ros2_control_macro_is_found_in_the_macro(
    tmp_path: Path, old: str, new: str, code: str, anchor: str
) -> None:
    import shutil

    root = tmp_path / "pkgs"
    shutil.copytree(PACKAGES, root)
    macro = root / DIFFBOT_MACRO
    text = macro.read_text()
    assert text.count(old) == 1
    macro.write_text(text.replace(old, new))
    line = text[: text.index(anchor)].count("\n") + 1
    options = CheckOptions(package_paths=(str(root),), select=(code,))
    found = [d for r in check_file(str(root / DIFFBOT), options) for d in r.diagnostics if d.code == code]
    assert [(Path(d.location.path).resolve(), d.location.line) for d in found] == [(macro.resolve(), line)]


def test_a_world_system_is_not_judged_against_the_first_models_links(tmp_path: Path) -> None:
    path = tmp_path / "w.sdf"
    path.write_text(
        """<sdf version="1.9"><world name="w">
  <plugin filename="gz-sim-kinetic-energy-monitor-system" name="gz::sim::systems::KineticEnergyMonitor">
    <link_name>rotor</link_name>
  </plugin>
  <model name="ground"><static>true</static><link name="plane"/></model>
</world></sdf>"""
    )
    assert not _codes(path, "G302")
