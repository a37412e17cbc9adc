"""xacro expansion in-process, without ROS, keeping the source of every element.

The ``xacro`` package does the expansion. urdftool wraps three of its seams:

* ``$(find PKG)`` goes through :class:`~urdftool.parse.packages.PackageResolver`
  instead of ``ament_index``/``rospkg``;
* every file xacro opens is first read by the safe reader (so a syntax error in
  an included file is located in that file), and each element of it is stamped
  with its file, line and column; the stamps ride through macro expansion, so
  an element produced by a macro points at the line of the macro body where it
  was written;
* an include whose path does not exist, when exactly one file of that name
  exists inside the package the path points into, is read from there and
  reported as ``include-not-at-path`` (a file moved within its package is the
  commonest cause of broken includes).

The expansion is not thread-safe (xacro keeps module-level state); urdftool runs
parallel checks in processes.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import threading
import xml.dom.minidom
from collections.abc import Iterator, Mapping
from dataclasses import field
from pathlib import Path
from typing import Any

from urdftool.catalogue.xacro import (
    IncludeNotAtPath,
    MacrosOnly,
    PackageMissing,
    XacroError,
    XacroWarning,
)
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.parse.ament import installed_at
from urdftool.parse.locate import encode_src, span_of
from urdftool.parse.packages import PackageResolver
from urdftool.parse.xacro_args import KnownArgument, known_arguments, merge, misspelt_arguments
from urdftool.parse.xacro_guard import guarded
from urdftool.parse.xacro_hints import text_property_help, undefined_property_help
from urdftool.parse.xmlio import XmlDocument, parse_bytes, to_utf8
from urdftool.records import record
from urdftool.safe_files import read_up_to
from urdftool.source import SRC_ATTRIBUTE, Span, element_starts, expat_element_starts

_LOCK = threading.Lock()
_XACRO_TAG = "xacro:"


class PackageNotFoundError(Exception):
    """``$(find PKG)`` named a package the resolver cannot find."""

    def __init__(self, package: str, tried: list[str]):
        super().__init__(f"package '{package}' not found")
        self.package = package
        self.tried = tried


@record(frozen=False)
class XacroResult:
    """The expanded document (or ``None``) and what happened on the way."""

    document: XmlDocument | None
    diagnostics: list[Diagnostic] = field(default_factory=list)
    #: every file read, the input first
    files: list[str] = field(default_factory=list)
    #: the input is a macro library (see the ``macros-only`` rule)
    macro_library: bool = False


@record(frozen=False)
class _Session:
    resolver: PackageResolver
    top: str
    diagnostics: list[Diagnostic] = field(default_factory=list)
    files: list[str] = field(default_factory=list)
    #: package name -> folder, for the include fallback
    found_packages: dict[str, str] = field(default_factory=dict)
    syntax_failed: bool = False
    #: names of the ``<xacro:macro>`` definitions in every file read
    macros: list[str] = field(default_factory=list)
    #: the input writes ``<link>`` or ``<joint>`` outside macro bodies
    top_builds_robot: bool = False
    #: names of the macros the input itself defines
    top_macros: list[str] = field(default_factory=list)
    #: the xacro arguments each file read declares or uses
    arguments: list[dict[str, KnownArgument]] = field(default_factory=list)


def _stamp(doc: xml.dom.minidom.Document, data: bytes, path: str) -> None:
    """Record each element's start position as an attribute (xacro's own tags excepted)."""
    root = doc.documentElement
    if root is None:
        return
    elements = [root, *root.getElementsByTagName("*")]
    starts = element_starts(data)
    if len(starts) != len(elements):  # the scan of the bytes missed something: ask expat
        starts = expat_element_starts(data)
    if len(starts) != len(elements):
        return
    for element, (line, column) in zip(elements, starts, strict=True):
        if not element.tagName.startswith(_XACRO_TAG):
            element.setAttribute(SRC_ATTRIBUTE, encode_src(path, line, column))


def _macro_names(doc: xml.dom.minidom.Document) -> list[str]:
    return [m.getAttribute("name") for m in doc.getElementsByTagName("xacro:macro")]


def _builds_robot(doc: xml.dom.minidom.Document) -> bool:
    """True when *doc* writes a ``<link>`` or ``<joint>`` outside a macro body."""
    for tag in ("link", "joint"):
        for element in doc.getElementsByTagName(tag):
            node = element.parentNode
            while node is not None and getattr(node, "tagName", "") != "xacro:macro":
                node = node.parentNode
            if node is None:
                return True
    return False


def _fallback(session: _Session, missing: str) -> str | None:
    """A unique file named like *missing* inside the package its path points into."""
    target = Path(missing).resolve()
    for folder in session.found_packages.values():
        root = Path(folder)
        if root in target.parents:
            hits = sorted(p for p in root.rglob(target.name) if p.is_file())
            if len(hits) == 1:
                return str(hits[0])
    return None


def _installed(session: _Session, missing: str) -> str | None:
    """The source file that a found package's ament install rules put at *missing*."""
    target = Path(missing).resolve()
    for name, folder in session.found_packages.items():
        root = Path(folder).resolve()
        if root in target.parents:
            return installed_at(name, root, target.relative_to(root).as_posix())
    return None


