"""Settings from the project's configuration, discovered from each checked file upward.

``[tool.urdftool]`` in a ``pyproject.toml`` or the top level of an
``urdftool.toml``: the nearest one above the checked file wins (an
``urdftool.toml`` before a ``pyproject.toml`` in the same folder; a
``pyproject.toml`` without the table is passed over), as ruff does.
Command-line flags and API keywords win over the file. Keys are the flags'
names in kebab-case (CONTRACTS.md); an unknown key or a wrong type is a
:class:`SettingsError` naming the file, with a did-you-mean.
"""

from __future__ import annotations

import fnmatch
import os
import re
import sys
from collections.abc import Collection, Mapping, Sequence
from dataclasses import field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from urdftool.budgets import BudgetError, checked
from urdftool.catalogue.registry import Family
from urdftool.catalogue.suggest import did_you_mean
from urdftool.diagnostics import Severity
from urdftool.lazy import LazyModule
from urdftool.pipeline.discover import excluded as is_excluded
from urdftool.records import record

if TYPE_CHECKING:
    if sys.version_info >= (3, 11):
        import tomllib
    else:
        import tomli as tomllib
elif sys.version_info >= (3, 11):  # imported when a configuration file is read, not at start
    tomllib = LazyModule("tomllib")
else:  # pragma: no cover - Python 3.10
    tomllib = LazyModule("tomli")

CONFIG_FILES = ("urdftool.toml", "pyproject.toml")

#: key -> (expected kind, what it holds); kinds: "codes" (list of strings), "bool", "paths",
#: "mapping" (name -> string), "glob-codes" (glob -> codes), "glob-args" (glob -> {name: value}),
#: "severity" (code or name -> level), "string", "numbers" (name -> number)
KEYS: dict[str, str] = {
    "select": "codes",
    "ignore": "codes",
    "extend-select": "codes",
    "per-file-ignores": "glob-codes",
    "severity": "severity",
    "strict": "bool",
    "package-path": "paths",
    "packages": "mapping",
    "xacro-args": "glob-args",
    "target": "codes",
    "budgets": "numbers",
    "format": "string",
    "exclude": "globs",
}


class SettingsError(ValueError):
    """A configuration file that cannot be used: unreadable TOML, an unknown key, a wrong type."""


@record
class ConfigFile:
    """One configuration file and its ``[tool.urdftool]`` table (or ``urdftool.toml`` body)."""

    path: Path
    table: Mapping[str, Any]

    @property
    def folder(self) -> Path:
        return self.path.parent

    @property
    def label(self) -> str:
        return f"{self.path} [tool.urdftool]" if self.path.name == "pyproject.toml" else str(self.path)


@record
class Settings:
    """What a check of one file runs with, and where each setting came from.

    ``sources`` maps each key that is set to ``"command line"``, a config
    file's label, or ``"default"``.
    """

    select: tuple[str, ...] | None = None
    ignore: tuple[str, ...] = ()
    severity: Mapping[str, Severity] = field(default_factory=dict)
    strict: bool = False
    package_paths: tuple[str, ...] = ()
    packages: Mapping[str, str] = field(default_factory=dict)
    xacro_args: Mapping[str, str] = field(default_factory=dict)
    target: tuple[str, ...] = ()
    budgets: Mapping[str, float] = field(default_factory=dict)
    format: str | None = None
    config: Path | None = None
    sources: Mapping[str, str] = field(default_factory=dict)
    #: the ``exclude`` patterns of the configuration, and whether they leave this file out of a
    #: directory walk (a file named on the command line is checked anyway)
    exclude: tuple[str, ...] = ()
    excluded: bool = False

    def describe(self) -> str:
        """The settings as ``key = value  # source`` lines (``check --show-settings``)."""
        rows = [
            ("config", str(self.config) if self.config else None),
            ("select", list(self.select) if self.select is not None else None),
            ("ignore", list(self.ignore)),
            ("severity", {k: v.value for k, v in self.severity.items()}),
            ("strict", self.strict),
            ("package-path", list(self.package_paths)),
            ("packages", dict(self.packages)),
            ("xacro-args", dict(self.xacro_args)),
            ("target", list(self.target)),
            ("budgets", dict(self.budgets)),
            ("format", self.format),
            ("exclude", list(self.exclude)),
        ]
        width = max(len(key) for key, _ in rows)
        out = []
        for key, value in rows:
            source = self.sources.get(key, "default")
            out.append(f"{key:<{width}} = {value!r}  # {source}")
        return "\n".join(out) + "\n"


