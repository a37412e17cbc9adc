"""Reading robot descriptions: format detection and the readers behind it."""

from __future__ import annotations

import dataclasses
import os
import stat
from collections.abc import Mapping
from dataclasses import field
from typing import TYPE_CHECKING

from urdftool.diagnostics import Diagnostic, Severity
from urdftool.model import Robot
from urdftool.parse.packages import PackageResolver
from urdftool.records import record
from urdftool.safe_files import UnsafeFile, check_regular, read_head
from urdftool.source import SourceIndex

if TYPE_CHECKING:  # the SRDF reader brings lxml, which ``import urdftool`` does not load
    from urdftool.parse.controllers import Controllers
    from urdftool.parse.srdf import Srdf

#: suffix -> format, longest first
SUFFIXES: tuple[tuple[str, str], ...] = (
    (".urdf.xacro", "xacro"),
    (".xacro", "xacro"),
    (".urdf", "urdf"),
    (".sdf", "sdf"),
    (".world", "sdf"),
)


class InputError(Exception):
    """The input cannot be read at all (missing file, unknown format): exit code 2."""


@record(frozen=False)
class Loaded:
    """One model read from one file (``robot`` is ``None`` when nothing could be built)."""

    path: str
    format: str
    robot: Robot | None
    diagnostics: list[Diagnostic] = field(default_factory=list)
    #: every file read to build it (the xacro includes), the input first
    files: list[str] = field(default_factory=list)
    #: the MoveIt SRDF read beside it (``check --srdf``, or found next to the model)
    srdf: Srdf | None = None
    #: the controllers YAML read for it (``check --controllers``, or named by a ros2_control plugin)
    controllers: Controllers | None = None
    #: files of :attr:`files` whose text was seen to hold no ``urdftool:`` comment, so no inline
    #: suppression: the suppression pass does not read them again
    without_suppressions: tuple[str, ...] = ()


def detect_format(path: str) -> str | None:
    """``urdf``, ``xacro`` or ``sdf`` from the suffix, else from the root tag; ``None`` if neither."""
    lower = path.lower()
    for suffix, fmt in SUFFIXES:
        if lower.endswith(suffix):
            return fmt
    try:
        head = read_head(path, 4096, "model")
    except OSError:
        return None
    if b"xmlns:xacro" in head:
        return "xacro"
    if b"<robot" in head:
        return "urdf"
    if b"<sdf" in head:
        return "sdf"
    return None


def read(
    path: str | os.PathLike[str],
    xacro_args: Mapping[str, str] | None = None,
    resolver: PackageResolver | None = None,
) -> list[Loaded]:
    """Read every model in *path*. Raises :class:`InputError` when the file cannot be read."""
    path = os.fspath(path)
    resolver = resolver or PackageResolver.create()
    try:
        status = os.stat(path)  # one look at the file for the three questions below
    except (OSError, ValueError):  # as os.path.exists: a broken link, a NUL in the name
        raise InputError(f"{path}: no such file") from None
    if stat.S_ISDIR(status.st_mode):
        raise InputError(f"{path}: is a directory")
    try:
        # A device or FIFO would hang the reader; an oversized file is a finding of the reader.
        check_regular(path, "model", check_size=False, status=status)
    except UnsafeFile as exc:
        raise InputError(str(exc)) from exc
    except OSError as exc:
        raise InputError(f"{path}: {exc.strerror or exc}") from exc
    fmt = detect_format(path)
    if fmt is None:
        raise InputError(f"{path}: unknown format (expected .urdf, .xacro, .urdf.xacro, .sdf or .world)")
    try:
        if fmt == "xacro":
            return [_read_xacro(path, xacro_args or {}, resolver)]
        if fmt == "sdf":
            # Function-level, like the readers below: lxml and the xacro package load on
            # the first read, not at ``import urdftool`` (a cold start of the CLI).
            from urdftool.parse.sdf import read_sdf

            return read_sdf(path, resolver)
        return [_read_urdf(path, resolver, xacro_args or {})]
    except OSError as exc:
        raise InputError(f"{path}: {exc.strerror or exc}") from exc


def _finish(path: str, fmt: str, robot: Robot | None, diagnostics: list[Diagnostic],
            files: list[str], without_suppressions: tuple[str, ...] = ()) -> Loaded:
    if robot is not None:
        robot = dataclasses.replace(robot, diagnostics=tuple(diagnostics), format=fmt, path=path)
    return Loaded(path, fmt, robot, diagnostics, files, without_suppressions=without_suppressions)


def _read_urdf(path: str, resolver: PackageResolver, args: Mapping[str, str]) -> Loaded:
    from urdftool.parse.urdf import UrdfReader
    from urdftool.parse.xmlio import read_file, uses_substitution, xacro_in_urdf

    # Positions in a table, not stamped on every element: the reader walks the tree once.
    document, problems = read_file(path, table=True)
    if document is None:
        return Loaded(path, "urdf", None, problems, [path])
    needs_xacro = xacro_in_urdf(document.root, document.span) if document.may_use_xacro else None
    # robot.xacro.urdf (gz_ros2_control's demos) says it is xacro, and its launch files run xacro
    # on it: nobody is misled into reading it as plain URDF. Such a file may use xacro only through
    # substitutions (`$(find pkg)` in a plugin's <parameters>), which xacro expands too.
    named = ".xacro." in os.path.basename(path)
    substituted = (needs_xacro is not None or named) and uses_substitution(document.root)
    if needs_xacro is not None or (named and substituted):
        # a xacro file under a .urdf name: read it as xacro does
        loaded = _read_xacro(path, args, resolver)
        found = [*problems, *([needs_xacro] if needs_xacro and not named else []), *loaded.diagnostics]
        if loaded.robot is not None or named or substituted:
            return _finish(path, "xacro", loaded.robot, found, loaded.files)
        # xacro cannot expand it, and nothing in it needs xacro but stray elements (a macro call
        # left from an old include: NASA's Valkyrie). urdfdom, PyBullet and MuJoCo read the .urdf
        # directly and skip elements they do not know: check it as they read it.
        problems = [_as_read_directly(d) for d in found]
    reader = UrdfReader(path, SourceIndex(), resolver, document=document)
    robot = reader.read(document.root)
    return _finish(path, "urdf", robot, problems + reader.diagnostics, [path],
                   () if document.may_hold_suppressions else (path,))


def _as_read_directly(finding: Diagnostic) -> Diagnostic:
    """A xacro failure on a ``.urdf`` file that loaders read without xacro: a warning."""
    if finding.code != "X001" or finding.severity is not Severity.ERROR:
        return finding
    return dataclasses.replace(
        finding, severity=Severity.WARNING,
        message=f"{finding.message}; urdfdom, PyBullet and MuJoCo read this .urdf without xacro and "
        "skip its xacro elements, and it is checked as they read it",
    )


def _read_xacro(path: str, args: Mapping[str, str], resolver: PackageResolver) -> Loaded:
    from urdftool.parse.urdf import UrdfReader
    from urdftool.parse.xacro import expand

    result = expand(path, resolver, args)
    if result.document is None:
        return Loaded(path, "xacro", None, result.diagnostics, result.files)
    reader = UrdfReader(path, SourceIndex(), resolver, expanded=True)
    robot = reader.read(result.document.root)
    found = reader.diagnostics
    if result.macro_library:  # a macro library needs no robot name (see macros-only)
        found = [d for d in found if d.name != "robot-name-missing"]
    return _finish(path, "xacro", robot, result.diagnostics + found, result.files)


__all__ = ["InputError", "Loaded", "PackageResolver", "detect_format", "read"]
