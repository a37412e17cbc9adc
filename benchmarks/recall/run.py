"""Planted-defect harness: how many of the catalogue's defects urdftool finds, and where.

For every class of docs/defects/catalogue.yaml that has a rule and a mutation in
mutations.py, the defect is planted into each real model it applies to (example-robot-data,
pybullet_data, the URDFs of fixtures/seeds). Each mutant and its unmutated twin are checked
in-process with the class's rule and counted:

- found: the class's rule reports a finding on the mutant that it does not report on the twin;
- located: one of those findings is at the planted line of the mutant;
- noise: the rule reports an error or a warning on the unmutated twin that nobody reviewed.

A twin is a clean base for a class only when the class's rule is silent on it. A real model on
which the rule reports a defect that was reviewed as genuine (reviewed_twins.yaml: rule, model,
verdict) is not planted with that class: its findings are the model's own, and a precise rule
must keep reporting them. Such models are counted apart ("reviewed defects"); any other twin
finding is noise and fails the CI slice.

    python benchmarks/recall/run.py                       # print the table
    python benchmarks/recall/run.py --write docs/recall.md  # and record it (+ recorded.json)
    python benchmarks/recall/run.py --per-class 12        # the CI slice's sample
    python benchmarks/recall/run.py --realworld --write docs/recall-realworld.md
                                  # the URDF models of the real-world corpus, where it is present
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import shutil
import sys
import tempfile
from collections.abc import Iterable
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(HERE))

from mutations import MUTATIONS, NOT_PLANTED, _tree  # noqa: E402

from urdftool.diagnostics import Severity  # noqa: E402
from urdftool.parse import InputError  # noqa: E402
from urdftool.pipeline.check import CheckOptions, check_file  # noqa: E402

CATALOGUE = ROOT / "docs" / "defects" / "catalogue.yaml"
RECORDED = HERE / "recorded.json"
REVIEWED = HERE / "reviewed_twins.yaml"


def reviewed() -> dict[str, dict[str, Any]]:
    """rule code -> {"verdict": why its findings on these real models are genuine, "models": keys}."""
    data: dict[str, dict[str, Any]] = yaml.safe_load(REVIEWED.read_text())
    return data


def model_key(path: str) -> str:
    """A corpus model's name that does not depend on where the corpus is installed:
    ``example-robot-data/…``, ``pybullet_data/…``, ``seeds/…`` or ``realworld/…``."""
    sys.path.insert(0, str(ROOT / "tests"))
    from conftest import ERD, PBD

    here = Path(path).resolve()
    bases = (("example-robot-data", ERD), ("pybullet_data", PBD),
             ("seeds", ROOT / "fixtures" / "seeds"), ("realworld", ROOT / "fixtures" / "realworld"))
    for name, base in bases:
        if base is None:
            continue
        try:
            return f"{name}/{here.relative_to(Path(base).resolve()).as_posix()}"
        except ValueError:
            continue
    return here.name


def rule_codes() -> dict[str, str]:
    """class id -> code of its existing rule, for the statically visible classes that have one."""
    classes = yaml.safe_load(CATALOGUE.read_text())["classes"]
    return {
        c["id"]: c["existing_rule"].split()[0]
        for c in classes
        if c.get("existing_rule") and c["visible_in_files"].get("visible")
    }


def unruled() -> list[str]:
    classes = yaml.safe_load(CATALOGUE.read_text())["classes"]
    return [c["id"] for c in classes if not c.get("existing_rule") and c["visible_in_files"].get("visible")]


def corpus() -> list[tuple[str, Path | None]]:
    """(model path, folder that package:// URIs of example-robot-data resolve to)."""

    sys.path.insert(0, str(ROOT / "tests"))
    from conftest import ERD, erd_urdfs, pybullet_robots

    out: list[tuple[str, Path | None]] = [(p, ERD.parent if ERD else None) for p in erd_urdfs()]
    out += [(p, None) for p in pybullet_robots()]
    out += [(str(p), None) for p in sorted((ROOT / "fixtures" / "seeds").rglob("*.urdf"))]

    return out


def _mirror(original: str, work: Path) -> Path:
    """A folder in *work* that shows the original's folder and its parent's entries (for relative meshes)."""
    src = Path(original).resolve().parent
    top = work / "p"
    here = top / "d"
    here.mkdir(parents=True)
    for entry in src.parent.iterdir():
        if entry != src:
            (top / entry.name).symlink_to(entry)
    for entry in src.iterdir():
        if entry.is_file() and entry.suffix.lower() in (".urdf", ".xacro", ".srdf", ".sdf"):
            continue
        (here / entry.name).symlink_to(entry)
    return here


def _findings(
    path: Path, codes: Iterable[str], packages: dict[str, str], package_paths: tuple[str, ...] = ()
) -> list[tuple[str, str, int | None, str]]:
    options = CheckOptions(
        select=tuple(codes), rule_options={"dynamics": False}, packages=packages,
        package_paths=package_paths, discover_srdf=False,
    )
    try:
        reports = check_file(str(path), options)
    except InputError:
        return []
    out = []
    for report in reports:
        for d in report.diagnostics:
            line = d.location.line if d.location and os.path.samefile(d.location.path, path) else None
            out.append((d.code, d.message, line, d.severity.value))
    return out


def accepted_lines(mutated: str, line: int) -> set[int]:
    """Lines where a finding counts as located: the planted line, the rest of the element that
    starts there (a <limit> inside the planted <joint>) and the opening lines of its ancestors
    (the <link> whose <mass> was planted); never the <robot> line unless that was planted."""
    lines = {line}
    root = _tree(mutated)
    if root is None:
        return lines
    element = next((e for e in root.iter() if isinstance(e.tag, str) and e.sourceline == line), None)
    if element is None:
        return lines
    lines.update(int(e.sourceline) for e in element.iter() if isinstance(e.tag, str) and e.sourceline)
    lines.update(int(a.sourceline) for a in element.iterancestors() if a.getparent() is not None)
    return lines


@dataclass
class Counts:
    mutants: int = 0
    found: int = 0
    located: int = 0
    twins: int = 0
    noisy: int = 0
    excluded: int = 0
    misses: list[str] = field(default_factory=list)
    noisy_models: set[str] = field(default_factory=set)
    excluded_models: set[str] = field(default_factory=set)


def run_model(args: tuple[Any, ...]) -> list[dict[str, Any]]:
    """Every mutant of one model: [{class, found, located, noisy}]."""
    path, erd, classes, _ = args[:4]
    package_paths: tuple[str, ...] = args[4] if len(args) > 4 else ()
    xacro_args: dict[str, str] = args[5] if len(args) > 5 else {}
    codes = rule_codes()
    genuine = {code: set(entry["models"]) for code, entry in reviewed().items()}
    key = model_key(path)
    if path.endswith(".xacro"):
        urdf = expanded(path, package_paths, xacro_args)
        if urdf is None:
            return []
        text = urdf
    else:
        text = Path(path).read_text(errors="replace")
    packages = {"example-robot-data": erd} if erd else {}
    results = []
    with tempfile.TemporaryDirectory(prefix="recall-") as tmp:
        folder = _mirror(path, Path(tmp))
        name = Path(path).with_suffix(".urdf").name
        twin = folder / name
        twin.write_text(text)
        wanted = sorted({codes[c] for c in classes})
        twin_findings = _findings(twin, wanted, packages, package_paths)
        mutant = folder / ("planted_" + name)
        for cls in classes:
            planted = MUTATIONS[cls](text)
            if planted is None or planted[0] == text:
                continue
            mutated, line = planted
            code = codes[cls]
            noisy = any(
                c == code and sev in (Severity.ERROR.value, Severity.WARNING.value)
                for c, _, _, sev in twin_findings
            )
            if noisy and key in genuine.get(code, ()):
                results.append({"class": cls, "model": path, "key": key, "excluded": True})
                continue
            mutant.write_text(mutated)
            before = collections.Counter((c, m) for c, m, _, _ in twin_findings if c == code)
            new = []
            for c, m, at, _ in _findings(mutant, [code], packages, package_paths):
                if c != code:
                    continue
                if before[(c, m)]:
                    before[(c, m)] -= 1
                else:
                    new.append(at)
            results.append(
                {
                    "class": cls,
                    "model": path,
                    "key": key,
                    "excluded": False,
                    "found": bool(new),
                    "located": bool(accepted_lines(mutated, line) & set(new)),
                    "noisy": noisy,
                    "line": line,
                }
            )
        shutil.rmtree(folder.parent, ignore_errors=True)
    return results


#: the CI slice (tests/test_recall.py) plants into every SLICE_STRIDE-th model of the corpus
SLICE_STRIDE = 4


def realworld_corpus() -> list[tuple[str, tuple[str, ...], dict[str, str]]]:
    """The URDF and xacro models of the real-world corpus (docs/realworld-manifest.yaml) present
    on this machine under fixtures/realworld, with their package folders and xacro arguments;
    empty on a bare clone (the corpus cannot be committed). A xacro model is planted in the URDF
    it expands to (what robot_state_publisher receives), written beside the xacro file."""
    root = ROOT / "fixtures" / "realworld"
    manifest = yaml.safe_load((ROOT / "docs" / "realworld-manifest.yaml").read_text())["models"]
    out = []
    for entry in manifest:
        path = root / entry["path"]
        if path.suffix in (".urdf", ".xacro") and path.is_file():
            out.append((str(path), tuple(str(root / p) for p in entry.get("package_paths") or ()),
                        {str(k): str(v) for k, v in (entry.get("xacro_args") or {}).items()}))
    return out


def expanded(path: str, package_paths: tuple[str, ...], args: dict[str, str]) -> str | None:
    """The URDF text a xacro model expands to, or None when it does not expand."""
    from lxml import etree

    from urdftool.parse.packages import PackageResolver
    from urdftool.parse.xacro import expand
    from urdftool.source import SRC_ATTRIBUTE

    result = expand(path, PackageResolver.create(package_paths=package_paths), args)
    if result.document is None or result.macro_library:
        return None
    root = result.document.root
    for node in root.iter():  # urdftool's source stamps are not part of the URDF
        if isinstance(node.tag, str):
            node.attrib.pop(SRC_ATTRIBUTE, None)
    etree.indent(root, space="  ")  # one element a line, as `xacro` writes it
    return '<?xml version="1.0"?>\n' + etree.tostring(root, encoding="unicode") + "\n"


def measure(
    per_class: int | None = None, jobs: int = 2, classes: Iterable[str] | None = None, stride: int = 1,
    realworld: bool = False,
) -> dict[str, Counts]:
    codes = rule_codes()
    chosen = tuple(c for c in (classes or MUTATIONS) if c in codes)
    if realworld:
        work: list[tuple[Any, ...]] = [
            (p, None, chosen, i, paths, xargs)
            for i, (p, paths, xargs) in enumerate(realworld_corpus()[::stride])]
    else:
        models = corpus()[::stride]
        work = [(p, str(erd) if erd else None, chosen, i) for i, (p, erd) in enumerate(models)]
    if jobs > 1:
        with ProcessPoolExecutor(jobs) as pool:
            rows = [r for part in pool.map(run_model, work, chunksize=4) for r in part]
    else:
        rows = [r for w in work for r in run_model(w)]
    counts: dict[str, Counts] = {c: Counts() for c in chosen}
    taken: collections.Counter[str] = collections.Counter()
    for row in rows:
        cls = row["class"]
        k = counts[cls]
        if row["excluded"]:
            k.excluded += 1
            k.excluded_models.add(row["key"])
            continue
        if per_class is not None and taken[cls] >= per_class:
            continue
        taken[cls] += 1
        k.mutants += 1
        k.found += row["found"]
        k.located += row["located"]
        k.twins += 1
        k.noisy += row["noisy"]
        if row["noisy"]:
            k.noisy_models.add(row["key"])
        if not row["located"]:
            model = row["model"]
            shown = os.path.relpath(model, ROOT) if model.startswith(str(ROOT)) else Path(model).name
            k.misses.append(f"{shown}:{row['line']}")
    return counts


def totals(counts: dict[str, Counts]) -> dict[str, float]:
    mutants = sum(k.mutants for k in counts.values())
    return {
        "mutants": mutants,
        "recall": sum(k.found for k in counts.values()) / mutants if mutants else 0.0,
        "located": sum(k.located for k in counts.values()) / mutants if mutants else 0.0,
        "noisy_twins": sum(k.noisy for k in counts.values()),
        "reviewed_twins": sum(k.excluded for k in counts.values()),
    }


def pct(a: int, b: int) -> str:
    return f"{100 * a / b:.0f} %" if b else "–"


def table(counts: dict[str, Counts]) -> str:
    codes = rule_codes()
    lines = [
        "# Recall on planted defects",
        "",
        "Generated by `python benchmarks/recall/run.py --write docs/recall.md`; do not edit by hand.",
        "How a class is measured: "
        "[docs/defects/README.md](defects/README.md#how-the-recall-harness-measures-a-class).",
        "",
        "| class | rule | mutants | found | located | noisy twins | reviewed defects |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    for cls, k in sorted(counts.items()):
        lines.append(
            f"| [{cls}](defects/{cls}.md) | {codes[cls]} | {k.mutants} | {pct(k.found, k.mutants)} "
            f"| {pct(k.located, k.mutants)} | {k.noisy} | {k.excluded} |"
        )
    t = totals(counts)
    review = reviewed()
    by_rule: dict[str, set[str]] = collections.defaultdict(set)
    for cls, k in counts.items():
        by_rule[codes[cls]] |= k.excluded_models
    noisy = sorted({(codes[cls], m) for cls, k in counts.items() for m in k.noisy_models})
    lines += [
        f"| **all** | | {t['mutants']} | {100 * t['recall']:.1f} % | {100 * t['located']:.1f} % "
        f"| {t['noisy_twins']} | {t['reviewed_twins']} |",
        "",
        "A twin is noisy when the class's rule reports an error or a warning on the unmutated model",
        "and nobody has reviewed that finding; the column counts such mutants, and the CI slice",
        "fails when it rises. Noisy twins now:",
        "",
        *([f"- {code}: {model} (NOT REVIEWED)" for code, model in noisy] or ["- none"]),
        "",
        "## Real models not planted with a class: their own reviewed defects",
        "",
        "A real model on which the class's rule already reports a defect is not a clean twin for",
        "that class: a precise rule must keep reporting the model's own defect, and a finding there",
        "says nothing about the plant. Each such finding was reviewed (benchmarks/recall/",
        "reviewed_twins.yaml); the column \"reviewed defects\" counts the plants left out for it.",
        "",
    ]
    for code in sorted(by_rule):
        models = sorted(by_rule[code])
        if models:
            lines += [f"- {code} ({len(models)} models): {review[code]['verdict']}",
                      "  " + ", ".join(f"`{m}`" for m in models)]
    lines += [
        "",
        "## Classes with a rule that are not planted yet",
        "",
        *[f"- {c}: {why}" for c, why in sorted(NOT_PLANTED.items())],
        "",
        "## Statically visible classes with no rule yet",
        "",
        *[f"- [{c}](defects/{c}.md)" for c in unruled()],
        "",
    ]
    return "\n".join(lines)


def figures(counts: dict[str, Counts]) -> dict[str, Any]:
    return {
        "overall": totals(counts),
        "classes": {
            c: {"mutants": k.mutants, "found": k.found, "located": k.located, "noisy": k.noisy,
                "reviewed": k.excluded}
            for c, k in sorted(counts.items())
        },
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument(
        "--write", metavar="MD", help="write the table there and the figures to recorded.json"
    )
    parser.add_argument("--per-class", type=int, default=None, help="at most this many mutants per class")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--misses", action="store_true", help="list the mutants not found at their line")
    parser.add_argument("--realworld", action="store_true",
                        help="plant into the URDF models of fixtures/realworld (local only; with --write, "
                        "only the table is written, recorded.json is the vendored corpus's)")
    args = parser.parse_args(argv)
    counts = measure(args.per_class, args.jobs, realworld=args.realworld)
    text = table(counts)
    if args.realworld:
        title = "# Recall on planted defects"
        text = text.replace(title, title + ": the real-world corpus", 1).replace(
            "`python benchmarks/recall/run.py --write docs/recall.md`",
            "`python benchmarks/recall/run.py --realworld --write docs/recall-realworld.md` on a "
            "machine with the corpus beside the tree (docs/realworld.md; its URDF models)", 1)
    print(text)
    if args.misses:
        for cls, k in sorted(counts.items()):
            for miss in k.misses:
                print(f"miss {cls} {miss}")
    if args.write and args.realworld:
        Path(args.write).write_text(text)
    elif args.write:
        Path(args.write).write_text(text)
        ci = measure(jobs=args.jobs, stride=SLICE_STRIDE)
        record = {"full": figures(counts), "slice": {"stride": SLICE_STRIDE, **figures(ci)}}
        RECORDED.write_text(json.dumps(record, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
