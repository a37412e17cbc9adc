"""Where a value written through xacro came from: a property's definition, a macro's argument.

A finding on an expanded element points at the element as written (inside a
macro body, that is the macro's definition). When the element's attributes
are expressions (``upper="${max_angle}"``), the number the rule judged was
written elsewhere: in a ``<xacro:property>`` or in the argument of a macro
call. This pass reads the element's start tag back from its source, finds the
names its ``${…}`` expressions use, and adds the places they were defined as
related locations of the finding (the text output prints them as notes):

* ``<xacro:property name="NAME" …>``: "the value comes from property `NAME`";
* a parameter of the macro whose body holds the element: each call that
  passes it, "`NAME="…"` is passed to macro `M` here".

* a property loaded from YAML (``value="${xacro.load_yaml('limits.yaml')}"``)
  and read by key (``${limits['jaw']['upper']}`` or ``${limits.jaw.upper}``):
  the key's line in the YAML file, "the value comes from `jaw.upper` in
  limits.yaml", besides the property.

It runs on the intent findings (``N``) located in ``.xacro`` files.
"""

from __future__ import annotations

import dataclasses
import functools
import re
from collections.abc import Iterable
from pathlib import Path

from urdftool.diagnostics import Diagnostic, Related
from urdftool.model import Robot
from urdftool.safe_files import read_up_to
from urdftool.source import Span, decode_source

_EXPR = re.compile(r"\$\{([^}]*)\}")
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_LOAD_YAML = re.compile(r"load_yaml\(\s*['\"]([^'\"]+)['\"]\s*\)")
_FIND = re.compile(r"\$\(find ([^)\s]+)\)")
_KEYS = re.compile(r"\[\s*['\"]([^'\"]+)['\"]\s*\]|\.([A-Za-z_][A-Za-z0-9_]*)")
_MACRO = re.compile(r"<xacro:macro\b[^>]*?\bname\s*=\s*\"([^\"]+)\"[^>]*?\bparams\s*=\s*\"([^\"]*)\"", re.S)
#: at most this many call sites per parameter
MAX_CALLS = 3
FAMILIES = ("N",)


@functools.lru_cache(maxsize=64)
def _text(path: str) -> str | None:
    """The text of *path* as the readers decode it (a regular file only), or ``None``."""
    try:
        return decode_source(read_up_to(path, "include"))
    except OSError:
        return None


def _offset(text: str, line: int, column: int | None) -> int:
    lines = text.splitlines(keepends=True)
    return sum(len(x) for x in lines[: line - 1]) + max((column or 1) - 1, 0)


def _span(path: str, text: str, offset: int) -> Span:
    line = text.count("\n", 0, offset) + 1
    column = offset - (text.rfind("\n", 0, offset) + 1) + 1
    return Span(path, line, column)


def _start_tag(text: str, offset: int) -> str:
    end = text.find(">", offset)
    return text[offset : end if end >= 0 else len(text)]


def _files(robot: Robot, first: str) -> list[str]:
    """The location's file, every file the model's elements came from, and xacro files beside them."""
    seen: dict[str, None] = {first: None}
    spans = [link.span for link in robot.links if link.span is not None]
    spans += [joint.span for joint in robot.joints if joint.span is not None]
    folders = {Path(first).parent}
    for span in spans:
        if span.path.endswith(".xacro"):
            seen.setdefault(span.path, None)
            folders.add(Path(span.path).parent)
    for folder in sorted(folders):
        for path in sorted(folder.glob("*.xacro")):
            seen.setdefault(str(path), None)
    return list(seen)


def _macro_around(text: str, offset: int) -> tuple[str, list[str]] | None:
    """The macro whose body holds *offset*: its name and parameter names."""
    best = None
    for match in _MACRO.finditer(text, 0, offset):
        close = text.find("</xacro:macro>", match.end())
        if close == -1 or close > offset:
            best = match
    if best is None:
        return None
    params = [p.lstrip("*^").split(":=")[0].split("=")[0] for p in best[2].split()]
    return best[1], params


def origins(diagnostic: Diagnostic, robot: Robot) -> list[Related]:
    """Where the values of the element *diagnostic* points at were defined."""
    loc = diagnostic.location
    if loc is None or loc.line is None or not loc.path.endswith(".xacro"):
        return []
    text = _text(loc.path)
    if text is None:
        return []
    offset = _offset(text, loc.line, loc.column)
    expressions = _EXPR.findall(_start_tag(text, offset))
    names = [n for expr in expressions for n in _NAME.findall(expr)]
    if not names:
        return []
    out: list[Related] = []
    macro = _macro_around(text, offset)
    files = _files(robot, loc.path)
    for name in dict.fromkeys(names):
        if macro is not None and name in macro[1]:
            out.extend(_calls(files, macro[0], name, _element_name(diagnostic)))
            continue
        pattern = re.compile(rf"<xacro:property\b[^>]*?\bname\s*=\s*\"{re.escape(name)}\"", re.S)
        for path in files:
            body = _text(path)
            found = pattern.search(body) if body else None
            if body and found:
                label = f"the value comes from property `{name}`"
                out.append(Related(_span(path, body, found.start()), label))
                out.extend(_yaml_origins(path, _start_tag(body, found.start()), name, expressions))
                break
    return out


