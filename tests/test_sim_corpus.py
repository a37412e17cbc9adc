"""Every model of example-robot-data and pybullet_data gets a verdict from both engines.

One test per file, with a short run (0.5 s of simulated time) to keep the
corpus affordable in CI; the full 2 s runs and their verdicts are in
docs/sim.md. A model either runs in an engine (and gets a ``sim-summary``
verdict with finite numbers) or is refused by that engine's exporter with
located findings; no model may crash urdftool.
"""

from __future__ import annotations

import glob
import math

import pytest

from tests.conftest import ERD, PBD, erd_urdfs, pybullet_robots, relative
from urdftool.diagnostics import Severity
from urdftool.facts.simulation.scene import SimOptions
from urdftool.parse import read
from urdftool.parse.packages import PackageResolver
from urdftool.pipeline.simulate import simulate_robot

SHORT = SimOptions(duration=0.5)


def corpus() -> list[str]:
    assert ERD is not None
    return [*erd_urdfs(), *sorted(glob.glob(str(ERD / "**" / "*.sdf"), recursive=True)), *pybullet_robots()]


def label(path: str) -> str:
    return relative(path, ERD) if ERD and path.startswith(str(ERD)) else relative(path, PBD)


@pytest.mark.parametrize("path", corpus(), ids=label)
def test_model_gets_a_verdict_or_the_exporters_reasons(path: str) -> None:
    for loaded in read(path, {}, PackageResolver.create()):
        if loaded.robot is None or not loaded.robot.links:
            continue
        report = simulate_robot(loaded.robot, SHORT)
        assert not [d for d in report.diagnostics if d.code == "S000"], report.diagnostics
        verdicts = {d.data["engine"]: d for d in report.diagnostics if d.code == "R005"}
        assert set(verdicts) == {"mujoco", "pybullet"}
        for engine, verdict in verdicts.items():
            summary = verdict.data["summary"]
            if summary["ran"]:
                assert math.isfinite(summary["energy_initial"]) and summary["steps"] > 0, engine
            else:
                refusals = [
                    d for d in report.diagnostics if d.code != "R005" and d.severity is Severity.ERROR
                ]
                assert refusals and all(d.location is not None for d in refusals), (engine, verdict.message)
