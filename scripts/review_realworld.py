#!/usr/bin/env python3
"""Check every model of the real-world corpus and compare its errors with the reviewed verdicts.

Usage: python3 scripts/review_realworld.py [--no-dynamics] [--only TEXT] [--save DIR]

The corpus (docs/realworld.md) is not in the repository: it lives beside the working tree
and ``fixtures/realworld`` points at it. Models of docs/realworld-manifest.yaml that are not
on disk are skipped and counted. Each model is checked the way a user checks it, with
``urdftool check --format json --isolated``, the manifest's ``package_paths`` as
``--package-path``, its ``xacro_args`` as ``-a`` and its ``env`` (what the upstream's setup
script exports for xacro's ``$(optenv …)``) in the environment; one process per model, so a
crash in one model does not hide the others.

Every error finding is then sorted into:

- expected: listed under ``expected`` (reviewed as a genuine defect of the upstream file);
- omitted: ``mesh-not-found`` for a mesh listed under ``omitted_meshes`` (not vendored), or
  ``mesh-unreadable`` for one listed there whose companion file was not vendored (a glTF
  without its ``.bin`` buffer);
- known false: listed under ``known_false`` (a false error that was fixed: seeing it again
  is a regression, so it is reported with the unexpected ones);
- unexpected: anything else, to be reviewed by hand.

Expected errors that no longer appear are listed too (the rule or the verdict changed).
The report ends with the warning counts per rule over the corpus. Exit status 1 when a
finding is unexpected or a model could not be checked.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import subprocess
import sys
import time
from collections import Counter
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

ROOT = Path(__file__).resolve().parent.parent
MANIFEST = ROOT / "docs" / "realworld-manifest.yaml"
CORPUS = ROOT / "fixtures" / "realworld"


@dataclass
class Review:
    """One model's errors sorted against its manifest entry."""

    model: str
    errors: int = 0
    expected: list[dict[str, Any]] = field(default_factory=list)
    omitted: list[dict[str, Any]] = field(default_factory=list)
    known_false: list[dict[str, Any]] = field(default_factory=list)
    unexpected: list[dict[str, Any]] = field(default_factory=list)
    #: (code, element, what became of it) for expected errors the check no longer reports as errors
    vanished: list[tuple[str, str, str]] = field(default_factory=list)
    #: why the model could not be checked (a crash, bad JSON), else None
    failure: str | None = None


def label(entry: Mapping[str, Any]) -> str:
    """The model's path with its xacro arguments and environment, as docs/realworld.md writes it."""
    args = " ".join(f"{k}:={v}" for k, v in (entry.get("xacro_args") or {}).items())
    env = " ".join(f"{k}={v}" for k, v in (entry.get("env") or {}).items())
    return str(entry["path"]) + (f" [{args}]" if args else "") + (f" (env {env})" if env else "")


def environment(entry: Mapping[str, Any]) -> dict[str, str]:
    """The environment to check one model in: this process's, plus the entry's ``env``."""
    return {**os.environ, **{str(k): str(v) for k, v in (entry.get("env") or {}).items()}}


def command(entry: Mapping[str, Any], corpus: Path, dynamics: bool) -> list[str]:
    """The ``urdftool check`` command line for one manifest entry."""
    argv = [sys.executable, "-m", "urdftool", "check", str(corpus / entry["path"]),
            "--format", "json", "--exit-zero", "--isolated"]
    for folder in entry.get("package_paths") or ():
        argv += ["--package-path", str(corpus / folder)]
    for name, value in (entry.get("xacro_args") or {}).items():
        argv += ["-a", f"{name}:={value}"]
    for key, flag in (("srdf", "--srdf"), ("controllers", "--controllers")):
        if entry.get(key):  # a configuration the discovery cannot pair with the model
            argv += [flag, str(corpus / entry[key])]
    if not dynamics:
        argv.append("--no-dynamics")
    return argv


def diagnostics(report: Mapping[str, Any]) -> list[dict[str, Any]]:
    """Every diagnostic of a JSON report, each with the robot it belongs to."""
    return [{**d, "robot": f.get("robot")} for f in report.get("files", ()) for d in f.get("diagnostics", ())]


def _mesh_key(path: str, corpus: Path) -> str:
    """A mesh path relative to the corpus root (the manifest's spelling), if it is below it."""
    for base in (str(corpus), os.path.realpath(corpus)):
        if path.startswith(base + os.sep):
            return path[len(base) + 1:]
    return path


#: Errors a mesh that is not vendored, or vendored without its companion files, gives.
_OMISSION_FINDINGS = frozenset({"mesh-not-found", "mesh-unreadable"})


def review(entry: Mapping[str, Any], found: Iterable[Mapping[str, Any]], corpus: Path) -> Review:
    """Sort the error findings of one model against its manifest entry (pure; no I/O)."""
    result = Review(label(entry))
    expected = Counter((e["code"], e["element"]) for e in entry.get("expected") or ())
    known_false = Counter((e["code"], e["element"]) for e in entry.get("known_false") or ())
    omitted = set(entry.get("omitted_meshes") or ())
    found = list(found)
    for d in found:
        if d.get("severity") != "error":
            continue
        result.errors += 1
        key = (d["code"], d.get("element") or "")
        path = (d.get("data") or {}).get("path")
        if expected[key] > 0:
            expected[key] -= 1
            result.expected.append(dict(d))
        elif d.get("name") in _OMISSION_FINDINGS and path and _mesh_key(path, corpus) in omitted:
            result.omitted.append(dict(d))
        elif known_false[key] > 0:
            known_false[key] -= 1
            result.known_false.append(dict(d))
        else:
            result.unexpected.append(dict(d))
    result.vanished = [(code, element, _became(code, element, found))
                       for (code, element), n in sorted(expected.items()) for _ in range(n)]
    return result


