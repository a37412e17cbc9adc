"""Normal runs print nothing on stderr but urdftool's own messages: no library warnings or logs."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from tests.conftest import FIXTURES, SEEDS


def test_check_of_the_fixtures_and_seed_robots_keeps_stderr_empty(tmp_path: Path) -> None:
    # A fresh mesh cache: every mesh is read and measured (flat meshes included), not recalled.
    env = dict(os.environ, URDFTOOL_CACHE_DIR=str(tmp_path / "cache"))
    result = subprocess.run(
        [sys.executable, "-m", "urdftool", "check", "--format", "json", "-o", str(tmp_path / "r.json"),
         str(FIXTURES / "rules"), str(SEEDS)],
        capture_output=True, text=True, env=env, timeout=600, check=False,
    )
    assert result.returncode == 1, result.stderr  # the bad fixtures have errors
    assert result.stderr == ""
