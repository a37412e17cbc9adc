"""ros2_control blocks and controllers YAML: two real-style packages check clean, and each
single-edit breakage of a joint name, interface name, limit or file reference is found at its line.

The packages under ``fixtures/ros2_control/`` are written in the style of ros2_control_demos'
example_1 (RRBot, an arm on gz_ros2_control) and example_2 (DiffBot, a diff-drive robot whose
ros2_control block comes from a xacro macro in another file).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from tests.conftest import FIXTURES
from urdftool.parse.controllers import load_located, read_controllers
from urdftool.pipeline.check import CheckOptions, check_file

PACKAGES = FIXTURES / "ros2_control"
ARM = "arm_control/urdf/arm.urdf.xacro"
DIFFBOT = "diffbot_control/urdf/diffbot.urdf.xacro"
ARM_YAML = "arm_control/config/arm_controllers.yaml"
DIFFBOT_YAML = "diffbot_control/config/diffbot_controllers.yaml"
DIFFBOT_MACRO = "diffbot_control/urdf/diffbot.ros2_control.xacro"


def _check(root: Path, model: str, **options: object) -> list:
    opts = CheckOptions(package_paths=(str(root),), **options)  # type: ignore[arg-type]
    return [d for r in check_file(str(root / model), opts) for d in r.diagnostics]


@pytest.mark.parametrize("model", [ARM, DIFFBOT])
def test_packages_check_clean(model: str) -> None:
    found = _check(PACKAGES, model)
    assert not found, "\n".join(f"{d.location}: {d.code} {d.message}" for d in found)


def test_controllers_yaml_is_read_from_plugin_parameters(tmp_path: Path) -> None:
    root = tmp_path / "pkgs"
    shutil.copytree(PACKAGES, root)
    yaml_file = root / ARM_YAML
    yaml_file.write_text(
        yaml_file.read_text().replace(
            "      - joint2\n    interface_name", "      - joint3\n    interface_name"
        )
    )
    found = _check(root, ARM)
    assert [d.code for d in found] == ["G201"]


#: (file edited, text, replacement, code expected, file where it is reported)
EDITS = [
    # joint names
    (ARM_YAML, "      - joint2\n    interface_name", "      - joint_2\n    interface_name", "G201", ARM_YAML),
    (ARM_YAML, "    joint: finger_left_joint", "    joint: finger_left", "G201", ARM_YAML),
    (DIFFBOT_YAML, '["right_wheel_joint"]', '["right_wheel"]', "G201", DIFFBOT_YAML),
    (ARM, '<joint name="joint2">\n      <command', '<joint name="joint_2">\n      <command', "G002", ARM),
    (
        DIFFBOT_MACRO,
        '<joint name="${prefix}left_wheel_joint">',
        '<joint name="${prefix}left_wheel">',
        "G002",
        DIFFBOT_MACRO,
    ),
    (
        ARM,
        '<joint name="finger_left_joint">\n      <command',
        '<joint name="joint1">\n      <command',
        "G104",
        ARM,
    ),
    (
        ARM,
        '<param name="mimic">finger_left_joint</param>',
        '<param name="mimic">finger_lft_joint</param>',
        "G105",
        ARM,
    ),
    # interface names
    (
        ARM,
        '<joint name="joint2">\n      <command_interface name="position">',
        '<joint name="joint2">\n      <command_interface name="postion">',
        "G102",
        ARM,
    ),
    (
        DIFFBOT_MACRO,
        '<state_interface name="velocity"/>\n      </joint>\n      <joint',
        '<state_interface name="velocty"/>\n      </joint>\n      <joint',
        "G102",
        DIFFBOT_MACRO,
    ),
    (ARM_YAML, "    interface_name: position", "    interface_name: velocity", "G202", ARM_YAML),
    (ARM_YAML, "      - position\n      - velocity", "      - position\n      - effort", "G202", ARM_YAML),
    (
        ARM_YAML,
        "type: joint_trajectory_controller/JointTrajectoryController",
        "type: joint_trajectory_controller/JointTrajectoryControler",
        "G203",
        ARM_YAML,
    ),
    # limits and geometry
    (
        ARM,
        '<param name="max">${upper}</param>\n      </command_interface>\n'
        '      <state_interface name="position">\n        <param name="initial_value">0.0</param>',
        '<param name="max">3.14</param>\n      </command_interface>\n'
        '      <state_interface name="position">\n        <param name="initial_value">0.0</param>',
        "G103",
        ARM,
    ),
    (ARM, '<param name="initial_value">0.5</param>', '<param name="initial_value">2.5</param>', "G103", ARM),
    (
        DIFFBOT_MACRO,
        '<param name="max">10</param>\n        </command_interface>\n        <state_interface '
        'name="position"/>\n        <state_interface name="velocity"/>\n      </joint>\n      <joint',
        '<param name="max">20</param>\n        </command_interface>\n        <state_interface '
        'name="position"/>\n        <state_interface name="velocity"/>\n      </joint>\n      <joint',
        "G103",
        DIFFBOT_MACRO,
    ),
    (DIFFBOT_YAML, "wheel_separation: 0.40", "wheel_separation: 0.50", "G004", DIFFBOT_YAML),
    (DIFFBOT_YAML, "wheel_radius: 0.1", "wheel_radius: 0.15", "G004", DIFFBOT_YAML),
    # file references and the YAML itself
    (
        ARM,
        "package://arm_control/config/arm_controllers.yaml",
        "package://arm_control/config/arm_controller.yaml",
        "G106",
        ARM,
    ),
    (
        DIFFBOT,
        "$(find diffbot_control)/config/diffbot_controllers.yaml",
        "$(find diffbot_control)/config/controllers.yaml",
        "G106",
        DIFFBOT,
    ),
    (ARM_YAML, "    joint: finger_left_joint", "    joint: [finger_left_joint", "G200", ARM_YAML),
    (DIFFBOT_MACRO, "<plugin>gz_ros2_control/GazeboSimSystem</plugin>", "", "G101", DIFFBOT_MACRO),
]


def _model_of(edited: str) -> str:
    return ARM if edited.startswith("arm_control") else DIFFBOT


@pytest.mark.parametrize(
    "edited,old,new,code,reported", EDITS, ids=[f"{e[3]}-{i}" for i, e in enumerate(EDITS)]
)
def test_single_edit_is_found_at_its_line(
    tmp_path: Path, edited: str, old: str, new: str, code: str, reported: str
) -> None:
    root = tmp_path / "pkgs"
    shutil.copytree(PACKAGES, root)
    target = root / edited
    text = target.read_text()
    assert text.count(old) == 1, f"edit anchor not unique in {edited}: {old!r}"
    edited_text = text.replace(old, new)
    target.write_text(edited_text)
    # the line of the edit: where the replacement starts differing from the original
    prefix = 0
    while prefix < min(len(old), len(new)) and old[prefix] == new[prefix]:
        prefix += 1
    start = text.index(old) + prefix
    if code in ("G101",):  # reported at the block
        start = text.index("<ros2_control")
    if code == "G200":  # the YAML parser reports where the flow sequence breaks: the next line or so
        start = text.index(old)
    line = text.count("\n", 0, start) + 1
    found = _check(root, _model_of(edited))
    mine = [d for d in found if d.code == code]
    assert mine, f"{code} not found; got " + ", ".join(f"{d.code}@{d.location}" for d in found)
    places = {(Path(d.location.path).resolve(), d.location.line) for d in mine}
    if code == "G200":
        assert any(p == (root / reported).resolve() and abs(n - line) <= 2 for p, n in places), places
    else:
        assert ((root / reported).resolve(), line) in places, (places, line)


def test_located_loader_records_lines_and_columns() -> None:
    value = load_located("a:\n  b: [x, y]\n  c: 1.5\n", "f.yaml")
    assert value is not None
    b = value.get("a").get("b")  # type: ignore[union-attr]
    assert [(v.text(), v.span.line, v.span.column) for v in b.items()] == [("x", 2, 7), ("y", 2, 10)]  # type: ignore[union-attr]
    assert value.get("a").get("c").number() == 1.5  # type: ignore[union-attr]


def test_namespaced_node_names(tmp_path: Path) -> None:
    path = tmp_path / "c.yaml"
    path.write_text(
        "/**/controller_manager:\n  ros__parameters:\n    arm:\n      type: x/Y\n"
        "/robot/arm:\n  ros__parameters:\n    joints: [a]\n"
    )
    config = read_controllers(str(path))
    assert [(c.name, c.type.text() if c.type else None) for c in config.controllers] == [("arm", "x/Y")]
    assert config.controllers[0].param("joints") is not None


def _read(tmp_path: Path, text: str) -> list[tuple[str, str, str | None, str | None, list[str]]]:
    path = tmp_path / "c.yaml"
    path.write_text(text)
    return [
        (c.namespace, c.name, c.type.text() if c.type else None,
         c.listed_type.text() if c.listed_type else None, sorted(c.params))
        for c in read_controllers(str(path)).controllers
    ]


def test_type_in_the_controllers_own_parameters(tmp_path: Path) -> None:
    # ros2_control PR 1502: the manager lists nothing; the controller's node holds its type
    assert _read(tmp_path, (
        "controller_manager:\n  ros__parameters:\n    update_rate: 100\n"
        "fwd:\n  ros__parameters:\n    type: velocity_controllers/JointGroupVelocityController\n"
        "    joints: [j1]\n"
    )) == [("", "fwd", "velocity_controllers/JointGroupVelocityController", None, ["joints", "type"])]


def test_both_layouts_own_type_wins_and_manager_type_is_kept(tmp_path: Path) -> None:
    assert _read(tmp_path, (
        "controller_manager:\n  ros__parameters:\n    arm:\n      type: a/B\n"
        "arm:\n  ros__parameters:\n    type: c/D\n"
    )) == [("", "arm", "c/D", "a/B", ["type"])]


def test_a_node_whose_type_names_no_plugin_is_no_controller(tmp_path: Path) -> None:
    # crazyswarm2's motion_capture_tracking: `type: optitrack`
    assert _read(tmp_path, "/mocap:\n  ros__parameters:\n    type: optitrack\n    joint: x\n") == []


def test_nested_keys_are_namespaces_and_wildcards_reach_every_node(tmp_path: Path) -> None:
    found = _read(tmp_path, (
        "/**:\n  ros__parameters:\n    use_sim_time: true\n"
        "/**/arm:\n  ros__parameters:\n    type: a/B\n    interface_name: position\n"
        "r1:\n  arm:\n    ros__parameters:\n      joints: [r1_j]\n"
        "/r2/arm:\n  ros__parameters:\n    joints: [r2_j]\n"
        "/r3/*:\n  ros__parameters:\n    state_publish_rate: 10.0\n"
    ))
    assert found == [
        ("/r1", "arm", "a/B", None, ["interface_name", "joints", "type", "use_sim_time"]),
        ("/r2", "arm", "a/B", None, ["interface_name", "joints", "type", "use_sim_time"]),
    ]


def test_a_file_for_several_robots_is_checked_in_the_models_namespace(tmp_path: Path) -> None:
    path = tmp_path / "c.yaml"
    path.write_text(
        "/**/fwd:\n  ros__parameters:\n    type: position_controllers/JointGroupPositionController\n"
        "/other/fwd:\n  ros__parameters:\n    joints: [other_joint1, other_joint2]\n"
        "/mine/fwd:\n  ros__parameters:\n    joints: [joint1, joint_2]\n"
    )
    found = _check(PACKAGES, ARM, controllers=str(path))
    assert [(d.code, d.location.line, d.data["joint"]) for d in found if d.location] == [
        ("G201", 9, "joint_2")
    ]


def test_controllers_option_checks_every_model(tmp_path: Path) -> None:
    path = tmp_path / "c.yaml"
    path.write_text(
        "controller_manager:\n  ros__parameters:\n    arm:\n"
        "      type: position_controllers/JointGroupPositionController\n"
        "arm:\n  ros__parameters:\n    joints: [joint1, wrist]\n"
    )
    found = _check(PACKAGES, ARM, controllers=str(path))
    assert [(d.code, d.location.line) for d in found if d.location] == [("G201", 7)]
