"""The CI integrations: the pre-commit hook (through ``pre-commit try-repo``), the GitHub
action's definition and its check step (``scripts/action-check.sh``)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from tests.conftest import FIXTURES, ROOT

BAD = FIXTURES / "rules" / "S005" / "bad.urdf"
GOOD = FIXTURES / "robots" / "two_link_arm.urdf"


def _env(tmp_path: Path) -> dict[str, str]:
    return {
        **os.environ,
        "PYTHONPATH": os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH", "")) if p),
        "PRE_COMMIT_HOME": str(tmp_path / "pre-commit-home"),
        "GIT_AUTHOR_NAME": "t", "GIT_AUTHOR_EMAIL": "t@example.invalid",
        "GIT_COMMITTER_NAME": "t", "GIT_COMMITTER_EMAIL": "t@example.invalid",
        "NO_COLOR": "1",
    }


def _git(cwd: Path, env: dict[str, str], *args: str) -> None:
    subprocess.run(["git", *args], cwd=cwd, env=env, check=True, capture_output=True, timeout=60)


def test_hook_definition() -> None:
    (hook,) = yaml.safe_load((ROOT / ".pre-commit-hooks.yaml").read_text(encoding="utf-8"))
    assert hook["id"] == "urdftool" and hook["entry"] == "urdftool check"
    assert hook["language"] == "python" and hook["files"] == r"\.(urdf|xacro|sdf|world)$"


@pytest.mark.skipif(shutil.which("git") is None, reason="git is not installed")
def test_pre_commit_try_repo_runs_the_hook(tmp_path: Path) -> None:
    """The repository's hook, run by pre-commit on a repository with one bad and one good robot.

    pre-commit would build a virtual environment and install urdftool from PyPI for
    ``language: python``; here the hook runs this checkout instead (``language: system``,
    ``python -m urdftool check``), everything else as the hook file says.
    """
    env = _env(tmp_path)
    hooks = tmp_path / "hooks"
    hooks.mkdir()
    (hook,) = yaml.safe_load((ROOT / ".pre-commit-hooks.yaml").read_text(encoding="utf-8"))
    entry = hook["entry"].replace("urdftool", f"{sys.executable} -m urdftool", 1)
    hook.update(language="system", entry=entry)
    (hooks / ".pre-commit-hooks.yaml").write_text(yaml.safe_dump([hook]), encoding="utf-8")
    _git(hooks, env, "init", "-q")
    _git(hooks, env, "add", ".")
    _git(hooks, env, "commit", "-q", "-m", "hooks")

    project = tmp_path / "project"
    (project / "urdf").mkdir(parents=True)
    shutil.copy(BAD, project / "urdf" / "bad.urdf")
    shutil.copy(GOOD, project / "urdf" / "good.urdf")
    (project / "README.md").write_text("not a robot\n", encoding="utf-8")
    _git(project, env, "init", "-q")
    _git(project, env, "add", ".")

    def try_repo(*files: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [sys.executable, "-m", "pre_commit", "try-repo", str(hooks), "urdftool", "--files", *files],
            cwd=project, env=env, capture_output=True, text=True, timeout=300, check=False,
        )

    failing = try_repo("urdf/bad.urdf", "urdf/good.urdf", "README.md")
    assert failing.returncode == 1, failing.stdout + failing.stderr
    assert "invalid-number" in failing.stdout and "Failed" in failing.stdout
    passing = try_repo("urdf/good.urdf", "README.md")
    assert passing.returncode == 0, passing.stdout + passing.stderr
    skipped = try_repo("README.md")
    assert skipped.returncode == 0 and "no files to check" in skipped.stdout.lower()


def test_action_definition() -> None:
    action = yaml.safe_load((ROOT / "action.yml").read_text(encoding="utf-8"))
    assert action["runs"]["using"] == "composite"
    steps = action["runs"]["steps"]
    check = next(s for s in steps if s.get("id") == "check")
    assert "scripts/action-check.sh" in check["run"] and check["shell"] == "bash"
    upload = next(s for s in steps if str(s.get("uses", "")).startswith("github/codeql-action/upload-sarif"))
    assert upload["with"]["sarif_file"] == "${{ inputs.sarif-file }}"
    assert action["inputs"]["sarif-file"]["default"] == "urdftool.sarif"


@pytest.mark.skipif(shutil.which("bash") is None, reason="bash is not installed")
@pytest.mark.parametrize("fail_on_findings, expected", [("true", 1), ("false", 0)])
def test_action_step_writes_sarif_and_outputs(tmp_path: Path, fail_on_findings: str, expected: int) -> None:
    shim = tmp_path / "bin"
    shim.mkdir()
    (shim / "urdftool").write_text(f'#!/bin/sh\nexec "{sys.executable}" -m urdftool "$@"\n', encoding="utf-8")
    (shim / "urdftool").chmod(0o755)
    work = tmp_path / "repo"
    (work / "robots").mkdir(parents=True)
    shutil.copy(BAD, work / "robots" / "arm.urdf")
    outputs = tmp_path / "github_output"
    env = {
        **_env(tmp_path),
        "PATH": os.pathsep.join([str(shim), os.environ.get("PATH", "")]),
        "URDFTOOL_SKIP_INSTALL": "1",
        "URDFTOOL_PATHS": "robots",
        "URDFTOOL_ARGS": "--select S",
        "URDFTOOL_FAIL_ON_FINDINGS": fail_on_findings,
        "GITHUB_OUTPUT": str(outputs),
    }
    result = subprocess.run(["bash", str(ROOT / "scripts" / "action-check.sh")], cwd=work, env=env,
                            capture_output=True, text=True, timeout=300, check=False)
    assert result.returncode == expected, result.stdout + result.stderr
    sarif = json.loads((work / "urdftool.sarif").read_text(encoding="utf-8"))
    results = sarif["runs"][0]["results"]
    uris = {r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] for r in results}
    assert uris == {"robots/arm.urdf"}
    assert outputs.read_text(encoding="utf-8").splitlines() == ["exit-code=1", "sarif-file=urdftool.sarif"]


def test_action_step_stops_on_unreadable_input(tmp_path: Path) -> None:
    shim = tmp_path / "bin"
    shim.mkdir()
    (shim / "urdftool").write_text(f'#!/bin/sh\nexec "{sys.executable}" -m urdftool "$@"\n', encoding="utf-8")
    (shim / "urdftool").chmod(0o755)
    env = {**_env(tmp_path), "PATH": os.pathsep.join([str(shim), os.environ.get("PATH", "")]),
           "URDFTOOL_SKIP_INSTALL": "1", "URDFTOOL_PATHS": "missing.urdf",
           "URDFTOOL_FAIL_ON_FINDINGS": "false"}
    result = subprocess.run(["bash", str(ROOT / "scripts" / "action-check.sh")], cwd=tmp_path, env=env,
                            capture_output=True, text=True, timeout=300, check=False)
    assert result.returncode == 2 and "::error" in result.stdout