def _became(code: str, element: str, found: Sequence[Mapping[str, Any]]) -> str:
    """What became of an expected error the check no longer reports as an error."""
    for d in found:
        if d["code"] == code and (d.get("element") or "") == element:
            return f"now {d.get('severity')}"
    if code in {"I001", "D001"} and any(d["code"] == "I011" for d in found):
        return "kinematic model: one I011 instead"
    return "gone"


def report_name(entry: Mapping[str, Any]) -> str:
    """The file name ``--save`` gives a model's JSON report: its label with ``/`` and spaces
    replaced, shortened with a digest when it would pass the 255 bytes file systems allow (a
    model with many xacro arguments, such as RotorS's fixed wing)."""
    name = label(entry).replace("/", "__").replace(" ", "_")
    if len(name.encode("utf-8")) > 200:
        digest = hashlib.sha1(name.encode("utf-8")).hexdigest()[:12]
        name = name.encode("utf-8")[:180].decode("utf-8", "ignore") + "_" + digest
    return f"{name}.json"


def check(entry: Mapping[str, Any], corpus: Path, dynamics: bool, save: Path | None) -> tuple[Review, list]:
    """Run urdftool on one model; its review and all its diagnostics."""
    run = subprocess.run(command(entry, corpus, dynamics), capture_output=True, text=True,
                         cwd=ROOT, env=environment(entry), check=False, timeout=1800)
    if save is not None:
        (save / report_name(entry)).write_text(run.stdout)
    try:
        found = diagnostics(json.loads(run.stdout))
    except json.JSONDecodeError:
        failed = Review(label(entry), failure=f"exit {run.returncode}: {run.stderr.strip()[-500:]}")
        return failed, []
    return review(entry, found, corpus), found


def table(reviews: Sequence[Review]) -> str:
    """A Markdown table: model, errors found, expected, unexpected (code, element, message)."""
    rows = ["| model | errors | expected | omitted mesh | unexpected | expected, not found |",
            "|---|---:|---:|---:|---|---|"]
    for r in reviews:
        if r.failure:
            rows.append(f"| `{r.model}` | – | – | – | check failed: {r.failure} | |")
            continue
        bad = [*r.unexpected, *r.known_false]
        unexpected = "<br>".join(
            f"{d['code']} `{d.get('element')}`: {d['message']}"
            + (" (known false: regression)" if d in r.known_false else "") for d in bad)
        vanished = ", ".join(f"{c} `{e}` ({why})" for c, e, why in r.vanished)
        rows.append(f"| `{r.model}` | {r.errors} | {len(r.expected)} | {len(r.omitted)} "
                    f"| {unexpected or '0'} | {vanished} |")
    return "\n".join(rows)


def warning_counts(found: Mapping[str, list], top: int) -> str:
    """Warnings per rule over the corpus: findings and models, the *top* rules by findings."""
    findings: Counter[str] = Counter()
    models: Counter[str] = Counter()
    for diags in found.values():
        codes = [f"{d['code']} {d['name']}" for d in diags if d.get("severity") == "warning"]
        findings.update(codes)
        models.update(set(codes))
    rows = ["| rule | warnings | models |", "|---|---:|---:|"]
    rows += [f"| {rule} | {n} | {models[rule]} |" for rule, n in findings.most_common(top)]
    return "\n".join(rows)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--manifest", type=Path, default=MANIFEST)
    parser.add_argument("--corpus", type=Path, default=CORPUS, help="where the manifest's paths start")
    parser.add_argument("--no-dynamics", action="store_true", help="skip the Pinocchio dynamics pass")
    parser.add_argument("--only", default="", help="only models whose path contains this text")
    parser.add_argument("--save", type=Path, help="write each model's JSON report into this folder")
    parser.add_argument("--top", type=int, default=15, help="rules in the warning table")
    args = parser.parse_args(argv)

    entries = yaml.safe_load(args.manifest.read_text())["models"]
    present = [e for e in entries if args.only in e["path"] and (args.corpus / e["path"]).is_file()]
    absent = [label(e) for e in entries if args.only in e["path"] and e not in present]
    if args.save:
        args.save.mkdir(parents=True, exist_ok=True)
    reviews: list[Review] = []
    found: dict[str, list] = {}
    for index, entry in enumerate(present, 1):
        start = time.monotonic()
        result, diags = check(entry, args.corpus, not args.no_dynamics, args.save)
        reviews.append(result)
        found[result.model] = diags
        print(f"[{index}/{len(present)}] {result.model}: {result.errors} error(s), "
              f"{len(result.unexpected) + len(result.known_false)} unexpected "
              f"({time.monotonic() - start:.1f} s)", file=sys.stderr)

    mode = "--no-dynamics" if args.no_dynamics else "default check (dynamics included)"
    print(f"# Real-world corpus review: {mode}\n")
    print(f"{len(present)} of {len(present) + len(absent)} models on disk under {args.corpus}")
    for model in absent:
        print(f"- not on disk: `{model}`")
    clean = sum(1 for r in reviews if not r.failure and r.errors == len(r.expected) + len(r.omitted))
    print(f"{clean} models have no error beyond the reviewed ones\n")
    print(table(reviews))
    print("\n## Warnings per rule\n")
    print(warning_counts(found, args.top))
    return 1 if any(r.failure or r.unexpected or r.known_false for r in reviews) else 0


if __name__ == "__main__":
    sys.exit(main())
