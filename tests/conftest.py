"""Shared test helpers: paths to the fixtures and the installed corpora."""

from __future__ import annotations

import glob
import os
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
FIXTURES = ROOT / "fixtures"
SEEDS = FIXTURES / "seeds"


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
    assert SEEDS.is_dir(), f"the vendored seed corpus is missing at {SEEDS}"
    return SEEDS


def pybullet_robots() -> list[str]:
    """pybullet_data's robot URDFs: outside random_urdfs/, with a moving joint or at least 3 links.

    Counted on the raw text (not with urdftool's reader) so that files urdftool
    rejects still belong to the set: 45 files in pybullet 3.2.x.
    """
    import re

    assert PBD is not None, "pybullet is a test dependency"
    out = []
    for path in sorted(glob.glob(str(PBD / "**" / "*.urdf"), recursive=True)):
        if "/random_urdfs/" in path.replace(os.sep, "/"):
            continue
        text = Path(path).read_bytes().decode("utf-8", "replace")
        links = len(re.findall(r"<link\b", text))
        moving = [t for t in re.findall(r"<joint\b[^>]*\btype\s*=\s*\"([^\"]+)\"", text) if t != "fixed"]
        if moving or links >= 3:
            out.append(path)
    return out


def seed_standalone_xacros() -> list[str]:
    """The seed xacro files that no other seed xacro includes (checked on their own)."""
    from urdftool.parse.packages import PackageResolver
    from urdftool.pipeline.discover import expand_paths

    files = expand_paths([str(SEEDS)], PackageResolver.create())
    return sorted(f for f in files if f.endswith(".xacro"))


#: Test modules that walk the installed corpora or run the engines over many robots: the
#: whole suite runs them; `python3 scripts/test --fast` (the inner loop) leaves them out.
SLOW_MODULES = frozenset({
    "test_collada",
    "test_corpus_structure",
    "test_crosscheck",
    "test_graph_corpus",
    "test_inertia_corpus",
    "test_json_schema",
    "test_meshes_corpus",
    "test_meshes_engines",
    "test_mjcf_corpus",
    "test_mjcf_stand",
    "test_pybullet_corpus",
    "test_sim_corpus",
    "test_static_checks",
    # the fuzz slice (2,000 cases) and the 5,000-link chains run in the whole suite
    "test_fuzz",
})


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    for item in items:
        if item.module is not None and item.module.__name__.rsplit(".", 1)[-1] in SLOW_MODULES:
            item.add_marker(pytest.mark.slow)