def _yaml_origins(path: str, property_tag: str, name: str, expressions: list[str]) -> list[Related]:
    """The YAML keys that *expressions* read from property *name*, when it was loaded from YAML."""
    loaded = _LOAD_YAML.search(property_tag)
    if loaded is None:
        return []
    yaml_path = _yaml_file(path, loaded[1])
    body = _text(yaml_path) if yaml_path else None
    if yaml_path is None or body is None:
        return []
    out: list[Related] = []
    for expr in expressions:
        for access in re.finditer(rf"\b{re.escape(name)}((?:\[[^\]]*\]|\.[A-Za-z_][A-Za-z0-9_]*)+)", expr):
            keys = [a or b for a, b in _KEYS.findall(access[1])]
            span = _yaml_key_span(yaml_path, body, keys)
            if span is not None:
                label = f"the value comes from `{'.'.join(keys)}` in {Path(yaml_path).name}"
                related = Related(span, label)
                if related not in out:
                    out.append(related)
    return out


def _yaml_file(xacro_path: str, spec: str) -> str | None:
    """The file ``load_yaml`` reads: relative to the xacro file, or below a ``$(find PKG)``
    that names a package folder above it (the common layout: the robot's own package)."""
    found = _FIND.search(spec)
    if found is None:
        candidate = Path(spec) if Path(spec).is_absolute() else Path(xacro_path).parent / spec
        return str(candidate) if candidate.is_file() else None
    rest = spec[found.end() :].lstrip("/")
    for folder in Path(xacro_path).resolve().parents:
        manifest = folder / "package.xml"
        if manifest.is_file() and f"<name>{found[1]}</name>" in (_text(str(manifest)) or ""):
            candidate = folder / rest
            return str(candidate) if candidate.is_file() else None
    return None


def _yaml_key_span(path: str, body: str, keys: list[str]) -> Span | None:
    """Where the value at *keys* is written in the YAML text (line and column of its key)."""
    import yaml  # type: ignore[import-untyped]  # loaded only when a traced value came from YAML

    try:
        node = yaml.compose(body, Loader=yaml.SafeLoader)
    except (yaml.YAMLError, RecursionError):  # nesting deep enough to exhaust the stack
        return None
    mark = None
    for key in keys:
        if not isinstance(node, yaml.MappingNode):
            return None
        match = next(((k, v) for k, v in node.value if getattr(k, "value", None) == key), None)
        if match is None:
            return None
        mark, node = match[0].start_mark, match[1]
    return Span(path, mark.line + 1, mark.column + 1) if mark is not None else None


def _element_name(diagnostic: Diagnostic) -> str:
    """The name of the link or joint the finding is about (``joint[right_hip]/limit``: ``right_hip``)."""
    found = re.match(r"\w+\[([^\]]*)\]", diagnostic.element or "")
    return found[1] if found else ""


def _calls(files: Iterable[str], macro: str, param: str, element: str) -> list[Related]:
    """The calls of *macro* that pass *param*; those that named *element* when any did."""
    pattern = re.compile(rf"<xacro:{re.escape(macro)}\b[^>]*?\b{re.escape(param)}\s*=\s*\"([^\"]*)\"", re.S)
    calls: list[tuple[Related, bool]] = []
    for path in files:
        body = _text(path) or ""
        for found in pattern.finditer(body):
            tag = _start_tag(body, found.start())
            values = re.findall(r"=\s*\"([^\"]+)\"", tag)
            named = bool(element) and any(_NAME.fullmatch(v) and v in element.split("_") for v in values)
            label = f'the value comes from `{param}="{found[1]}"` passed to macro `{macro}` here'
            calls.append((Related(_span(path, body, found.start()), label), named))
    if any(named for _, named in calls):
        calls = [c for c in calls if c[1]]
    return [related for related, _ in calls[:MAX_CALLS]]


def trace(diagnostics: Iterable[Diagnostic], robot: Robot) -> list[Diagnostic]:
    """*diagnostics* with the origins of their values added as related locations."""
    _text.cache_clear()  # files are read once per check, and afresh on the next one
    out = []
    for d in diagnostics:
        if d.code.startswith(FAMILIES) and d.location is not None and d.location.path.endswith(".xacro"):
            extra = tuple(r for r in origins(d, robot) if r not in d.related)
            if extra:
                d = dataclasses.replace(d, related=(*d.related, *extra))
        out.append(d)
    return out
