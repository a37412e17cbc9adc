"""Self-collision: the home check and ``urdftool collisions`` (MoveIt's collision matrix)."""

from __future__ import annotations

import re
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from tests.conftest import ERD
from urdftool.cli import main
from urdftool.pipeline.check import CheckOptions, check_file
from urdftool.pipeline.collisions import collision_matrix, merge_srdf, mjcf_bytes, new_srdf
from urdftool.pipeline.load import load_one

pytest.importorskip("pinocchio")
pytest.importorskip("coal")

FIXTURES = Path(__file__).parent.parent / "fixtures" / "rules" / "P101"
_PAIR = re.compile(r'<disable_collisions\s+link1="([^"]+)"\s+link2="([^"]+)"\s+reason="([^"]+)"')


def _panda() -> tuple[Path, Path]:
    assert ERD is not None
    folder = ERD / "panda_description"
    return folder / "urdf" / "panda.urdf", folder / "srdf" / "panda.srdf"


def _pairs(text: str) -> dict[tuple[str, str], str]:
    return {tuple(sorted((a, b))): reason for a, b, reason in _PAIR.findall(text)}  # type: ignore[misc]


def _matrix(samples: int = 1000, seed: int = 0):  # type: ignore[no-untyped-def]
    urdf, _ = _panda()
    robot = load_one(str(urdf), CheckOptions()).robot
    assert robot is not None
    return collision_matrix(robot, samples, seed)


def test_panda_matrix_agrees_with_its_srdf_and_covers_adjacent_pairs() -> None:
    _, srdf = _panda()
    start = time.monotonic()
    found = _matrix(1000)
    assert time.monotonic() - start < 30
    theirs = _pairs(srdf.read_text())
    ours = dict(found.reasons)
    for key, reason in theirs.items():
        if reason == "Adjacent":
            assert ours.get(key) == "Adjacent", key
    links = found.links
    every = [tuple(sorted((a, b))) for i, a in enumerate(links) for b in links[i + 1:]]
    agree = sum((tuple(sorted(p)) in ours) == (tuple(sorted(p)) in theirs) for p in every)
    assert agree / len(every) >= 0.9, (agree, len(every))


def test_panda_matrix_is_deterministic_for_a_seed() -> None:
    first, second = _matrix(300, seed=7), _matrix(300, seed=7)
    assert first.reasons == second.reasons and first.sometimes == second.sometimes
    assert new_srdf(first, "panda") == new_srdf(second, "panda")


def test_merge_keeps_every_other_byte() -> None:
    _, srdf = _panda()
    original = srdf.read_bytes()
    found = _matrix(300)
    merged = merge_srdf(original, found)
    strip = re.compile(rb"[ \t]*<disable_collisions\b[^>]*/>[ \t]*\r?\n")
    assert strip.sub(b"", merged) == strip.sub(b"", original)
    assert _pairs(merged.decode()) == dict(found.reasons)


def test_merge_into_an_srdf_without_entries() -> None:
    found = _matrix(100)
    text = (b'<?xml version="1.0"?>\r\n<robot name="panda">\r\n'
            b'  <!-- <disable_collisions link1="x" link2="y"/> -->\r\n'
            b'  <group name="arm"/>\r\n</robot>\r\n')
    merged = merge_srdf(text, found)
    assert merged.startswith(text[: text.index(b"</robot>")])
    assert b'\r\n  <disable_collisions link1="panda_hand"' in merged
    assert merged.endswith(b"</robot>\r\n")
    assert b'link1="x"' in merged  # the commented-out entry is kept


def test_mjcf_block() -> None:
    found = _matrix(100)
    text = mjcf_bytes(found, "panda").decode()
    assert text.count("<exclude ") == len(found.reasons)
    assert "<contact>" in text and 'body1="panda_link0" body2="panda_link1"' in text


def test_cli_writes_and_merges(tmp_path: Path) -> None:
    urdf, srdf = _panda()
    out = tmp_path / "panda.srdf"
    out.write_bytes(srdf.read_bytes())
    result = CliRunner().invoke(main, ["collisions", str(urdf), "-o", str(out), "--samples", "500",
                                       "--seed", "3"])
    assert result.exit_code == 0, result.output
    assert "<group_state name=\"default\"" in out.read_text()
    fresh = tmp_path / "new.srdf"
    again = CliRunner().invoke(main, ["collisions", str(urdf), "-o", str(fresh), "--samples", "500",
                                      "--seed", "3", "-q"])
    assert again.exit_code == 0, again.output
    assert _pairs(fresh.read_text()) == _pairs(out.read_text())
    bad = CliRunner().invoke(main, ["collisions", str(urdf), "-o", str(tmp_path / "x.txt")])
    assert bad.exit_code == 2


def test_panda_with_its_srdf_is_clean_at_home() -> None:
    urdf, _ = _panda()
    [report] = check_file(str(urdf), CheckOptions(select=("P101", "P102")))
    assert not report.diagnostics


def test_panda_without_srdf_overlaps_at_home() -> None:
    urdf, _ = _panda()
    [report] = check_file(str(urdf), CheckOptions(select=("P101",), discover_srdf=False))
    pairs = {(d.data["link1"], d.data["link2"]) for d in report.diagnostics}
    assert ("panda_link5", "panda_link7") in pairs
    assert all(d.related and d.data["depth"] > 0 for d in report.diagnostics)


def test_fixture_overlap_depth() -> None:
    [report] = check_file(str(FIXTURES / "bad.urdf"), CheckOptions(select=("P101",)))
    [finding] = report.diagnostics
    assert finding.data["depth"] == pytest.approx(0.05, abs=1e-3)
    assert "50 mm" in finding.message
