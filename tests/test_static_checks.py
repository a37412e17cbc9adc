"""The code base is clean under its own tools: ruff (lint) and mypy (strict), as configured in pyproject."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LINTED = ["urdftool", "tests", "benchmarks", "scripts"]


def run_tool(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", *args], cwd=ROOT, capture_output=True, text=True, timeout=600, check=False
    )


def test_ruff_reports_nothing() -> None:
    result = run_tool("ruff", "check", "--no-cache", *LINTED)
    assert result.returncode == 0, f"ruff check failed:\n{result.stdout}\n{result.stderr}"


def test_mypy_strict_passes() -> None:
    # Packages and strictness come from [tool.mypy]; the cache is the default .mypy_cache (gitignored).
    result = run_tool("mypy")
    assert result.returncode == 0, f"mypy failed:\n{result.stdout}\n{result.stderr}"