@contextlib.contextmanager
def _patched(session: _Session) -> Iterator[None]:
    import xacro
    import xacro.substitution_args as subst

    original_find = subst._eval_find
    original_parse = xacro.parse

    def eval_find(package: str) -> str:
        current = xacro.filestack[-1] if xacro.filestack else session.top
        lookup = session.resolver.find_package(package, current or session.top)
        if lookup.path is None:
            raise PackageNotFoundError(package, lookup.tried)
        session.found_packages[package] = lookup.path
        return lookup.path

    def parse(inp: Any, filename: str | None = None) -> Any:
        if inp is not None:
            return original_parse(inp, filename)
        assert filename is not None
        path = os.path.join(xacro.root_dir, filename)
        if not os.path.exists(path):
            installed = _installed(session, path)
            moved = installed or _fallback(session, path)
            if moved is not None:
                if installed is None:
                    _report_moved(session, path, moved)
                path = moved
                if xacro.filestack:
                    # Relative includes inside the moved file resolve from where it is.
                    xacro.filestack[-1] = moved
        kind = "include" if session.files else "model"
        try:
            data = read_up_to(path, kind)
        except OSError as exc:
            if xacro.filestack:
                xacro.filestack.pop()
            raise xacro.XacroException(f"{exc.strerror}: {exc.filename}", exc=exc) from exc
        session.files.append(os.path.abspath(path))
        # minidom (expat) parses the same UTF-8 bytes that the entity guards have seen.
        data, problem = to_utf8(data, os.path.abspath(path))
        checked, problems = (None, [problem]) if problem is not None else parse_bytes(
            data, os.path.abspath(path), stamp=False, kind=kind
        )
        session.diagnostics.extend(problems)
        if checked is None:
            session.syntax_failed = True
            raise xacro.XacroException("XML syntax error")
        doc = xml.dom.minidom.parseString(data)
        _stamp(doc, data, os.path.abspath(path))
        session.arguments.append(known_arguments(os.path.abspath(path), data.decode("utf-8", "replace")))
        session.macros.extend(_macro_names(doc))
        if len(session.files) == 1:
            session.top_builds_robot = _builds_robot(doc)
            session.top_macros = _macro_names(doc)
        return doc

    subst._eval_find = eval_find
    xacro.parse = parse
    try:
        yield
    finally:
        subst._eval_find = original_find
        xacro.parse = original_parse


def _report_moved(session: _Session, missing: str, found: str) -> None:
    import xacro

    # xacro has already pushed the missing file; the includer is below it.
    stack = [f for f in (xacro.filestack or []) if f]
    includer = stack[-2] if len(stack) >= 2 else session.top
    include = re.compile(r"""filename\s*=\s*["'][^"']*""" + re.escape(os.path.basename(missing)))
    written = _locate_pattern(includer, include) or Span(includer)
    package, where = _package_of(session, found)
    better = f"$(find {package})/{where}" if package else found
    session.diagnostics.append(
        IncludeNotAtPath.diagnostic(
            f"included file {missing} does not exist; read {found} instead, the only "
            f"{os.path.basename(found)} in "
            + (f"package '{package}'" if package else "its package"),
            written,
            help=f"write the include as {better}",
            data={"written": missing, "used": found, "package": package},
        )
    )


