"""Shared by scripts/demo and scripts/test: a virtual environment with urdftool and its test deps.

Only the Python standard library is used here, so the scripts run on a fresh
machine with nothing but Python 3.10+.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
VENV = Path(os.environ.get("URDFTOOL_VENV", ROOT / ".venv"))
STAMP = VENV / ".urdftool-installed"


def _bin(name: str) -> Path:
    return VENV / ("Scripts" if os.name == "nt" else "bin") / name


def python() -> str:
    return str(_bin("python"))


#: program -> Debian package: Graphviz renders `urdftool graph` PDFs/SVGs/PNGs; poppler's
#: pdftoppm lets the tests look inside the rendered PDFs.
SYSTEM_TOOLS = {"dot": "graphviz", "pdftoppm": "poppler-utils"}


def ensure_system_tools() -> None:
    """Install the programs of SYSTEM_TOOLS that are missing, where apt-get allows."""
    missing = [tool for tool in SYSTEM_TOOLS if not shutil.which(tool)]
    if not missing:
        return
    apt = shutil.which("apt-get")
    if apt and hasattr(os, "geteuid") and os.geteuid() == 0:
        env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
        packages = sorted({SYSTEM_TOOLS[tool] for tool in missing})
        subprocess.run([apt, "update", "-qq"], check=False, env=env, stdout=subprocess.DEVNULL)
        subprocess.run([apt, "install", "-y", "-qq", *packages], check=False, env=env,
                       stdout=subprocess.DEVNULL)
    for tool in SYSTEM_TOOLS:
        if not shutil.which(tool):
            print(f"note: `{tool}` ({SYSTEM_TOOLS[tool]}) is not installed; the graph tests "
                  "that need it will fail", file=sys.stderr)


def ensure_venv(extras: str) -> None:
    """Create the environment and install urdftool[extras] once (again when the pins change)."""
    inputs = [ROOT / "pyproject.toml", ROOT / "constraints-test.txt"]
    wanted = extras + "".join(f":{p.stat().st_mtime_ns}" for p in inputs if p.exists())
    if STAMP.exists() and STAMP.read_text() == wanted and Path(python()).exists():
        return
    if not Path(python()).exists():
        print(f"creating {VENV}", file=sys.stderr)
        venv.EnvBuilder(with_pip=True).create(VENV)
    pip = [python(), "-m", "pip", "install", "--quiet", "--disable-pip-version-check"]
    subprocess.run([*pip, "--upgrade", "pip"], check=True)
    constraints = ROOT / "constraints-test.txt"
    pins = ["-c", str(constraints)] if constraints.exists() else []
    subprocess.run([*pip, "-e", f"{ROOT}[{extras}]", *pins], check=True)
    STAMP.write_text(wanted)


def run(args: list[str]) -> int:
    return subprocess.run(args, cwd=ROOT).returncode
