"""The dynamics pass on large models: linear-time gravity loads instead of a DOF³ Pinocchio Data."""

from __future__ import annotations

import resource
import time
from pathlib import Path

import pytest

import urdftool
from tests.conftest import erd_urdfs
from tests.scale_models import chain_urdf
from urdftool.facts.dynamics.analysis import analyse
from urdftool.facts.dynamics.coverage import floating_base, not_covered
from urdftool.facts.dynamics.linear import DENSE_DOF, gravity_loads
from urdftool.model import KinematicTree


def _fixed_base_arms() -> list[str]:
    out = []
    for path in erd_urdfs():
        robot = urdftool.load(path)
        tree = KinematicTree.of(robot)
        if robot.links and not_covered(robot, tree) is None and not floating_base(robot, tree)[0] \
                and not robot.loop_closures and tree.joints_in_order:
            out.append(path)
    return out


@pytest.mark.parametrize("path", _fixed_base_arms(), ids=lambda p: Path(p).name)
def test_linear_gravity_loads_match_pinocchio(path: str) -> None:
    robot = urdftool.load(path)
    tree = KinematicTree.of(robot)
    dense = {g.joint.name: g for g in analyse(robot, tree, False, "", 8).gravity}
    linear = {g.joint.name: g for g in gravity_loads(robot, tree, False, "", 8).gravity}
    assert dense.keys() == linear.keys()
    for name, load in dense.items():
        assert linear[name].torque == pytest.approx(load.torque, rel=1e-9, abs=1e-9), name


def test_a_thousand_link_chain_is_checked_in_linear_memory(tmp_path: Path) -> None:
    path = tmp_path / "chain.urdf"
    path.write_text(chain_urdf(1000, "revolute"))
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    started = time.perf_counter()
    report = urdftool.check(path, select=["D"])
    elapsed = time.perf_counter() - started
    grown_mb = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) / 1024
    notes = [d for d in report.diagnostics if d.code == "D004"]
    assert len(notes) == 1 and notes[0].data["reason"] == "size" and notes[0].data["limit"] == DENSE_DOF
    assert "gravity loads checked" in notes[0].message
    # Generous bounds for a shared CI machine; benchmarks/bench_scale.py measures the real figures.
    assert elapsed < 60 and grown_mb < 1000, (elapsed, grown_mb)
