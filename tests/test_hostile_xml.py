"""Hostile or broken XML ends as one located xml-syntax finding (exit 1), never a traceback.

Each input is tried three ways: as a ``.urdf``, as a ``.urdf.xacro``, and as a
file that a well-formed xacro includes; in the last case the finding must point
into the included file, since that is the file to fix.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import pytest
from click.testing import CliRunner

from tests.conftest import FIXTURES
from urdftool.cli import main
from urdftool.parse.xmlio import MAX_BYTES

ARM = (FIXTURES / "robots" / "two_link_arm.urdf").read_bytes()

BILLION_LAUGHS = b"""<?xml version="1.0"?>
<!DOCTYPE robot [
  <!ENTITY lol "lol">
  <!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
  <!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
  <!ENTITY lol4 "&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;">
]>
<robot name="&lol4;"><link name="base"/></robot>
"""

EXTERNAL_ENTITY = b"""<?xml version="1.0"?>
<!DOCTYPE robot [
<!ENTITY secret SYSTEM "file:///etc/passwd">
]>
<robot name="arm"><link name="&secret;"/></robot>
"""

#: markup in a comment before the DOCTYPE: the guard once took the comment's "<link" for the root
#: element and looked for entity declarations only before it
HIDDEN_BY_COMMENT = b"""<?xml version="1.0"?>
<!-- generated from <link> templates -->
<!DOCTYPE robot [<!ENTITY lol "lol"><!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">]>
<robot name="&lol2;"><link name="base"/></robot>
"""

#: a byte order mark before the DOCTYPE
AFTER_BOM = b"\xef\xbb\xbf" + BILLION_LAUGHS.split(b"\n", 1)[1]


def _oversized() -> bytes:
    body = b'<robot name="big">\n' + b'  <link name="l"/>\n' * (MAX_BYTES // 18 + 1) + b"</robot>\n"
    assert len(body) > MAX_BYTES
    return body


#: name -> (content factory, the line the finding must be on, a word the message must contain)
CASES: dict[str, tuple[Callable[[], bytes], int, str]] = {
    "billion-laughs": (lambda: BILLION_LAUGHS, 3, "entity"),
    "external-entity": (lambda: EXTERNAL_ENTITY, 3, "entity"),
    "entity-behind-a-comment": (lambda: HIDDEN_BY_COMMENT, 3, "entity"),
    "entity-after-a-bom": (lambda: AFTER_BOM, 2, "entity"),
    "deep-nesting": (
        lambda: b'<robot name="deep">\n' + b"<a>" * 300 + b"</a>" * 300 + b"\n</robot>\n",
        2,
        "256",
    ),
    "over-size-cap": (_oversized, 1, "MiB"),
    "binary-garbage": (lambda: bytes(range(256)) * 16, 1, "binary"),
    "empty": (lambda: b"", 1, "empty"),
    "not-utf8": (
        lambda: '<robot name="Bräu">\n  <link name="base"/>\n</robot>\n'.encode("latin-1"),
        1,
        "UTF-8",
    ),
    "truncated": (lambda: ARM[: len(ARM) // 2], 20, "truncated"),
}

INCLUDER = """<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:include filename="{name}"/>
  <link name="base"/>
</robot>
"""


def _write(tmp_path: Path, case: str, mode: str) -> tuple[Path, Path]:
    """Write the hostile file for *mode*; return (file to check, file the finding must name)."""
    content = CASES[case][0]()
    if mode == "urdf":
        hostile = tmp_path / f"{case}.urdf"
        hostile.write_bytes(content)
        return hostile, hostile
    if mode == "xacro":
        hostile = tmp_path / f"{case}.urdf.xacro"
        hostile.write_bytes(content)
        return hostile, hostile
    hostile = tmp_path / f"{case}.xacro"
    hostile.write_bytes(content)
    top = tmp_path / "robot.urdf.xacro"
    top.write_text(INCLUDER.format(name=hostile.name), encoding="utf-8")
    return top, hostile


def _check(*args: str) -> tuple[int, str]:
    result = CliRunner().invoke(main, ["check", *args])
    # A traceback would surface as an exception other than the SystemExit of the exit code.
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    assert "Traceback" not in result.output
    return result.exit_code, result.output


@pytest.mark.parametrize("mode", ["urdf", "xacro", "included"])
@pytest.mark.parametrize("case", sorted(CASES))
def test_hostile_input_is_a_located_xml_syntax_error(tmp_path: Path, case: str, mode: str) -> None:
    checked, culprit = _write(tmp_path, case, mode)
    code, output = _check("--format", "json", str(checked))
    assert code == 1
    report = json.loads(output)
    (file_report,) = report["files"]
    found = file_report["diagnostics"]
    assert [d["name"] for d in found] == ["xml-syntax"], found
    finding = found[0]
    _, line, word = CASES[case]
    assert finding["severity"] == "error"
    assert Path(finding["location"]["path"]).resolve() == culprit.resolve()
    assert finding["location"]["line"] == line
    assert finding["location"]["column"] >= 1
    assert word.lower() in finding["message"].lower()


@pytest.mark.parametrize("case", ["billion-laughs", "external-entity", "entity-behind-a-comment",
                                  "entity-after-a-bom"])
def test_entities_are_never_expanded(tmp_path: Path, case: str) -> None:
    checked, _ = _write(tmp_path, case, "urdf")
    code, output = _check(str(checked))
    assert code == 1
    assert "lollollol" not in output
    assert "root:" not in output  # no line of /etc/passwd leaks into the report


def test_text_report_of_binary_file_is_printable(tmp_path: Path) -> None:
    checked, _ = _write(tmp_path, "binary-garbage", "urdf")
    code, output = _check(str(checked))
    assert code == 1
    assert f"{checked}:1:1: error[S001 xml-syntax] file is binary data" in output
    assert "\x00" not in output and "\x07" not in output
    assert max(len(line) for line in output.splitlines()) < 300


def test_hostile_file_does_not_stop_a_directory_check(tmp_path: Path) -> None:
    _write(tmp_path, "truncated", "urdf")
    (tmp_path / "arm.urdf").write_bytes(ARM)
    code, output = _check("--format", "json", str(tmp_path))
    assert code == 1
    report = json.loads(output)
    by_name = {Path(f["path"]).name: f for f in report["files"]}
    assert set(by_name) == {"arm.urdf", "truncated.urdf"}
    assert by_name["arm.urdf"]["robot"] == "two_link_arm"
    assert [d["code"] for d in by_name["truncated.urdf"]["diagnostics"]] == ["S001"]


def test_a_mesh_naming_a_fifo_as_its_material_library_loads_without_it(tmp_path: Path) -> None:
    """An OBJ's ``mtllib`` is a FIFO beside it: trimesh's own resolver would open it and wait for
    a writer forever. The resolver urdftool gives trimesh reads regular files only (within the
    mesh size cap), so the mesh loads without materials, as with a missing library."""
    import os

    from urdftool.backends import mesh_files
    from urdftool.backends.meshes import load_trimesh
    from urdftool.safe_files import UnsafeFile

    os.mkfifo(tmp_path / "part.mtl")
    (tmp_path / "part.obj").write_text(
        "mtllib part.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nusemtl grey\n"
        "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    with pytest.raises(UnsafeFile):
        mesh_files.resolver(str(tmp_path / "part.obj")).get("part.mtl")
    assert len(load_trimesh(str(tmp_path / "part.obj")).faces) == 4
