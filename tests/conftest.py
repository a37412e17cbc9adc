"""Shared test helpers: paths to the fixtures and the installed corpora."""

from __future__ import annotations

import glob
import os
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
FIXTURES = ROOT / "fixtures"
SEEDS = ROOT.parent / "shared" / "corpus" / "seed-systems"


def example_robot_data_dir() -> Path | None:
    for entry in sys.path:
        candidate = Path(entry) / "cmeel.prefix" / "share" / "example-robot-data" / "robots"
        if candidate.is_dir():
            return candidate
    return None


def pybullet_data_dir() -> Path | None:
    try:
        import pybullet_data
    except ImportError:
        return None
    return Path(pybullet_data.getDataPath())


ERD = example_robot_data_dir()
PBD = pybullet_data_dir()


def erd_urdfs() -> list[str]:
    assert ERD is not None, "example-robot-data is a test dependency"
    return sorted(glob.glob(str(ERD / "**" / "*.urdf"), recursive=True))


def relative(path: str, base: Path | None) -> str:
    return os.path.relpath(path, base) if base else path


@pytest.fixture
def seeds() -> Path:
    assert SEEDS.is_dir(), f"the seed corpus is expected beside the repository at {SEEDS}"
    return SEEDS
