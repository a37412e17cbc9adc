#!/usr/bin/env python3
"""Print urdftool's package import graph and every function-level import of a project module.

Usage: python3 scripts/import_graph.py [--function-level]

The layer contract itself is enforced by import-linter ([tool.importlinter] in
pyproject.toml, run by tests/test_architecture.py); this script is for reading
the graph while changing it.
"""

from __future__ import annotations

import ast
import sys
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "urdftool"


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _target(node: ast.ImportFrom, module: str, is_package: bool) -> str:
    if not node.level:
        return node.module or ""
    base = module.split(".") if is_package else module.split(".")[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join([*base, node.module] if node.module else base)


def imports(path: Path) -> list[tuple[str, int, bool]]:
    """(imported project module, line, inside a function) for every project import in *path*."""
    module = _module_name(path)
    tree = ast.parse(path.read_text(encoding="utf-8"))
    found: list[tuple[str, int, bool]] = []
    stack: list[tuple[ast.AST, bool]] = [(tree, False)]
    while stack:
        node, in_function = stack.pop()
        for child in ast.iter_child_nodes(node):
            inside = in_function or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef))
            if isinstance(child, ast.ImportFrom):
                target = _target(child, module, path.name == "__init__.py")
                if target.startswith("urdftool"):
                    found.append((target, child.lineno, inside))
            elif isinstance(child, ast.Import):
                names = [a.name for a in child.names if a.name.startswith("urdftool")]
                found.extend((name, child.lineno, inside) for name in names)
            stack.append((child, inside))
    return found


def package_of(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "urdftool"


def main() -> int:
    edges: dict[str, set[str]] = defaultdict(set)
    function_level: list[str] = []
    for path in sorted(PACKAGE.rglob("*.py")):
        source = package_of(_module_name(path))
        for target, line, inside in imports(path):
            if package_of(target) != source:
                edges[source].add(package_of(target))
            if inside:
                function_level.append(f"{path.relative_to(ROOT)}:{line} {target}")
    if "--function-level" in sys.argv:
        print("\n".join(function_level))
        print(f"{len(function_level)} function-level project imports")
        return 0
    for source in sorted(edges):
        print(f"{source} -> {', '.join(sorted(edges[source]))}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
