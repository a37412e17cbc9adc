"""check_many on any concurrent.futures executor: a process pool and a Dask distributed cluster."""

from __future__ import annotations

import pickle
from concurrent.futures import ProcessPoolExecutor

import distributed
import pytest

import urdftool
from tests.conftest import FIXTURES

RULES = FIXTURES / "rules"


def _corpus() -> list[str]:
    return sorted(str(p) for p in RULES.glob("[SJI]0*/bad.urdf"))[:12]


def _summary(reports: list[urdftool.Report]) -> list[tuple[str, tuple[str, ...]]]:
    return [(f.path, tuple(d.code for d in f.diagnostics)) for r in reports for f in r.files]


def test_without_an_executor_and_on_a_process_pool_the_reports_agree() -> None:
    paths = _corpus()
    here = urdftool.check_many(paths, select=["S", "J", "I"])
    with ProcessPoolExecutor(max_workers=2) as pool:
        pooled = urdftool.check_many(paths, pool, select=["S", "J", "I"])
    assert _summary(here) == _summary(pooled) and len(here) == len(paths)
    assert pickle.loads(pickle.dumps(here)) == here  # plain, picklable results


def test_on_a_dask_local_cluster() -> None:
    paths = _corpus()
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        reports = urdftool.check_many(paths, client.get_executor(), select=["S", "J", "I"])
    assert _summary(reports) == _summary(urdftool.check_many(paths, select=["S", "J", "I"]))


def test_a_bad_selector_fails_before_any_work_is_sent() -> None:
    with pytest.raises(ValueError, match="nonsense"):
        urdftool.check_many(_corpus(), select=["nonsense"])