def find_config(start: str | os.PathLike[str]) -> ConfigFile | None:
    """The nearest configuration at or above *start* (a file or a folder), or ``None``."""
    folder = Path(start).resolve()
    if not folder.is_dir():
        folder = folder.parent
    for candidate in (folder, *folder.parents):
        for name in CONFIG_FILES:
            path = candidate / name
            if not path.is_file():
                continue
            if name == "pyproject.toml" and not _may_configure(path):
                continue
            document = _load_toml(path)
            if name == "pyproject.toml":
                table = document.get("tool", {}).get("urdftool")
                if table is None:
                    continue
            else:
                table = document
            config = ConfigFile(path, table)
            validate(config)
            return config
    return None


#: Where a TOML document can name urdftool's table: a dotted ``tool.urdftool`` (a table header
#: ``[tool.urdftool]`` or ``[tool.urdftool.severity]``, or a dotted key), or a ``[tool]`` table or
#: a ``tool = {…}`` inline table, which may hold an ``urdftool`` key; keys bare or quoted.
_TOOL_TABLE = re.compile(
    rb"""["']?tool["']?[ \t]*\.[ \t]*["']?urdftool|^[ \t]*\[[ \t]*["']?tool["']?[ \t]*\]"""
    rb"""|^[ \t]*["']?tool["']?[ \t]*=""", re.MULTILINE)


def _may_configure(path: Path) -> bool:
    """Whether a ``pyproject.toml`` can hold urdftool's table (:data:`_TOOL_TABLE`).

    A project that names urdftool only as a dependency or a script is passed over unread, and
    the TOML parser, a few milliseconds of a cold start, is not imported; an unreadable file is
    read to say why."""
    try:
        text = path.read_bytes()
    except OSError:
        return True
    return b"urdftool" in text and _TOOL_TABLE.search(text) is not None


def _load_toml(path: Path) -> dict[str, Any]:
    try:
        with path.open("rb") as handle:
            document: dict[str, Any] = tomllib.load(handle)
            return document
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise SettingsError(f"{path}: cannot read the configuration: {exc}") from exc


def validate(config: ConfigFile) -> None:
    """Raise :class:`SettingsError` for an unknown key or a value of the wrong kind."""
    for key, value in config.table.items():
        if key not in KEYS:
            raise SettingsError(f"{config.label}: unknown key '{key}'" + did_you_mean(key, KEYS))
        if not _fits(KEYS[key], value):
            raise SettingsError(f"{config.label}: '{key}' must be {_KIND_WORDS[KEYS[key]]}")


_KIND_WORDS = {
    "codes": "a list of rule codes, prefixes or names",
    "bool": "true or false",
    "paths": "a list of folders",
    "mapping": "a table of names to folders",
    "glob-codes": "a table of file patterns to lists of codes",
    "glob-args": "a table of file patterns to tables of xacro arguments",
    "severity": "a table of codes or names to error, warning, info or off",
    "string": "a string",
    "numbers": "a table of names to numbers",
    "globs": "a list of file or folder patterns",
}


def _is_strings(value: Any) -> bool:
    return isinstance(value, list) and all(isinstance(v, str) for v in value)


def _fits(kind: str, value: Any) -> bool:
    if kind in ("codes", "paths", "globs"):
        return _is_strings(value)
    if kind == "bool":
        return isinstance(value, bool)
    if kind == "string":
        return isinstance(value, str)
    if not isinstance(value, dict):
        return False
    if kind == "mapping":
        return all(isinstance(v, str) for v in value.values())
    if kind == "glob-codes":
        return all(_is_strings(v) for v in value.values())
    if kind == "glob-args":
        return all(isinstance(v, dict) and all(isinstance(x, str) for x in v.values())
                   for v in value.values())
    if kind == "severity":
        return all(v in ("error", "warning", "info", "off") for v in value.values())
    if kind == "numbers":
        return all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value.values())
    return False


@record
class Overrides:
    """What the command line (or the API's keywords) set; ``None`` and empty mean "not given"."""

    select: tuple[str, ...] | None = None
    ignore: tuple[str, ...] = ()
    extend_select: tuple[str, ...] = ()
    strict: bool | None = None
    package_paths: tuple[str, ...] = ()
    packages: Mapping[str, str] = field(default_factory=dict)
    xacro_args: Mapping[str, str] = field(default_factory=dict)
    format: str | None = None
    #: ignore configuration files (``--isolated``)
    isolated: bool = False


