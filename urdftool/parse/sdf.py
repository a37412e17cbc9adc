"""SDF reader: an ``.sdf`` or ``.world`` file into one :class:`~urdftool.parse.Loaded` per model.

A file holding a ``<model>`` yields that model. A ``<world>`` yields each of
its ``<model>`` elements and each ``<include>`` that names a model, in file
order; ``model://sun`` and ``model://ground_plane`` are Gazebo's standard
light and ground plane and are recognised without their files (and not
reported as models). Versions 1.4 to 1.11 are read with their own pose and
axis rules; see docs/sdf.md for every decision the reader takes.
"""

from __future__ import annotations

import dataclasses

from lxml import etree

from urdftool.catalogue.sdf import SdfModelMissing, SdfVersion
from urdftool.catalogue.syntax import NotARobot
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.parse import Loaded
from urdftool.parse.locate import span_of
from urdftool.parse.packages import PackageResolver
from urdftool.parse.sdf_include import read_include
from urdftool.parse.sdf_model import SdfModelReader, parse_version
from urdftool.parse.sdf_semantics import check_document
from urdftool.parse.sdf_values import SdfValues
from urdftool.parse.xmlio import read_file
from urdftool.source import SourceIndex

OLDEST = (1, 4)
NEWEST = (1, 11)


def read_sdf(path: str, resolver: PackageResolver) -> list[Loaded]:
    """Every model in the SDF file *path* (a world yields each of its models).

    Raises :class:`OSError` when the file cannot be read; everything else is a
    located diagnostic on the returned models.
    """
    document, problems = read_file(path)
    if document is None:
        return [Loaded(path, "sdf", None, problems, [path])]
    root = document.root
    if root.tag != "sdf":
        problems.append(
            NotARobot.diagnostic(
                f"root element is <{root.tag}>, not <sdf>",
                span_of(root),
                help="an SDF file starts with <sdf version=\"…\">; a model.config names the SDF file to read",
            )
        )
        return [Loaded(path, "sdf", None, problems, [path])]
    version = _version(root, problems)
    owners: list[tuple[etree._Element, Loaded]] = []
    models = _read_models(root, version, path, resolver, owners)
    # an <include> without <name> takes its model's name, known once the include is read
    names = {id(e): m.robot.name for e, m in owners if e.tag == "include" and m.robot and m.robot.name}
    problems.extend(check_document(root, version, names))
    if not models and not _has_world(root):
        others = _lights_and_actors(root)
        problems.append(
            SdfModelMissing.diagnostic(
                f"the SDF file holds {'an' if others[0] == 'actor' else 'a'} <{others[0]}>, which has no "
                "links or joints to check", span_of(root), element="sdf", severity=Severity.INFO,
            ) if others else SdfModelMissing.diagnostic(
                "the SDF file holds no <model> and no <world>", span_of(root), element="sdf"
            )
        )
    if not models:
        return [Loaded(path, "sdf", None, problems, [path])]
    # A finding inside a model (or include) of a world goes with that model, so that a report names
    # the model it is about; file-level findings (version, XML quirks, the world's own elements)
    # go with the first model.
    owned: dict[int, list[Diagnostic]] = {}
    for problem in problems:
        owner = _owner(problem, owners) or models[0]
        owned.setdefault(id(owner), []).append(problem)
    for model in models:
        found = owned.get(id(model))
        if found:
            model.diagnostics[:0] = found
            if model.robot is not None:
                model.robot = dataclasses.replace(model.robot, diagnostics=tuple(model.diagnostics))
    return models


def _owner(problem: Diagnostic, owners: list[tuple[etree._Element, Loaded]]) -> Loaded | None:
    """The model whose element holds *problem*'s position: at or after the element's start tag and
    before the next element that is not inside it."""
    where = problem.location
    if len(owners) < 2 or where is None or where.line is None:
        return None
    position = (where.line, where.column or 0)
    for element, loaded in owners:
        start = span_of(element)
        if (start is None or start.line is None or start.path != where.path
                or position < (start.line, start.column or 0)):
            continue
        after = _following(element)
        end = span_of(after) if after is not None else None
        if end is None or end.line is None or position < (end.line, end.column or 0):
            return loaded
    return None


def _following(element: etree._Element) -> etree._Element | None:
    """The first element after *element* in document order that is not inside it."""
    node: etree._Element | None = element
    while node is not None:
        after = node.getnext()
        while after is not None and not isinstance(after.tag, str):  # a comment or processing instruction
            after = after.getnext()
        if after is not None:
            return after
        node = node.getparent()
    return None


def _has_world(root: etree._Element) -> bool:
    return root.find("world") is not None


