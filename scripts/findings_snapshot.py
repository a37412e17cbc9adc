#!/usr/bin/env python3
"""Write every finding urdftool reports over the corpora to one JSON file, for before/after diffs.

Usage: python3 scripts/findings_snapshot.py OUT.json [--quick] [--digits N]

A change meant to make urdftool faster, or to restructure it, must not change what it reports.
Run this on the commit before and after the change and compare the two files (``diff`` or
``cmp``): every finding of the structural check (``--select S,X``) and of the default check
without the dynamics pass, with its code, severity, location, message, help and ``data``, over
example-robot-data, pybullet_data, the vendored seeds, every rule fixture and, when it is on
disk, the real-world corpus (docs/realworld.md). ``--quick`` leaves out the real-world corpus.
``--digits N`` writes the floats of ``data`` with N significant digits: for a change that computes
a measurement in another, equally exact order (plain floats instead of NumPy), whose last digits
may move while every code, location, message and help must stay the same.

Runs in one process through the Python API, so it takes a few minutes, not the corpus review's
twenty. Paths are written relative to the installed packages, the real-world corpus or the
checkout, so two checkouts sharing one environment can be compared; compare runs of one
checkout to be exact, since findings from several files sort by their absolute paths.
"""

from __future__ import annotations

import glob
import json
import os
import sys
import sysconfig
import warnings
from pathlib import Path
from typing import Any

import yaml

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.conftest import erd_urdfs  # noqa: E402
from urdftool.parse import InputError  # noqa: E402
from urdftool.pipeline.check import CheckOptions, check_file  # noqa: E402

MANIFEST = ROOT / "docs" / "realworld-manifest.yaml"
CORPUS = ROOT / "fixtures" / "realworld"
MODEL_SUFFIXES = (".urdf", ".xacro", ".sdf", ".world")


def _files() -> list[tuple[str, dict[str, Any]]]:
    """(path, CheckOptions keywords) of every model to check, in a fixed order."""
    import pybullet_data

    files: list[tuple[str, dict[str, Any]]] = [(p, {}) for p in erd_urdfs()]
    files += [(p, {}) for p in sorted(glob.glob(os.path.join(pybullet_data.getDataPath(), "**", "*.urdf"),
                                                recursive=True))]
    for folder in ("fixtures/seeds", "fixtures/rules"):
        files += [(str(p), {}) for p in sorted((ROOT / folder).rglob("*"))
                  if p.suffix in MODEL_SUFFIXES and p.is_file()]
    if "--quick" not in sys.argv and CORPUS.is_dir():
        for entry in yaml.safe_load(MANIFEST.read_text())["models"]:
            path = CORPUS / entry["path"]
            if path.is_file():
                files.append((str(path), {
                    "package_paths": tuple(str(CORPUS / p) for p in entry.get("package_paths", ())),
                    "xacro_args": {k: str(v) for k, v in (entry.get("xacro_args") or {}).items()},
                    # what the upstream's setup script exports for xacro's $(optenv ...)
                    "env": {k: str(v) for k, v in (entry.get("env") or {}).items()}}))
    return files


def _bases() -> tuple[str, ...]:
    """Folders whose paths are written relative: the installed packages first (the corpora from
    PyPI, wherever the environment is), then the real-world corpus and the checkout."""
    folders = (sysconfig.get_paths()["purelib"], str(CORPUS.resolve()), str(ROOT))
    return tuple(os.path.realpath(folder) + os.sep for folder in folders)


BASES = _bases()


def _relative(path: str) -> str:
    path = os.path.realpath(path)
    for base in BASES:
        if path.startswith(base):
            return path[len(base):]
    return os.path.basename(path)


def _findings(path: str, options: CheckOptions) -> list[str]:
    try:
        reports = check_file(path, options)
    except InputError as error:
        return [f"InputError {error}"]
    # data as --format json writes it: a change that moves the last digit of a number there
    # changes what users' scripts read. Paths in any text are made relative.
    return [_relative_text(f"{d.code} {d.severity.value} {_relative(str(d.location)) if d.location else '-'} "
                           f"{d.element} {d.message} | help: {d.help} | "
                           f"data: {json.dumps(_rounded(d.data), sort_keys=True, default=str)}")
            for report in reports for d in report.diagnostics]


def _digits() -> int | None:
    if "--digits" not in sys.argv:
        return None
    return int(sys.argv[sys.argv.index("--digits") + 1])


DIGITS = _digits()


def _rounded(value: Any) -> Any:
    """*value* with every float at DIGITS significant digits (unchanged without ``--digits``)."""
    if DIGITS is None:
        return value
    if isinstance(value, float):
        return float(f"{value:.{DIGITS}g}")
    if isinstance(value, dict):
        return {k: _rounded(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_rounded(v) for v in value]
    return value


def _relative_text(text: str) -> str:
    for base in BASES:
        text = text.replace(base, "")
    return text


def main() -> int:
    out = sys.argv[1]
    snapshot: dict[str, dict[str, list[str]]] = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for path, keywords in _files():
            env = keywords.pop("env", None) or {}
            arguments = keywords.get("xacro_args")
            key = (_relative(path) + (json.dumps(arguments) if arguments else "")
                   + (json.dumps(env, sort_keys=True) if env else ""))
            saved = {name: os.environ.get(name) for name in env}
            os.environ.update(env)
            try:
                snapshot[key] = {
                    "structural": _findings(path, CheckOptions(select=("S", "X"), **keywords)),
                    "default": _findings(path, CheckOptions(rule_options={"dynamics": False}, **keywords)),
                }
            finally:
                for name, value in saved.items():
                    if value is None:
                        os.environ.pop(name, None)
                    else:
                        os.environ[name] = value
    with open(out, "w", encoding="utf-8") as handle:
        json.dump(snapshot, handle, indent=1, sort_keys=True)
    total = sum(len(v["default"]) for v in snapshot.values())
    print(f"{len(snapshot)} files, {total} default findings -> {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
