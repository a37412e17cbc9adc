#!/usr/bin/env python3
"""Print the codes ``urdftool check`` reports per file over example-robot-data and pybullet_data, as JSON.

Usage: python3 scripts/corpus_summary.py > summary.json

Refactors compare this summary before and after (docs/architecture.md): a
change in it must be a deliberate one, named in CHANGELOG.md.
"""

from __future__ import annotations

import json
import sys
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.conftest import ERD, PBD, erd_urdfs, pybullet_robots  # noqa: E402

try:
    from urdftool.pipeline.check import CheckOptions, check_file
except ImportError:  # a checkout from before the pipeline package (for before/after comparisons)
    from urdftool.check import CheckOptions, check_file  # type: ignore[no-redef]


def main() -> int:
    summary: dict[str, dict[str, int]] = {}
    options = CheckOptions()
    files = [*erd_urdfs(), *pybullet_robots()]
    for path in files:
        for report in check_file(path, options):
            key = f"{Path(path).relative_to(ERD if ERD and str(path).startswith(str(ERD)) else PBD)}"
            key += f"#{report.robot}" if report.robot else ""
            summary[key] = dict(sorted(Counter(d.code for d in report.diagnostics).items()))
    json.dump(summary, sys.stdout, indent=1, sort_keys=True)
    print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
