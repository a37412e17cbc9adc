"""The ``dot`` target: a robot's kinematic tree as a Graphviz diagram.

:func:`export` is the exporter behind ``urdftool convert IN -o tree.dot`` and
returns DOT text; ``urdftool graph`` and :func:`urdftool.to_dot` also render
it to PDF, SVG or PNG (:mod:`urdftool.export.graph.render`). The modules:

* ``dot``      DOT syntax and escaping
* ``labels``   numbers, units and the words on nodes and edges
* ``findings`` which link or joint a diagnostic is about
* ``groups``   merging fixed-joint chains (``collapse_fixed``)
* ``build``    the diagram itself
* ``render``   running Graphviz
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from urdftool.diagnostics import Diagnostic
from urdftool.export import ExportOptions, ExportResult
from urdftool.export.graph.build import GraphSettings, build_dot
from urdftool.export.graph.render import (
    DOT_SUFFIXES,
    RENDERED_SUFFIXES,
    GraphvizFailed,
    GraphvizNotFound,
    find_dot,
    graphviz_format,
    render_files,
)
from urdftool.export.write import write_text_atomic
from urdftool.model import Robot
from urdftool.records import record

RANKDIRS = ("TB", "LR", "BT", "RL")


@record
class GraphOptions:
    """Everything that changes the diagram.

    ``diagnostics`` runs the rules and marks links and joints with error or
    warning findings; ``select``/``ignore`` choose the rules as in ``check``.
    """

    rankdir: str = "TB"
    collapse_fixed: bool = False
    diagnostics: bool = True
    select: tuple[str, ...] | None = None
    ignore: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.rankdir.upper() not in RANKDIRS:
            raise ValueError(f"rankdir must be one of {', '.join(RANKDIRS)}, not '{self.rankdir}'")
        object.__setattr__(self, "rankdir", self.rankdir.upper())

    @classmethod
    def of(cls, extra: Mapping[str, Any]) -> GraphOptions:
        """From ``ExportOptions.extra`` or keyword arguments; unknown keys are an error."""
        known = {"rankdir", "collapse_fixed", "diagnostics", "select", "ignore"}
        unknown = sorted(set(extra) - known)
        if unknown:
            raise ValueError(f"unknown graph option(s): {', '.join(unknown)}")
        values = dict(extra)
        if values.get("select") is not None:
            values["select"] = tuple(values["select"])
        values["ignore"] = tuple(values.get("ignore") or ())
        return cls(**values)


def dot_text(
    robot: Robot,
    options: GraphOptions | None = None,
    diagnostics: Sequence[Diagnostic] | None = None,
) -> str:
    """The DOT text of *robot*, marking the links and joints named by *diagnostics*.

    The findings come from the pipeline (:func:`urdftool.pipeline.convert.graph_findings`);
    an exporter runs no rules.
    """
    options = options or GraphOptions()
    found = list(diagnostics or ())
    settings = GraphSettings(rankdir=options.rankdir, collapse_fixed=options.collapse_fixed)
    return build_dot(robot, settings, found)


def export(robot: Robot, out: Path, options: ExportOptions) -> ExportResult:
    """The ``dot`` exporter: ``{out.name: DOT text}``; graph options come in ``extra``."""
    text = dot_text(robot, GraphOptions.of(options.extra), options.findings)
    return ExportResult(files={out.name: text.encode("utf-8")})


def check_output_suffix(out: str | os.PathLike[str]) -> None:
    """Raise ``ValueError`` unless *out* ends in a suffix the graph can be written as."""
    suffix = Path(out).suffix.lower()
    if suffix not in DOT_SUFFIXES and suffix not in RENDERED_SUFFIXES:
        choices = ", ".join((*RENDERED_SUFFIXES, *DOT_SUFFIXES))
        raise ValueError(
            f"{out}: cannot write a graph as '{suffix or Path(out).name}' (choose from {choices})"
        )


def dot_companion(out: str | os.PathLike[str]) -> Path:
    """Where ``keep_dot`` puts the DOT text of a rendered *out*: beside it, suffix ``.dot``."""
    return Path(out).with_suffix(".dot")


def write_diagram(
    text: str,
    out: str | os.PathLike[str],
    inputs: Iterable[str | os.PathLike[str]] = (),
    keep_dot: bool = False,
    written: list[Path] | None = None,
) -> list[str]:
    """Write DOT *text* to *out*: as text for ``.dot``/``.gv``, else rendered by Graphviz.

    With *keep_dot* the DOT text is written beside a rendered *out* first, so it
    exists even when Graphviz is missing. Each file is appended to *written* as
    soon as it is in place, so a caller catching an error knows what exists.
    Returns Graphviz's warnings. Raises ``ValueError`` (suffix),
    :class:`GraphvizNotFound`, :class:`GraphvizFailed` and
    :class:`~urdftool.export.write.OutputError` (an output is an input).
    """
    check_output_suffix(out)
    written = written if written is not None else []
    sources = list(inputs)
    fmt = graphviz_format(out)
    if fmt is None or keep_dot:
        target = Path(out) if fmt is None else dot_companion(out)
        write_text_atomic(target, text, sources)
        written.append(target)
    if fmt is None:
        return []
    warnings = render_files(text, {out: fmt}, sources)
    written.append(Path(out))
    return warnings


__all__ = [
    "DOT_SUFFIXES",
    "RANKDIRS",
    "RENDERED_SUFFIXES",
    "GraphOptions",
    "GraphSettings",
    "GraphvizFailed",
    "GraphvizNotFound",
    "build_dot",
    "check_output_suffix",
    "dot_companion",
    "dot_text",
    "export",
    "find_dot",
    "graphviz_format",
    "render_files",
    "write_diagram",
]
