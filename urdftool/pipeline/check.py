"""Running the rules: one model, one file, or many files in parallel."""

from __future__ import annotations

import dataclasses
import functools
import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import field
from typing import TYPE_CHECKING, Any

from urdftool.budgets import stage_budgets
from urdftool.catalogue.syntax import InternalError
from urdftool.collector import collector_paused
from urdftool.diagnostics import Diagnostic, FileReport, Report, Severity
from urdftool.facts.context import CONTROLLERS_OPTION, SIM_OPTION, SRDF_OPTION, CheckContext
from urdftool.lazy import LazyModule
from urdftool.model import KinematicTree, Robot
from urdftool.parse import Loaded, read
from urdftool.parse.packages import PackageResolver
from urdftool.pipeline import controllers, srdf, suppress
from urdftool.records import record
from urdftool.rules import Selection
from urdftool.rules.registry import model_rules
from urdftool.safe_files import file_limits

if TYPE_CHECKING:
    from urdftool.catalogue.registry import Rule
    from urdftool.facts.simulation import Simulator
    from urdftool.pipeline import fixes, provenance
else:
    # Both act on findings: a model with none (the common case of a CI gate) never imports them.
    fixes = LazyModule("urdftool.pipeline.fixes")
    provenance = LazyModule("urdftool.pipeline.provenance")


@record
class CheckOptions:
    """Everything a check run needs besides the files; picklable for worker processes."""

    select: tuple[str, ...] | None = None
    ignore: tuple[str, ...] = ()
    xacro_args: Mapping[str, str] = field(default_factory=dict)
    packages: Mapping[str, str] = field(default_factory=dict)
    package_paths: tuple[str, ...] = ()
    #: extra switches for rules (e.g. ``{"dynamics": False}``)
    rule_options: Mapping[str, Any] = field(default_factory=dict)
    #: size caps by file kind (``model``, ``include``, ``mesh``) over the defaults; see safe_files
    file_limits: Mapping[str, int] = field(default_factory=dict)
    #: stage budgets (:mod:`urdftool.budgets`) that differ from the defaults
    budgets: Mapping[str, float] = field(default_factory=dict)
    #: honour ``<!-- urdftool: ignore[...] -->`` comments (``--no-suppressions`` turns them off)
    suppressions: bool = True
    #: rule code or name -> severity it is reported at (the configuration's ``severity`` table)
    severity: Mapping[str, Severity] = field(default_factory=dict)
    #: the MoveIt SRDF to check every model against (``--srdf``); else one is looked for beside it
    srdf: str | None = None
    #: look for an SRDF beside each model when none is given
    discover_srdf: bool = True
    #: the ros2_control controllers YAML to check every model against (``--controllers``); else the
    #: file a Gazebo ros2_control plugin's ``<parameters>`` names
    controllers: str | None = None

    def selection(self) -> Selection:
        return Selection.of(self.select, self.ignore)

    def resolver(self) -> PackageResolver:
        return PackageResolver.create(self.packages, self.package_paths)


def run_rules(
    robot: Robot, selection: Selection, options: Mapping[str, Any] | None = None
) -> list[Diagnostic]:
    """The reader's findings plus every selected model rule's, sorted by location."""
    found = [d for d in robot.diagnostics if selection.enabled_code(d.code)]
    options = dict(options or {})
    ctx = CheckContext(robot, KinematicTree.of(robot), options, simulator=_simulator(options))
    try:
        for rule in _selected_rules(selection):
            try:
                found.extend(rule().check(ctx))
            except Exception as exc:  # a rule bug must not hide the other findings
                found.append(
                    InternalError.diagnostic(
                        f"rule {rule.code} ({rule.name}) failed: {type(exc).__name__}: {exc}",
                        robot.span,
                        data={"rule": rule.code},
                    )
                )
    finally:
        # Some facts keep a closure over the context (a memo of the link solids, say): a cycle
        # that held the whole robot, its XML tree and every span until the cyclic collector
        # walked them, 50 ms a pass over example-robot-data (a fifth of the structural check).
        # The rules are done with the facts; dropping them lets reference counting free the robot.
        ctx.cache.clear()
    if not found:
        return found
    return sorted(provenance.trace(_unique(found), robot), key=Diagnostic.sort_key)


@functools.lru_cache(maxsize=64)
def _selected_rules(selection: Selection) -> tuple[type[Rule], ...]:
    """The model rules *selection* turns on, in code order: looked up once per selection (every
    file of a run has the same one), not once per file."""
    return tuple(model_rules(lambda entry: selection.enabled_code(entry.code)))


def _simulator(options: Mapping[str, Any]) -> Simulator | None:
    """The smoke simulation for the runtime rules, when the run asks for one."""
    if not options.get(SIM_OPTION):
        return None
    # Function-level: the simulation brings NumPy, the exporters and the engine
    # adapters, which a check without --sim never loads.
    from urdftool.pipeline.simulate import simulator

    return simulator


def _unique(diagnostics: Iterable[Diagnostic]) -> list[Diagnostic]:
    seen: set[tuple[Any, ...]] = set()
    out = []
    for d in diagnostics:
        key = (d.code, d.message, d.location)
        if key not in seen:
            seen.add(key)
            out.append(d)
    return out