def _package_of(session: _Session, path: str) -> tuple[str | None, str]:
    """The found package that holds *path*, and *path* relative to its folder."""
    target = Path(path).resolve()
    for name, folder in session.found_packages.items():
        root = Path(folder).resolve()
        if root in target.parents:
            return name, target.relative_to(root).as_posix()
    return None, path


def _locate_text(path: str, needle: str) -> Span:
    """The first line of *path* containing *needle* (the file alone when absent)."""
    try:
        with open(path, encoding="utf-8", errors="replace") as handle:
            for number, line in enumerate(handle, start=1):
                column = line.find(needle)
                if column >= 0:
                    return Span(path, number, column + 1)
    except OSError:
        pass
    return Span(path)


_QUOTED = re.compile(r"[\"']([^\"']+)[\"']")
_NAME_IN_MESSAGE = re.compile(r"(?:name|macro name|symbol|property|parameters?)\s*[:\"' \[]+([\w.:-]+)")


_ARG_IN_MESSAGE = re.compile(r"substitution argument (\w+)")
_PATH_IN_MESSAGE = re.compile(r"(/[^\s'\"]+\.[\w]+)")


def _error_help(message: str, read: list[str]) -> str | None:
    args = _ARG_IN_MESSAGE.findall(message)
    if args:
        name = args[0]
        return f'pass it with -a {name}:=VALUE, or declare <xacro:arg name="{name}" default="..."/>'
    return text_property_help(message, reversed(read)) or undefined_property_help(message, reversed(read))


def _error_location(
    stack: list[str | None], message: str, package: str | None, read: list[str] | None = None
) -> Span:
    """Best location for a xacro failure: the innermost file, and a line when a name in the
    message can be found in it or, failing that, in another file read (a macro body is
    expanded where it is called, so the culprit may sit in an included file)."""
    files = [f for f in stack if f]
    path = files[-1] if files else ""
    needles: list[str] = []
    if package:
        needles.append(f"$(find {package})")
    needles += [f"$(arg {name})" for name in _ARG_IN_MESSAGE.findall(message)]
    needles += _NAME_IN_MESSAGE.findall(message) + _QUOTED.findall(message)
    needles += [os.path.basename(p) for p in _PATH_IN_MESSAGE.findall(message)]
    candidates = list(reversed(files)) + [f for f in reversed(read or []) if f not in files]
    for candidate in candidates:
        for needle in needles:
            span = _locate_text(candidate, needle.replace("xacro:", ""))
            if span.line is not None:
                return span
    return Span(path) if path else Span("")


def expand(
    path: str,
    resolver: PackageResolver,
    args: Mapping[str, str] | None = None,
) -> XacroResult:
    """Expand the xacro file *path*; failures become diagnostics, never exceptions."""
    import xacro

    top = os.path.abspath(path)
    session = _Session(resolver, top)
    stderr = io.StringIO()
    stack: list[str | None] = []
    with (_LOCK, _patched(session), guarded(xacro), contextlib.redirect_stderr(stderr),
          contextlib.redirect_stdout(stderr)):
        try:
            xacro.all_includes = []
            doc = xacro.process_file(top, mappings=dict(args or {}), verbosity=1)
            text = doc.documentElement.toxml()
        except Exception as exc:  # xacro raises many kinds; each becomes a diagnostic
            stack = list(xacro.filestack or [top])
            doc = None
            text = ""
            failure: BaseException | None = exc
        else:
            failure = None
        finally:
            xacro.filestack = None
            xacro.macrostack = None
    session.diagnostics.extend(misspelt_arguments(args or {}, merge(session.arguments)))
    for message, files in _warnings(stderr.getvalue()):
        session.diagnostics.append(
            XacroWarning.diagnostic(f"xacro: {message}", _warning_location(message, files or [top]))
        )
    if failure is not None:
        if not session.syntax_failed:
            missing = _package_error(failure)
            lines = [line.strip() for line in str(failure).splitlines() if line.strip()]
            message = "; ".join(lines) or type(failure).__name__
            if missing is not None:
                session.diagnostics.append(
                    PackageMissing.diagnostic(
                        f"$(find {missing.package}): package '{missing.package}' not found",
                        _error_location(stack, message, missing.package, session.files),
                        help="pass --package NAME=DIR or --package-path DIR; searched: "
                        + "; ".join(missing.tried[-6:]),
                        data={"package": missing.package, "searched": missing.tried},
                    )
                )
            else:
                session.diagnostics.append(
                    XacroError.diagnostic(
                        f"xacro: {message}",
                        _error_location(stack, message, None, session.files),
                        help=_error_help(message, session.files),
                        data={"files": [f for f in stack if f]},
                    )
                )
        return XacroResult(None, session.diagnostics, session.files)
    document, problems = parse_bytes(text.encode("utf-8"), top, stamp=False)
    session.diagnostics.extend(problems)
    library = document is not None and _is_macro_library(session, document.root)
    if library and document is not None:
        session.diagnostics.append(_macros_only(session, document))
    return XacroResult(document, session.diagnostics, session.files, library)


