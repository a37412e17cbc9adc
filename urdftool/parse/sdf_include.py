"""``<include>``: finding the model a URI names and reading its SDF file.

``model://NAME`` is looked up by the package resolver (``--package``,
``--package-path``, ``GZ_SIM_RESOURCE_PATH``, ``IGN_GAZEBO_RESOURCE_PATH``,
``GAZEBO_MODEL_PATH``, the folders around the including file). The folder's
``model.config`` names the SDF file (the highest ``<sdf version>`` listed);
without one, ``model.sdf`` is read. A URI may also be a folder or an ``.sdf``
file path; a relative path not found beside the including file is looked up as a model
name, as gz-sim's resource path does. ``model://sun`` and ``model://ground_plane`` are Gazebo's standard
light and ground and need no files.
"""

from __future__ import annotations

import os
from dataclasses import field
from pathlib import Path

from lxml import etree

from urdftool.catalogue.sdf import ModelIncludeNotFound
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.parse.locate import span_of
from urdftool.parse.packages import PackageResolver
from urdftool.parse.xmlio import XmlDocument, read_file
from urdftool.records import record
from urdftool.targets.gazebo_classic_models import database_model, read_by_classic

#: Gazebo's bundled models, recognised by name without their files
STANDARD_MODELS = frozenset({"sun", "ground_plane"})


@record(frozen=False)
class IncludedFile:
    """The document an include leads to (``None`` when it could not be read)."""

    uri: str
    path: str | None
    document: XmlDocument | None
    diagnostics: list[Diagnostic] = field(default_factory=list)
    standard: bool = False


def include_uri(include: etree._Element) -> str:
    uri = include.find("uri")
    return (uri.text or "").strip() if uri is not None and uri.text else ""


def standard_model(uri: str) -> str | None:
    """``sun``/``ground_plane`` for their ``model://`` URIs, else ``None``."""
    if uri.startswith("model://"):
        name = uri[len("model://"):].strip("/")
        if name in STANDARD_MODELS:
            return name
    return None


def read_include(include: etree._Element, resolver: PackageResolver, base: str) -> IncludedFile:
    """Resolve and parse the SDF file that *include* names; report what cannot be found."""
    uri = include_uri(include)
    where = span_of(include)
    if not uri:
        return IncludedFile(uri, None, None, [
            ModelIncludeNotFound.diagnostic("<include> has no <uri>", where, element="include")
        ])
    folder_or_file = _locate(uri, resolver, base)
    sdf_path = _model_file(folder_or_file) if folder_or_file else None
    if sdf_path is None:
        if standard_model(uri):
            return IncludedFile(uri, None, None, standard=True)
        # Fetched by the simulator on first load, so not missing: a Gazebo Fuel URL (gz-sim), or a
        # model of Gazebo Classic's online database in a world Classic reads. urdftool reads no
        # network, so the model goes unchecked, which is worth saying.
        if uri.startswith(("http://", "https://")):
            return _fetched(include, uri, "is fetched from the web by Gazebo; urdftool does not download "
                            "it", "download the model and include it by model:// with --package-path "
                            "or GZ_SIM_RESOURCE_PATH")
        if database_model(uri) and read_by_classic(include):
            return _fetched(include, uri, "is not on this machine; Gazebo Classic downloads it from its "
                            "model database on first load", "download the model (osrf/gazebo_models) "
                            "and pass its folder's parent with --package-path or GAZEBO_MODEL_PATH")
        lookup = resolver.resolve_uri(uri, base)
        tried = "; ".join(lookup.tried[:6]) or "nowhere"
        return IncludedFile(uri, None, None, [
            ModelIncludeNotFound.diagnostic(
                f"included model '{uri}' was not found",
                span_of(include.find("uri")) or where,
                element="include",
                help="add the folder that holds it with --package-path or GZ_SIM_RESOURCE_PATH"
                f" (tried: {tried})",
                data={"uri": uri, "tried": lookup.tried},
            )
        ])
    document, problems = read_file(sdf_path)
    return IncludedFile(uri, sdf_path, document, problems)


def _fetched(include: etree._Element, uri: str, how: str, check_it: str) -> IncludedFile:
    """An include the simulator downloads: one info saying it is not checked, and how to check it."""
    return IncludedFile(uri, None, None, [
        ModelIncludeNotFound.diagnostic(
            f"included model '{uri}' {how}, so it is not checked",
            span_of(include.find("uri")) or span_of(include), element="include", severity=Severity.INFO,
            help=f"to check it too, {check_it}", data={"uri": uri, "remote": True},
        )
    ])


def _locate(uri: str, resolver: PackageResolver, base: str) -> str | None:
    if uri.startswith("model://"):
        rest = uri[len("model://"):].strip("/")
        name, _, sub = rest.partition("/")
        found = resolver.find_model(name, base)
        if found.path is None:
            return None
        target = Path(found.path) / sub if sub else Path(found.path)
        return str(target) if target.exists() else None
    lookup = resolver.resolve_uri(uri, base)
    if lookup.path and os.path.exists(lookup.path):
        return lookup.path
    if "://" not in uri and not os.path.isabs(uri):
        # A bare name (PX4's <uri>x500</uri>): sdformat hands what it cannot find to gz-sim's
        # find-file callback, which looks it up on the resource path, as it does model://NAME.
        return _locate("model://" + uri, resolver, base)
    return None


def _model_file(location: str) -> str | None:
    """The SDF file of a model folder (by ``model.config``), or *location* if it is a file."""
    path = Path(location)
    if path.is_file():
        return str(path)
    config = path / "model.config"
    if config.is_file():
        best = _config_sdf(config)
        if best and (path / best).is_file():
            return str(path / best)
    fallback = path / "model.sdf"
    return str(fallback) if fallback.is_file() else None


def _config_sdf(config: Path) -> str | None:
    document, _problems = read_file(str(config))
    if document is None:
        return None
    entries = []
    for element in document.root.iter("sdf"):
        version = element.get("version", "0")
        try:
            key = tuple(int(p) for p in version.split("."))
        except ValueError:
            key = (0,)
        entries.append((key, (element.text or "").strip()))
    entries = [e for e in entries if e[1]]
    return max(entries)[1] if entries else None