def resolve(path: str | os.PathLike[str], overrides: Overrides | None = None) -> Settings:
    """The settings for checking *path*: defaults, then the nearest config file, then *overrides*."""
    given = overrides or Overrides()
    config = None if given.isolated else find_config(path)
    table: Mapping[str, Any] = config.table if config else {}
    label = config.label if config else "default"
    sources: dict[str, str] = {}

    def from_file(key: str) -> Any:
        if key in table:
            sources[key] = label
            return table[key]
        return None

    relative = _relative(path, config.folder) if config else Path(path).name
    select: tuple[str, ...] | None = tuple(from_file("select")) if "select" in table else None
    extend = tuple(from_file("extend-select") or ())
    if given.select is not None:
        select, sources["select"] = given.select, "command line"
    if select is not None and (extend or given.extend_select):
        select = (*select, *extend, *given.extend_select)
    elif extend or given.extend_select:
        # the default set (every family) plus what is named: rules that are off by default
        # (optional conventions) come on only when named exactly
        select = (*(f.letter for f in Family), *extend, *given.extend_select)
    ignore = tuple(from_file("ignore") or ())
    for pattern, codes in (from_file("per-file-ignores") or {}).items():
        if _matches(relative, pattern):
            ignore = (*ignore, *codes)
    if given.ignore:
        ignore, sources["ignore"] = (*ignore, *given.ignore), "command line"
    xacro_args: dict[str, str] = {}
    for pattern, args in (from_file("xacro-args") or {}).items():
        if _matches(relative, pattern):
            xacro_args.update(args)
    if given.xacro_args:
        xacro_args.update(given.xacro_args)
        sources["xacro-args"] = "command line"
    folder = config.folder if config else Path.cwd()
    package_paths = tuple(str((folder / p).resolve()) for p in (from_file("package-path") or ()))
    if given.package_paths:
        package_paths, sources["package-path"] = (*given.package_paths, *package_paths), "command line"
    packages = {k: str((folder / v).resolve()) for k, v in (from_file("packages") or {}).items()}
    if given.packages:
        packages.update(given.packages)
        sources["packages"] = "command line"
    strict = bool(from_file("strict") or False)
    if given.strict is not None and given.strict:
        strict, sources["strict"] = True, "command line"
    fmt = from_file("format")
    if given.format is not None:
        fmt, sources["format"] = given.format, "command line"
    exclude = tuple(from_file("exclude") or ())
    severity = {k: Severity(v) for k, v in (from_file("severity") or {}).items() if v != "off"}
    ignore = (*ignore, *(k for k, v in (table.get("severity") or {}).items() if v == "off"))
    if config:
        sources["config"] = label
    return Settings(
        select=select, ignore=ignore, severity=severity, strict=strict, package_paths=package_paths,
        packages=packages, xacro_args=xacro_args, target=tuple(from_file("target") or ()),
        budgets=_budgets(from_file("budgets") or {}, label), format=fmt,
        config=config.path if config else None,
        sources=sources, exclude=exclude, excluded=bool(config) and is_excluded(relative, exclude),
    )


def _budgets(values: Mapping[str, Any], label: str) -> dict[str, float]:
    """The ``budgets`` table, its names and values checked (an unknown name is an error with
    did-you-mean, as an unknown key is)."""
    try:
        return checked(values)
    except BudgetError as exc:
        raise SettingsError(f"{label}: {exc}") from exc


def _relative(path: str | os.PathLike[str], folder: Path) -> str:
    try:
        return Path(path).resolve().relative_to(folder).as_posix()
    except ValueError:
        return Path(path).name


def _matches(relative: str, pattern: str) -> bool:
    """A per-file pattern matches the path relative to the config's folder, or its file name."""
    return fnmatch.fnmatch(relative, pattern) or fnmatch.fnmatch(Path(relative).name, pattern)


def group_by_settings(paths: Sequence[str], overrides: Overrides,
                      named: Collection[str] = ()) -> list[tuple[Settings, list[str]]]:
    """The files to check, grouped by the settings each resolves to (input order kept); a file
    its configuration's ``exclude`` matches is left out unless it is one of *named* (given on the
    command line)."""
    groups: dict[str, tuple[Settings, list[str]]] = {}
    for path in paths:
        settings = resolve(path, overrides)
        if settings.excluded and path not in named:
            continue
        groups.setdefault(repr(settings), (settings, []))[1].append(path)
    return list(groups.values())


__all__ = [
    "ConfigFile",
    "Overrides",
    "Settings",
    "SettingsError",
    "find_config",
    "group_by_settings",
    "resolve",
]