def _is_macro_library(session: _Session, root: Any) -> bool:
    """Macros defined, no ``<link>``/``<joint>`` written outside them, none in the expansion."""
    if not session.macros or session.top_builds_robot:
        return False
    return not any(child.tag in ("link", "joint") for child in root if isinstance(child.tag, str))


def _macros_only(session: _Session, document: XmlDocument) -> Diagnostic:
    names = sorted(set(session.macros))
    own = session.top_macros or names
    shown = ", ".join(own[:5]) + (", ..." if len(own) > 5 else "")
    return MacrosOnly.diagnostic(
        f"macro library: defines xacro macro{'s' if len(own) != 1 else ''} {shown} and no "
        "links; its macros are checked where a robot calls them",
        span_of(document.root) or Span(session.top),
        element="robot",
        help="check the robot description that includes this file",
        data={"macros": names},
    )


_WARNING_FILE = re.compile(r"^(?:in file|when processing file|included from):\s*(.+)$")
_WARNING_MACRO = re.compile(r"^(?:when instantiating macro|instantiated from):.*\((.+)\)\s*$")


def _warnings(stderr: str) -> list[tuple[str, list[str]]]:
    """xacro's warnings on *stderr*, each with the files named after it (innermost first)."""
    out: list[tuple[str, list[str]]] = []
    for raw in stderr.splitlines():
        line = raw.strip()
        if line.startswith("warning:") or line.lower().startswith("deprecated"):
            out.append((line.removeprefix("warning:").strip(), []))
            continue
        if not out:
            continue
        match = _WARNING_MACRO.match(line) or _WARNING_FILE.match(line)
        if match and match.group(1) not in ("???", "string"):
            out[-1][1].append(os.path.abspath(match.group(1)))
    return out


_NAME_ATTRIBUTE = r"""name\s*=\s*["']{}["']"""
#: warning text -> pattern of the line that caused it ({} is the symbol)
_SYMBOL_IN_WARNING = (
    (re.compile(r"redefining global symbol: ([\w.]+)"), _NAME_ATTRIBUTE),
    (re.compile(r"^([\w.]+): (?:default property value|no parent scope)"), _NAME_ATTRIBUTE),
    (re.compile(r"unknown attribute\(s\): ([\w:.-]+)"), r"(?<![\w:.-]){}\s*="),
)


def _warning_location(message: str, files: list[str]) -> Span:
    """Where a xacro warning points: the line naming its symbol, else the innermost file."""
    for finder, template in _SYMBOL_IN_WARNING:
        match = finder.search(message)
        if not match:
            continue
        pattern = re.compile(template.format(re.escape(match.group(1))))
        for path in files:
            span = _locate_pattern(path, pattern)
            if span is not None:
                return span
    return Span(files[0])


def _locate_pattern(path: str, pattern: re.Pattern[str]) -> Span | None:
    try:
        with open(path, encoding="utf-8", errors="replace") as handle:
            for number, line in enumerate(handle, start=1):
                match = pattern.search(line)
                if match:
                    return Span(path, number, match.start() + 1)
    except OSError:
        pass
    return None


def _package_error(exc: BaseException) -> PackageNotFoundError | None:
    seen = 0
    current: Any = exc
    while current is not None and seen < 10:
        if isinstance(current, PackageNotFoundError):
            return current
        current = getattr(current, "exc", None) or current.__cause__ or current.__context__
        seen += 1
    return None


__all__ = ["PackageNotFoundError", "Severity", "XacroResult", "expand"]
