"""Every rule has a failing and a passing fixture; findings must match the marks.

Layout: ``fixtures/rules/<CODE>/bad.<ext>`` and ``good.<ext>`` (``.urdf``,
``.urdf.xacro``, ``.sdf``, ``.world``). In a bad fixture, each line where the
rule must fire carries a comment ``<!-- expect: CODE -->`` (several codes may
be listed, comma-separated); a file-level finding without a line is marked
``<!-- expect-file: CODE -->`` anywhere. The rule must fire exactly on the
marked lines. In a good fixture, the rule must not fire at all.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from tests.conftest import FIXTURES
from urdftool.pipeline.check import CheckOptions, check_file
from urdftool.rules import all_rules, lookup

RULES_DIR = FIXTURES / "rules"
_EXPECT = re.compile(r"<!--\s*expect:\s*([A-Z0-9, ]+?)\s*-->")
_EXPECT_FILE = re.compile(r"<!--\s*expect-file:\s*([A-Z0-9, ]+?)\s*-->")


#: Conversion rules fire on export, not on check: their fixtures (fixtures/rules/C*/)
#: are run through the MJCF exporter by tests/test_mjcf_rules.py.
EXPORT_ONLY = {"C001", "C002", "C003", "C004", "C005", "C007"}
#: collision-simplified is reported by `convert --collision`: tests/test_collision_convert.py.
CONVERT_ONLY = {"C006"}
#: Runtime rules fire only when the simulation runs, which `check` does not do by default:
#: their fixtures (fixtures/rules/R*/) are run with the simulation by tests/test_sim_rules.py.
SIM_ONLY = {"R001", "R002", "R003", "R004", "R005"}


def fixture_files(kind: str) -> list[Path]:
    """Fixtures of *kind*; an SRDF or controllers YAML fixture (``bad.srdf``, ``bad.yaml``) stands
    for itself and the model of its stem beside it (``bad.urdf``), which is checked with it and
    carries no marks (the model's ros2_control plugin names the YAML in its ``<parameters>``)."""
    return sorted(
        p
        for p in RULES_DIR.glob(f"*/{kind}*.*")
        if not p.name.endswith((".stl", ".obj", ".dae")) and p.parent.name not in EXPORT_ONLY | SIM_ONLY
        and not (p.suffix == ".urdf" and (p.with_suffix(".srdf").exists() or p.with_suffix(".yaml").exists()))
    )


def expected_marks(path: Path, code: str) -> tuple[set[int], bool]:
    lines: set[int] = set()
    file_level = False
    for number, text in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
        for match in _EXPECT.finditer(text):
            if code in [c.strip() for c in match.group(1).split(",")]:
                lines.add(number)
        for match in _EXPECT_FILE.finditer(text):
            if code in [c.strip() for c in match.group(1).split(",")]:
                file_level = True
    return lines, file_level


_TARGET = re.compile(r"<!--\s*check-target:\s*([a-z,\- ]+?)\s*-->")
#: xacro arguments a fixture is expanded with: <!-- xacro-args: name:=value, other:=value -->
_XACRO_ARGS = re.compile(r"<!--\s*xacro-args:\s*(.+?)\s*-->")


def fixture_xacro_args(path: Path) -> dict[str, str]:
    """The xacro arguments the fixture's ``<!-- xacro-args: … -->`` comment gives (none without one)."""
    given = _XACRO_ARGS.search(path.read_text(encoding="utf-8", errors="replace"))
    pairs = [a.strip().partition(":=") for a in given.group(1).split(",")] if given else []
    return {name: value for name, _, value in pairs}


def findings(path: Path, code: str) -> list:
    rule = lookup(code)
    # a rule that is off by default (an optional convention) runs when named
    select = None if rule is None or rule.default_enabled else (code,)
    # consumer rules (T) fire for the targets a fixture names with <!-- check-target: name -->
    named = _TARGET.search(path.read_text(encoding="utf-8", errors="replace"))
    rule_options = {"targets": tuple(t.strip() for t in named.group(1).split(","))} if named else {}
    options = CheckOptions(package_paths=(str(path.parent),), select=select, rule_options=rule_options,
                           xacro_args=fixture_xacro_args(path))
    model = path.with_suffix(".urdf") if path.suffix in (".srdf", ".yaml") else path
    return [d for r in check_file(str(model), options) for d in r.diagnostics if d.code == code]


@pytest.mark.parametrize("path", fixture_files("bad"), ids=lambda p: p.parent.name)
def test_bad_fixture_fires_on_marked_lines(path: Path) -> None:
    code = path.parent.name
    lines, file_level = expected_marks(path, code)
    assert lines or file_level, f"{path} marks no expected finding for {code}"
    found = findings(path, code)
    found_lines = {d.location.line for d in found if d.location and d.location.line and
                   Path(d.location.path).resolve() == path.resolve()}
    assert found, f"{code} did not fire on {path}"
    if lines:
        assert found_lines == lines, (
            f"{code} fired on lines {sorted(found_lines)}, fixture marks {sorted(lines)}:\n"
            + "\n".join(f"  {d.location}: {d.message}" for d in found)
        )


@pytest.mark.parametrize("path", fixture_files("good"), ids=lambda p: p.parent.name)
def test_good_fixture_is_quiet(path: Path) -> None:
    code = path.parent.name
    found = findings(path, code)
    assert not found, "\n".join(f"{d.location}: {d.message}" for d in found)


#: Rules that no input file can trigger, each with a dedicated test instead.
NO_FIXTURE = {"S000"}  # internal-error: see test_rule_crash_becomes_internal_error
NO_FIXTURE |= EXPORT_ONLY | CONVERT_ONLY
NO_FIXTURE |= SIM_ONLY  # runtime rules: see tests/test_sim_rules.py


def test_every_rule_has_both_fixtures() -> None:
    missing = []
    for rule in all_rules():
        if rule.code in NO_FIXTURE:
            continue
        folder = RULES_DIR / rule.code
        if not list(folder.glob("bad.*")) or not list(folder.glob("good.*")):
            missing.append(f"{rule.code} {rule.name}")
    assert not missing, "rules without a bad and a good fixture: " + ", ".join(missing)


def test_no_fixture_folder_without_a_rule() -> None:
    codes = {rule.code for rule in all_rules()}
    orphans = [p.name for p in RULES_DIR.iterdir() if p.is_dir() and p.name not in codes]
    assert not orphans, f"fixture folders for unknown codes: {orphans}"


def test_rule_crash_becomes_internal_error(monkeypatch) -> None:
    from urdftool.catalogue.syntax import SelfLoopJoint

    def explode(self, ctx):
        raise RuntimeError("boom")

    monkeypatch.setattr(SelfLoopJoint, "check", explode)
    path = FIXTURES / "robots" / "two_link_arm.urdf"
    found = [d for r in check_file(str(path), CheckOptions()) for d in r.diagnostics]
    crash = [d for d in found if d.name == "internal-error"]
    assert len(crash) == 1 and "S019" in crash[0].message and "boom" in crash[0].message
