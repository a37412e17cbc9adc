"""`import urdftool` and a plain `urdftool check` of a URDF load no heavy engine.

Run in fresh interpreters, since the test process itself has imported them.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import FIXTURES

HEAVY = ("trimesh", "pinocchio", "mujoco", "pybullet")

#: Modules a ``check --select S`` of a URDF never imports, findings or not: each is for a flag
#: (--fix/--diff, -o, --baseline, --sim), another input (xacro, an SRDF is read only when one is
#: found, a controllers YAML only when the model names one) or another family of rules.
OFF_THE_CHECK_PATH = (
    "numpy", "yaml", "scipy", "xacro", "json", "difflib", "tempfile", "hashlib",
    "urdftool.parse.xacro", "urdftool.parse.srdf", "urdftool.parse.controllers", "urdftool.parse.ament",
    "urdftool.backends", "urdftool.simulation", "urdftool.export", "urdftool.export.write",
    "urdftool.pipeline.fix", "urdftool.pipeline.baseline", "urdftool.facts.simulation.options",
    "urdftool.rules.summaries",
    # the compiled __init__ methods of records that only exports, engines and simulations build
    "urdftool.records_compiled.export", "urdftool.records_compiled.export_mjcf",
    "urdftool.records_compiled.backends", "urdftool.records_compiled.simulation",
    # ...and of records that only the SDF and SRDF readers build
    "urdftool.records_compiled.parse_sdf", "urdftool.records_compiled.parse_srdf",
)
#: Modules that act on findings, imported only when a file has some.
ONLY_FOR_FINDINGS = (
    "urdftool.pipeline.fixes", "urdftool.pipeline.fixtext", "urdftool.pipeline.provenance",
    "urdftool.facts.simulation", "urdftool.facts.simulation.verdict",
)

#: lists the modules of *heavy* that are loaded, before importing json to print them
_REPORT = ("import sys; loaded = sorted(m for m in {heavy!r} if m in sys.modules); "
           "import json; print(json.dumps(loaded))")


def _heavy_modules_after(code: str) -> list[str]:
    script = code + "\n" + _REPORT.format(heavy=HEAVY)
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_import_urdftool_loads_no_engine() -> None:
    assert _heavy_modules_after("import urdftool") == []


@pytest.mark.parametrize(
    "path",
    [FIXTURES / "robots" / "two_link_arm.urdf", FIXTURES / "rules" / "S005" / "bad.urdf"],
    ids=["clean-arm", "broken-arm"],
)
def test_check_of_a_urdf_loads_no_engine(path) -> None:
    # The dynamics pass (Pinocchio) runs by default; --no-dynamics keeps check engine-free.
    code = (
        "import sys\n"
        "from urdftool.cli import main\n"
        "try:\n"
        f"    main(['check', '--no-dynamics', {str(path)!r}])\n"
        "except SystemExit as exc:\n"
        "    assert exc.code in (0, 1), exc.code\n"
    )
    assert _heavy_modules_after(code) == []


def test_default_check_loads_only_pinocchio() -> None:
    code = (
        "from urdftool.cli import main\n"
        "try:\n"
        f"    main(['check', {str(FIXTURES / 'robots' / 'two_link_arm.urdf')!r}])\n"
        "except SystemExit as exc:\n"
        "    assert exc.code in (0, 1), exc.code\n"
    )
    assert _heavy_modules_after(code) == ["pinocchio"]


def test_the_probe_sees_an_engine_when_one_is_imported() -> None:
    """The probe itself can fail: importing an engine is noticed."""
    assert _heavy_modules_after("import trimesh") == ["trimesh"]


def test_structural_check_does_not_import_numpy() -> None:
    """NumPy costs more to import than a structural check; the CLI start stays fast."""
    code = (
        "import sys\n"
        "from urdftool.cli import main\n"
        "try:\n"
        f"    main(['check', '--select', 'S,X', {str(FIXTURES / 'robots' / 'two_link_arm.urdf')!r}])\n"
        "except SystemExit as exc:\n"
        "    assert exc.code == 0, exc.code\n"
        "print('numpy' in sys.modules)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip().splitlines()[-1] == "False"


def test_structural_check_imports_only_the_structural_rules_and_lxml() -> None:
    """``check --select S`` imports the S rules' module and no other rule module (the generated
    table in urdftool/rules/table.py names them all), and no heavy library besides lxml."""
    path = FIXTURES / "rules" / "S011" / "bad.urdf"
    code = (
        "import sys\n"
        "from urdftool.cli import main\n"
        "try:\n"
        f"    main(['check', '--isolated', '--select', 'S', {str(path)!r}])\n"
        "except SystemExit as exc:\n"
        "    assert exc.code == 1, exc.code\n"
        "rules = sorted(m for m in sys.modules if m.startswith('urdftool.rules.'))\n"
        "assert rules == ['urdftool.rules.registry', 'urdftool.rules.selection', 'urdftool.rules.syntax',\n"
        "                 'urdftool.rules.table'], rules\n"
        "assert 'lxml.etree' in sys.modules\n"
    )
    heavy = (*HEAVY, *OFF_THE_CHECK_PATH)
    script = code + _REPORT.format(heavy=heavy)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout.strip().splitlines()[-1]) == []


def test_clean_structural_check_imports_nothing_that_acts_on_findings() -> None:
    """A plain URDF with no findings (the CI gate's common case, and the cold-start figure of
    docs/scale.md) loads neither the fix builders nor the provenance tracer, which act on findings,
    nor the simulation verdict, which reads them."""
    path = FIXTURES / "rules" / "S001" / "good.urdf"
    code = (
        "import sys\n"
        "from urdftool.cli import main\n"
        "try:\n"
        f"    main(['check', '--select', 'S', {str(path)!r}])\n"
        "except SystemExit as exc:\n"
        "    assert exc.code == 0, exc.code\n"
    )
    heavy = (*HEAVY, *OFF_THE_CHECK_PATH, *ONLY_FOR_FINDINGS)
    script = code + _REPORT.format(heavy=heavy)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout.strip().splitlines()[-1]) == []


def test_a_pyproject_without_urdftool_is_passed_over_unparsed(tmp_path: Path) -> None:
    """Config discovery reads a ``pyproject.toml`` only when it can hold ``[tool.urdftool]``: a
    project's own pyproject (every Python repository has one) costs no TOML parser at start."""
    (tmp_path / "pyproject.toml").write_text('[project]\nname = "robot"\n[tool.ruff]\nline-length = 99\n')
    model = tmp_path / "robot.urdf"
    model.write_text((FIXTURES / "rules" / "S001" / "good.urdf").read_text())
    code = (
        "import sys\n"
        "from urdftool.cli import main\n"
        "try:\n"
        f"    main(['check', '--select', 'S', {str(model)!r}])\n"
        "except SystemExit as exc:\n"
        "    assert exc.code == 0, exc.code\n"
    )
    script = code + _REPORT.format(heavy=("tomllib", "tomli"))
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout.strip().splitlines()[-1]) == []
    (tmp_path / "pyproject.toml").write_text('[tool.urdftool]\nselect = ["S"]\n')
    done = subprocess.run([sys.executable, "-m", "urdftool", "check", "--show-settings", str(model)],
                          capture_output=True, text=True, timeout=120)
    assert "pyproject.toml" in done.stdout + done.stderr, done.stdout + done.stderr