def _version(root: etree._Element, problems: list[Diagnostic]) -> tuple[int, int]:
    raw = root.get("version")
    values = SdfValues(SourceIndex())
    if raw is None:
        problems.append(
            SdfVersion.diagnostic("<sdf> has no version; read as SDF 1.11", span_of(root), element="sdf",
                                  help='write <sdf version="1.7"> (or the version the file was written for)')
        )
        return NEWEST
    version = parse_version(raw)
    if version < OLDEST or version > NEWEST or raw.strip().count(".") != 1:
        clamped = min(max(version, OLDEST), NEWEST)
        problems.append(
            SdfVersion.diagnostic(
                f'SDF version "{raw}" is outside 1.4–1.11; read with the rules of {clamped[0]}.{clamped[1]}',
                values.attr_span(root, "version"),
                element="sdf",
                data={"version": raw},
            )
        )
        return clamped
    return version


def _read_models(root: etree._Element, version: tuple[int, int], path: str,
                 resolver: PackageResolver, owners: list[tuple[etree._Element, Loaded]]) -> list[Loaded]:
    """The models of *root* and of its worlds, in file order; *owners* receives each model's
    element (a ``<model>`` or ``<include>``) with its model."""
    out: list[Loaded] = []
    # one text index for the file: each model reader locates attributes in the same text, and
    # reading it once per model made a world of 3000 models take 40 s instead of 2
    sources = SourceIndex()
    containers = [root, *root.findall("world")]
    for container in containers:
        start = len(out)
        for child in container:
            if child.tag == "model":
                out.append(_model(child, version, path, resolver, sources))
                owners.append((child, out[-1]))
            elif child.tag == "include":
                loaded = _included(child, path, resolver)
                if loaded is not None:
                    out.append(loaded)
                    owners.append((child, loaded))
        plugins = tuple(c for c in container if c.tag == "plugin") if container.tag == "world" else ()
        first = next((m for m in out[start:] if m.robot is not None), None)
        if plugins and first is not None and first.robot is not None:
            first.robot = dataclasses.replace(first.robot, world_plugins=plugins)
        for model in out[start:] if container.tag == "world" else ():
            if model.robot is not None:
                model.robot = dataclasses.replace(model.robot, world=container)
    return out


def _model(element: etree._Element, version: tuple[int, int], path: str, resolver: PackageResolver,
           sources: SourceIndex | None = None, **overrides: object) -> Loaded:
    reader = SdfModelReader(path, resolver, SdfValues(sources or SourceIndex()))
    robot = reader.read(element, version, **overrides)  # type: ignore[arg-type]
    diagnostics = reader.diagnostics
    robot = dataclasses.replace(robot, diagnostics=tuple(diagnostics))
    return Loaded(path, "sdf", robot, diagnostics, [path, *reader.files])


def _lights_and_actors(root: etree._Element) -> list[str]:
    """The tags of the ``<light>`` and ``<actor>`` children of ``<sdf>``: besides ``<model>`` and
    ``<world>``, what an SDF file or an included one may hold (libsdformat reads all four)."""
    return [child.tag for child in root if child.tag in ("light", "actor")]


def _included(include: etree._Element, path: str, resolver: PackageResolver) -> Loaded | None:
    """A world-level ``<include>`` as a model (``None`` for the standard sun and ground plane)."""
    found = read_include(include, resolver, path)
    if found.standard:
        return None
    if found.document is None:
        return Loaded(path, "sdf", None, found.diagnostics, [path])
    root = found.document.root
    model = root.find("model") if root.tag == "sdf" else None
    if model is None:
        # a <light> or <actor> is as valid an include as a <model> (Gazebo's own model://sun)
        if root.tag == "sdf" and root.find("world") is None and not _lights_and_actors(root):
            found.diagnostics.append(
                SdfModelMissing.diagnostic(f"'{found.uri}' holds no <model>", span_of(root), element="sdf")
            )
        return (
            Loaded(path, "sdf", None, found.diagnostics, [path, found.path or path])
            if found.diagnostics
            else None
        )
    values = SdfValues(SourceIndex())
    pose_el = include.find("pose")
    name = (include.findtext("name") or "").strip() or None
    static_el = include.find("static")
    static = values.text_bool(include, "static", "include") if static_el is not None else None
    world_pose = values.pose(pose_el, "include/pose").matrix if pose_el is not None else None
    loaded = _model(model, parse_version(root.get("version")), path, resolver,
                    name=name, world_pose=world_pose, static=static)
    loaded.files.insert(1, found.path or path)
    loaded.diagnostics[:0] = found.diagnostics + values.diagnostics
    if loaded.robot is not None:
        loaded.robot = dataclasses.replace(loaded.robot, diagnostics=tuple(loaded.diagnostics))
    return loaded
