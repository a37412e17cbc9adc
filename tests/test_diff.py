"""urdftool diff: what an edit did to a real robot, renames, reformatting, Markdown, --fail-on."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest
from click.testing import CliRunner
from lxml import etree

import urdftool
from tests.conftest import ERD, ROOT
from urdftool.cli import main
from urdftool.pipeline.diff import FailOnError, parse_fail_on, tripped

RRBOT = ROOT / "fixtures" / "seeds" / "gazebo_ros_demos" / "rrbot_description"
PACKAGES = {"rrbot_description": RRBOT}
PANDA = ERD / "panda_description" / "urdf" / "panda.urdf" if ERD else None


def _edited_rrbot(tmp_path: Path) -> Path:
    text = (RRBOT / "urdf" / "rrbot.xacro").read_text()
    text = text.replace('name="height2" value="1"', 'name="height2" value="1.2"')
    text = text.replace('name="mass" value="1"', 'name="mass" value="1.5"')
    new = tmp_path / "rrbot.xacro"
    new.write_text(text)
    return new


def test_a_changed_xacro_property_moves_links_and_masses_exactly(tmp_path: Path) -> None:
    new = _edited_rrbot(tmp_path)
    result = urdftool.diff(RRBOT / "urdf" / "rrbot.xacro", new, packages=PACKAGES, findings=False)
    moved = {c.subject: c for c in result.of_kind("pose") if c.field == "position"}
    # joint2 sits at height2 - 2·axel_offset: 0.9 m → 1.1 m, so link3 moves 200 mm
    assert moved["link3"].size == pytest.approx(200.0, abs=1e-9)
    assert moved["link3"].old[2] == pytest.approx(1.95 + 0.9, abs=1e-9)
    assert moved["link3"].new[2] == pytest.approx(1.95 + 1.1, abs=1e-9)
    assert "link1" not in moved and "link2" not in moved
    masses = {c.subject: c for c in result.of_kind("mass")}
    assert masses["link1"].old == 1.0 and masses["link1"].new == pytest.approx(1.5, abs=1e-12)
    assert masses["link2"].size == pytest.approx(50.0, abs=1e-9)
    total = result.of_kind("total-mass")[0]
    assert total.new - total.old == pytest.approx(1.5, abs=1e-9)
    inertia = {c.subject: c for c in result.of_kind("inertia")}
    # link2's box grew to 1.2 m and 1.5 kg: ixx = m/12 (w² + h²)
    assert inertia["link2"].new[0][0] == pytest.approx(1.5 / 12 * (0.01 + 1.44), abs=1e-9)
    assert not result.link_renames and not result.joint_renames


def test_the_text_of_totals_and_of_a_mass_from_nothing(tmp_path: Path) -> None:
    # provenance: written anew; a massless tool link that gains 0.5 kg (found by a new user on iiwa7)
    def robot(tool_mass: str) -> str:
        inertial = (f'<inertial><mass value="{tool_mass}"/><inertia ixx="0.001" iyy="0.001" izz="0.001" '
                    'ixy="0" ixz="0" iyz="0"/></inertial>') if tool_mass else ""
        return ('<robot name="arm"><link name="base"><inertial><mass value="2"/><inertia ixx="0.01" '
                'iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>'
                f'<link name="tool">{inertial}</link><joint name="j" type="fixed"><parent link="base"/>'
                '<child link="tool"/><origin xyz="0 0 0.3" rpy="1.5707963267948966 0 0"/></joint></robot>')
    old, new = tmp_path / "old.urdf", tmp_path / "new.urdf"
    old.write_text(robot(""))
    new.write_text(robot("0.5"))
    text = CliRunner().invoke(main, ["diff", str(old), str(new)]).output
    assert "total mass of 'arm': 2 → 2.5" in text
    assert "mass mass" not in text and "com of" not in text and "inf%" not in text
    assert "e-17" not in text and "e-16" not in text


def test_a_reformatted_reordered_file_diffs_as_empty(tmp_path: Path) -> None:
    assert PANDA is not None
    root = etree.parse(str(PANDA)).getroot()
    links = [e for e in root if e.tag == "link"]
    for link in links:  # every link after the joints, in reverse order
        root.remove(link)
    for link in reversed(links):
        root.append(link)
    for element in root.iter():
        if isinstance(element.tag, str) and len(element.attrib) > 1:  # attribute order reversed
            items = list(element.attrib.items())[::-1]
            element.attrib.clear()
            for key, value in items:
                element.set(key, value)
    # Beside its SRDF, as the original is: the SRDF's stance is part of the robot both sides load.
    copy = tmp_path / "urdf" / "panda.urdf"
    copy.parent.mkdir()
    copy.write_bytes(etree.tostring(root, pretty_print=True, xml_declaration=True, encoding="utf-8"))
    (tmp_path / "srdf").mkdir()
    srdf = PANDA.parent.parent / "srdf" / "panda.srdf"
    (tmp_path / "srdf" / "panda.srdf").write_bytes(srdf.read_bytes())
    assert copy.read_bytes() != PANDA.read_bytes()
    assert urdftool.diff(PANDA, copy).empty


def test_a_renamed_link_and_joint_are_renames(tmp_path: Path) -> None:
    assert PANDA is not None
    text = PANDA.read_text().replace('"panda_link3"', '"upper_elbow"').replace('"panda_joint3"', '"elbow"')
    new = tmp_path / "panda.urdf"
    new.write_text(text)
    result = urdftool.diff(PANDA, new, findings=False)
    assert dict(result.link_renames) == {"panda_link3": "upper_elbow"}
    assert dict(result.joint_renames) == {"panda_joint3": "elbow"}
    assert {c.kind for c in result.changes} == {"link-renamed", "joint-renamed"}


def test_cli_markdown_json_and_fail_on(tmp_path: Path) -> None:
    new = _edited_rrbot(tmp_path)
    base = ["diff", str(RRBOT / "urdf" / "rrbot.xacro"), str(new), "--package", f"rrbot_description={RRBOT}",
            "--no-findings"]
    markdown = CliRunner().invoke(main, [*base, "--format", "markdown"])
    assert markdown.exit_code == 0, markdown.output
    assert "| what | subject | change | size |\n|---|---|---|---|\n" in markdown.stdout
    data = json.loads(CliRunner().invoke(main, [*base, "--format", "json"]).stdout)
    assert any(c["kind"] == "pose" and c["subject"] == "link3" for c in data["changes"])
    assert CliRunner().invoke(main, [*base, "--fail-on", "pose>1mm"]).exit_code == 1
    assert CliRunner().invoke(main, [*base, "--fail-on", "pose>300mm,mass>60%"]).exit_code == 0
    assert CliRunner().invoke(main, [*base, "--fail-on", "mass>1%"]).exit_code == 1
    assert CliRunner().invoke(main, [*base, "--fail-on", "weight>1"]).exit_code == 2


def test_new_errors_trip_the_gate(tmp_path: Path) -> None:
    assert PANDA is not None
    new = tmp_path / "panda.urdf"
    new.write_text(PANDA.read_text().replace('<mass value="0.73"/>', '<mass value="-0.73"/>', 1))
    result = urdftool.diff(PANDA, new, package_paths=[], findings=True)
    assert any(c.kind == "finding-new" and c.subject == "I003" for c in result.changes)
    assert tripped(result, parse_fail_on("new-errors")) == ["new-errors"]
    with pytest.raises(FailOnError):
        parse_fail_on("pose>1deg")


def test_rev_compares_a_git_revision_with_the_working_copy(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    assert PANDA is not None
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "panda.urdf"
    path.write_bytes(PANDA.read_bytes())
    for command in (["init", "-q", "."], ["add", "panda.urdf"],
                    ["-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "panda"]):
        subprocess.run(["git", *command], check=True)
    path.write_text(PANDA.read_text().replace('xyz="0 0 0.333"', 'xyz="0 0 0.334"'))
    result = CliRunner().invoke(main, ["diff", "--rev", "HEAD", "panda.urdf", "--no-findings",
                                       "--format", "json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["old"] == "panda.urdf@HEAD"
    link1 = next(c for c in data["changes"] if c["kind"] == "pose" and c["subject"] == "panda_link1")
    assert link1["size"] == pytest.approx(1.0, abs=1e-9)
    assert sorted(p.name for p in tmp_path.iterdir()) == [".git", "panda.urdf"]
