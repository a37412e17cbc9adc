"""Fuzzing the readers, the checker and the exporters with mutated fixtures.

The CI slice runs a fixed, derandomized set of cases (``FUZZ_CASES``, default
2,000 over three tests) in a few minutes. For a longer run::

    URDFTOOL_FUZZ_CASES=20000 URDFTOOL_FUZZ_SEED=12345 \\
        python -m pytest tests/fuzz -q -p no:cacheprovider

The profile ``urdftool-ci`` is derandomized (the same cases on every run);
setting ``URDFTOOL_FUZZ_SEED`` switches to a seeded random run instead.
"""

from __future__ import annotations

import os
import tempfile
import warnings
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, seed, settings

from tests.fuzz.harness import applied_env, isolated_env, run_case
from tests.fuzz.mutations import SEEDS, Case, cases

TOTAL = int(os.environ.get("URDFTOOL_FUZZ_CASES", "2001"))
SEED = os.environ.get("URDFTOOL_FUZZ_SEED")

settings.register_profile(
    "urdftool-ci",
    max_examples=TOTAL // 3,
    deadline=None,  # the harness enforces its own per-case budget
    derandomize=SEED is None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.filter_too_much],
    print_blob=True,
)


def _seeds(*suffixes: str) -> list[Path]:
    return [p for p in SEEDS if p.name.endswith(suffixes)]


def _check(case: Case) -> None:
    with (applied_env(isolated_env()), tempfile.TemporaryDirectory(prefix="urdftool-fuzz-") as tmp,
          warnings.catch_warnings()):
        warnings.simplefilter("ignore")  # third-party readers warn on broken meshes; not under test
        problems = run_case(case, Path(tmp))
    assert not problems, f"{case!r}: {problems}"


def _seeded(test):  # type: ignore[no-untyped-def]
    return seed(int(SEED))(test) if SEED is not None else test


@pytest.mark.fuzz
@_seeded
@settings(settings.get_profile("urdftool-ci"))
@given(cases(_seeds(".urdf")))
def test_fuzz_urdf(case: Case) -> None:
    _check(case)


@pytest.mark.fuzz
@_seeded
@settings(settings.get_profile("urdftool-ci"))
@given(cases(_seeds(".xacro")))
def test_fuzz_xacro(case: Case) -> None:
    _check(case)


@pytest.mark.fuzz
@_seeded
@settings(settings.get_profile("urdftool-ci"))
@given(cases(_seeds(".sdf", ".world")))
def test_fuzz_sdf(case: Case) -> None:
    _check(case)
