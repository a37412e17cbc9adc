"""The shape of the code: the layer contract, no package cycles, few function-level imports, small modules."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from tests.conftest import ROOT

sys.path.insert(0, str(ROOT / "scripts"))
import import_graph

#: Function-level imports of project modules allowed at most (each says why: a heavy engine
#: or first-read cost); a new one to dodge a cycle means the code belongs in another layer.
MAX_FUNCTION_LEVEL_IMPORTS = 15
MAX_MODULE_LINES = 600


def test_import_linter_contracts_are_kept() -> None:
    lint = Path(sys.executable).with_name("lint-imports")
    result = subprocess.run([str(lint), "--config", str(ROOT / "pyproject.toml")], cwd=ROOT,
                            capture_output=True, text=True, check=False)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "0 broken" in result.stdout


def test_function_level_project_imports_are_few() -> None:
    found = [
        f"{path.relative_to(ROOT)}:{line} {target}"
        for path in sorted((ROOT / "urdftool").rglob("*.py"))
        for target, line, inside in import_graph.imports(path)
        if inside
    ]
    assert len(found) <= MAX_FUNCTION_LEVEL_IMPORTS, "\n".join(found)


def test_no_module_passes_600_lines() -> None:
    long = {
        str(path.relative_to(ROOT)): n
        for path in (ROOT / "urdftool").rglob("*.py")
        if (n := len(path.read_text(encoding="utf-8").splitlines())) > MAX_MODULE_LINES
    }
    assert not long, long


def test_no_package_imports_a_layer_above_it() -> None:
    """The graph the script prints has no cycle between packages."""
    edges: dict[str, set[str]] = {}
    for path in (ROOT / "urdftool").rglob("*.py"):
        source = import_graph.package_of(import_graph._module_name(path))
        for target, _line, _inside in import_graph.imports(path):
            if import_graph.package_of(target) != source:
                edges.setdefault(source, set()).add(import_graph.package_of(target))
    seen: dict[str, int] = {}

    def visit(node: str, trail: list[str]) -> None:
        seen[node] = 1
        for nxt in sorted(edges.get(node, ())):
            assert seen.get(nxt) != 1, f"package cycle: {' -> '.join([*trail, nxt])}"
            if nxt not in seen:
                visit(nxt, [*trail, nxt])
        seen[node] = 2

    for package in sorted(edges):
        if package not in seen:
            visit(package, [package])
