"""Every robot of the corpora is drawn: DOT, PDF and SVG, checked for real.

For each robot the DOT text is written, Graphviz renders a PDF and an SVG in
one run (one layout), the SVG must hold a node for every link and joint with
the right name on it, and the PDF's first page, rendered back to PNG by
poppler, must show a drawing. The robots are batched into a few tests so that
the corpus stays affordable on two cores (about 140 robots).
"""

from __future__ import annotations

import glob
import os
from collections import Counter
from pathlib import Path

import pytest

from tests.conftest import ERD, PBD, SEEDS, erd_urdfs
from tests.test_graph_readers import first_page_png, svg_nodes
from urdftool.export.graph import dot_text, render_files
from urdftool.model import Robot
from urdftool.parse import read
from urdftool.parse.packages import PackageResolver
from urdftool.pipeline.discover import expand_paths

BATCHES = 4
#: pybullet_data's robots: URDFs outside random_urdfs/ with a moving joint or
#: at least three links (the rest are props: cubes, planes, tables, ...)
PYBULLET_ROBOTS = 45


def pybullet_urdfs() -> list[str]:
    assert PBD is not None, "pybullet is a test dependency"
    found = glob.glob(str(PBD / "**" / "*.urdf"), recursive=True)
    return sorted(p for p in found if not os.path.relpath(p, PBD).startswith("random_urdfs"))


def seed_files() -> list[str]:
    """The seed systems' standalone URDFs and xacros (fragments come in through includers)."""
    files = expand_paths([str(SEEDS)], PackageResolver.create(None, [str(SEEDS)]))
    return [f for f in files if f.endswith((".urdf", ".xacro"))]


def is_robot(robot: Robot | None) -> bool:
    return robot is not None and (
        any(j.type.is_moving for j in robot.joints) or len(robot.links) >= 3
    )


def expected_ids(robot: Robot) -> Counter[str]:
    """Node ids the diagram must have: ``link:NAME``/``joint:NAME``, repeats numbered ``#2``...

    As Graphviz reports them: the backslashes of a quoted id stay doubled.
    """
    ids: Counter[str] = Counter()
    joints = [*robot.joints, *(closure.joint for closure in robot.loop_closures)]
    for kind, names in (
        ("link", [lnk.name for lnk in robot.links]),
        ("joint", [j.name for j in joints]),
    ):
        for name, count in Counter(names).items():
            for n in range(1, count + 1):
                ids[f"{kind}:{name}" + (f"#{n}" if n > 1 else "")] += 1
    return Counter({key.replace("\\", "\\\\"): value for key, value in ids.items()})


def draw_and_check(robot: Robot, work: Path, stem: str) -> list[str]:
    """Draw *robot* to DOT, PDF and SVG in *work*; the problems found (empty when all is well)."""
    text = dot_text(robot)
    (work / f"{stem}.dot").write_text(text, encoding="utf-8")
    pdf, svg = work / f"{stem}.pdf", work / f"{stem}.svg"
    render_files(text, {pdf: "pdf", svg: "svg"})
    nodes = svg_nodes(svg.read_bytes())
    problems = []
    expected = expected_ids(robot)
    missing = sorted(set(expected) - set(nodes))
    if missing:
        problems.append(f"no node for {missing[:5]}")
    extra = sorted(n for n in set(nodes) - set(expected) if not n.startswith("missing:"))
    if extra:
        problems.append(f"unexpected nodes {extra[:5]}")
    for lnk in robot.links:
        node = nodes.get(f"link:{lnk.name}".replace("\\", "\\\\"))
        if node is not None and node[0] != (lnk.name or "(no name)"):
            problems.append(f"link '{lnk.name}' is labelled {node[0]!r}")
    if first_page_png(pdf, work).ink() <= 0.0005:
        problems.append("the PDF's first page is blank")
    return problems


def draw_batch(
    paths: list[str], tmp_path: Path, resolver: PackageResolver | None = None, select: bool = False
) -> int:
    """Draw every robot in *paths*; fail listing every robot with a problem; return the count."""
    failures, drawn = [], 0
    for index, path in enumerate(paths):
        for loaded in read(path, {}, resolver):
            # An empty robot is drawn too: a title that says so, with its finding.
            if loaded.robot is None or (select and not is_robot(loaded.robot)):
                continue
            try:
                problems = draw_and_check(loaded.robot, tmp_path, f"r{index}")
            except Exception as exc:  # report every robot, not just the first failure
                problems = [f"{type(exc).__name__}: {exc}"]
            drawn += 1
            failures += [f"{path}: {p}" for p in problems]
    assert not failures, "\n".join(failures)
    return drawn


def batch(paths: list[str], index: int) -> list[str]:
    return paths[index::BATCHES]


@pytest.mark.parametrize("index", range(BATCHES))
def test_example_robot_data(index: int, tmp_path: Path) -> None:
    paths = batch(erd_urdfs(), index)
    assert draw_batch(paths, tmp_path) == len(paths)  # every URDF there is a robot


@pytest.mark.parametrize("index", range(BATCHES))
def test_pybullet_data_robots(index: int, tmp_path: Path) -> None:
    draw_batch(batch(pybullet_urdfs(), index), tmp_path, select=True)


def test_pybullet_data_has_the_robots_we_count() -> None:
    robots = [p for p in pybullet_urdfs() if any(is_robot(m.robot) for m in read(p))]
    assert len(robots) == PYBULLET_ROBOTS


def test_seed_systems(tmp_path: Path) -> None:
    resolver = PackageResolver.create(None, [str(SEEDS)])
    drawn = draw_batch(seed_files(), tmp_path, resolver)
    # rrbot, my_robot, m_robot, 20 learning_ros files, 4 from TurtleBot3, 5 of the
    # uos_tools sensor macros (no links; drawn as empty robots); one_link_w_mass.urdf
    # is not well-formed XML and kinect.urdf.xacro does not expand alone.
    assert drawn >= 31


def test_corpora_are_installed() -> None:
    assert ERD is not None and len(erd_urdfs()) == 69
    assert SEEDS.is_dir()
