"""The CI slice of the planted-defect harness (benchmarks/recall/).

Plants every catalogue class that has a rule into every fourth real model of the corpus
(a few hundred mutants) and fails when recall or located drops below, or noise on the
unmutated twins rises above, the figures recorded by
``python benchmarks/recall/run.py --write docs/recall.md``.
"""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
HARNESS = ROOT / "benchmarks" / "recall"


def _harness():  # type: ignore[no-untyped-def]
    sys.path.insert(0, str(HARNESS))
    spec = importlib.util.spec_from_file_location("recall_run", HARNESS / "run.py")
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    sys.modules["recall_run"] = module
    spec.loader.exec_module(module)
    return module


def test_recall_slice_does_not_regress() -> None:
    run = _harness()
    recorded = json.loads((HARNESS / "recorded.json").read_text())["slice"]
    counts = run.measure(jobs=2, stride=recorded["stride"])
    now = run.figures(counts)
    assert now["overall"]["mutants"] >= 200, now["overall"]
    drops = []
    for cls, old in recorded["classes"].items():
        new = now["classes"].get(cls)
        if new is None:
            drops.append(f"{cls}: no longer planted")
            continue
        if new["found"] * old["mutants"] < old["found"] * new["mutants"]:
            drops.append(
                f"{cls}: found {new['found']}/{new['mutants']}, recorded {old['found']}/{old['mutants']}"
            )
        if new["located"] * old["mutants"] < old["located"] * new["mutants"]:
            drops.append(
                f"{cls}: located {new['located']}/{new['mutants']}, "
                f"recorded {old['located']}/{old['mutants']}"
            )
        if new["noisy"] > old["noisy"]:
            drops.append(f"{cls}: {new['noisy']} noisy twins, recorded {old['noisy']}")
    assert not drops, (
        "recall regressed (rerun benchmarks/recall/run.py --misses to see the mutants):\n"
        + "\n".join(drops)
    )
    assert now["overall"]["recall"] >= recorded["overall"]["recall"] - 1e-9
    assert now["overall"]["located"] >= recorded["overall"]["located"] - 1e-9
    assert now["overall"]["noisy_twins"] <= recorded["overall"]["noisy_twins"]


def test_reviewed_twins_name_real_models_and_rules() -> None:
    """Every model the review excludes from planting exists in the corpus the tests install (the
    real-world corpus is local only), under a rule that the harness plants."""
    run = _harness()
    import yaml

    codes = set(run.rule_codes().values())
    keys = {run.model_key(p) for p, _ in run.corpus()}
    review = yaml.safe_load(run.REVIEWED.read_text())
    for code, entry in review.items():
        assert code in codes, code
        assert entry["verdict"].startswith("genuine"), (code, entry["verdict"])
        for model in entry["models"]:
            assert model.startswith("realworld/") or model in keys, (code, model)