def report_for(loaded: Loaded, selection: Selection, options: Mapping[str, Any] | None = None) -> FileReport:
    if loaded.robot is None:
        diags = [d for d in loaded.diagnostics if selection.enabled_code(d.code)]
        return FileReport(loaded.path, loaded.format, None, tuple(sorted(diags, key=Diagnostic.sort_key)))
    if loaded.srdf is not None:
        options = {**(options or {}), SRDF_OPTION: loaded.srdf}
    if loaded.controllers is not None:
        options = {**(options or {}), CONTROLLERS_OPTION: loaded.controllers}
    return FileReport(
        loaded.path, loaded.format, loaded.robot.name, tuple(run_rules(loaded.robot, selection, options)),
        srdf=loaded.srdf.path if loaded.srdf is not None else None,
        controllers=tuple(config.path for config in loaded.controllers.configs) if loaded.controllers else (),
    )


def check_file(path: str, options: CheckOptions) -> list[FileReport]:
    """Check every model in one file. Raises :class:`~urdftool.parse.InputError`."""
    with file_limits(options.file_limits), stage_budgets(options.budgets), collector_paused():
        # The models are freed when _check_models returns, before the collector resumes: it then
        # has the reports to look at, not every object of the robots it would otherwise walk.
        return _check_models(path, options)


def _check_models(path: str, options: CheckOptions) -> list[FileReport]:
    selection = options.selection()
    resolver = options.resolver()
    models = [controllers.attach(srdf.attach(m, options.srdf, resolver, options.discover_srdf,
                                             options.xacro_args),
                                 options.controllers, resolver)
              for m in read(path, options.xacro_args, resolver)]
    # Rules that re-resolve URIs (to say where a mesh was looked for) use the same resolver.
    rule_options = {**options.rule_options, "resolver": resolver}
    reports = [report_for(m, selection, rule_options) for m in models]
    found = _package_once([list(r.diagnostics) for r in reports], [r.robot for r in reports])
    if options.suppressions:
        files = [f for m in models for f in (m.files or [m.path]) if f not in m.without_suppressions]
        found = suppress.apply_to_models(found, files, selection)
    return [_settled(r, diagnostics, options) for r, diagnostics in zip(reports, found, strict=True)]


def _package_once(found: list[list[Diagnostic]], robots: Sequence[str | None]) -> list[list[Diagnostic]]:
    """A package (or Gazebo model) that several models of one file cannot find, the 27 copies of a
    wall in a saved world, is still each model's finding (``--model`` reports it), but its help,
    where to look and what was searched, is said once: at the first model's finding, with how many
    models use it; the others point there."""
    first: dict[tuple[str, str], tuple[int, Diagnostic]] = {}
    repeats: dict[tuple[str, str], int] = {}
    for index, diagnostics in enumerate(found):
        for d in diagnostics:
            key = _package_key(d)
            if key is not None:
                first.setdefault(key, (index, d))
                repeats[key] = repeats.get(key, 0) + 1
    if all(count == 1 for count in repeats.values()):
        return found
    out: list[list[Diagnostic]] = []
    for diagnostics in found:
        kept = []
        for d in diagnostics:
            key = _package_key(d)
            if key is None or repeats[key] == 1:
                kept.append(d)
                continue
            at, head = first[key]
            models = f"{repeats[key]} models of this file use '{key[1]}'"
            if head is d:
                kept.append(dataclasses.replace(d, help=f"{models}; {d.help}"))
                continue
            line = f" (line {head.location.line})" if head.location and head.location.line else ""
            kept.append(dataclasses.replace(d, help=f"{models}: see model '{robots[at]}'{line}"))
        out.append(kept)
    return out


def _package_key(d: Diagnostic) -> tuple[str, str] | None:
    package = (d.data or {}).get("package")
    return (d.code, package) if isinstance(package, str) and d.help else None


def _settled(report: FileReport, diagnostics: list[Diagnostic], options: CheckOptions) -> FileReport:
    """*report* with *diagnostics* (the inline suppressions applied) after the severity overrides."""
    if options.severity:
        diagnostics = [_with_severity(d, options.severity) for d in diagnostics]
    if diagnostics:
        diagnostics = [d.detached() for d in fixes.attach(diagnostics)]
    return dataclasses.replace(report, diagnostics=tuple(sorted(diagnostics, key=Diagnostic.sort_key)))


def _with_severity(diagnostic: Diagnostic, overrides: Mapping[str, Severity]) -> Diagnostic:
    level = overrides.get(diagnostic.code) or overrides.get(diagnostic.name)
    return dataclasses.replace(diagnostic, severity=level) if level else diagnostic


def check_files(
    paths: Sequence[str],
    options: CheckOptions,
    jobs: int = 1,
    progress: Callable[[int, int], None] | None = None,
) -> Report:
    """Check many files, in *jobs* worker processes; reports come back in input order.

    Input errors are not raised here: callers check paths for readability first.
    """
    results: list[list[FileReport]] = []
    if jobs <= 1 or len(paths) <= 1:
        for index, path in enumerate(paths):
            results.append(check_file(path, options))
            if progress:
                progress(index + 1, len(paths))
    else:
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(max_workers=jobs) as pool:
            for index, result in enumerate(pool.map(check_file, paths, [options] * len(paths))):
                results.append(result)
                if progress:
                    progress(index + 1, len(paths))
    return Report(tuple(r for group in results for r in group))


def default_jobs() -> int:
    return max(1, min(8, os.cpu_count() or 1))
