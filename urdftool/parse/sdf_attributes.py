"""SDFormat attributes that the spec requires, or that a version dropped: ``<plugin filename>``,
``<sensor name type>`` (``missing-attribute``) and ``<pose frame>`` in a 1.7+ file, which
libsdformat ignores (``unknown-attribute``). Part of the file-level checks of
:mod:`urdftool.parse.sdf_semantics`."""

from __future__ import annotations

from collections.abc import Iterator

from lxml import etree

from urdftool.catalogue.syntax import MissingAttribute, UnknownAttribute
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.parse.locate import span_of
from urdftool.parse.sdf_spec import custom_element, fmt
from urdftool.parse.sdf_values import SdfValues

Version = tuple[int, int]


def attribute_findings(root: etree._Element, version: Version,
                       values: SdfValues) -> Iterator[Diagnostic]:
    """Attributes the spec requires (``plugin@filename``, ``sensor@name``/``@type``), and the
    ``frame`` of a ``<pose>`` that SDFormat 1.7 replaced by ``relative_to``. A plugin's own
    content is the plugin's, not SDFormat's, and is not walked."""
    stack = [root]
    while stack:
        element = stack.pop()
        for child in element:
            if not isinstance(child.tag, str) or custom_element(child.tag):
                continue
            if child.tag == "plugin":
                yield from _required(child, ("filename",))
                continue
            if child.tag == "sensor":
                yield from _required(child, ("name", "type"))
            elif child.tag == "pose" and version >= (1, 7) and child.get("frame") is not None:
                yield _pose_frame(child, version, values)
            stack.append(child)


def _required(element: etree._Element, attributes: tuple[str, ...]) -> Iterator[Diagnostic]:
    for attribute in attributes:
        if (element.get(attribute) or "").strip():
            continue
        label = f" '{element.get('name')}'" if element.get("name") else ""
        yield MissingAttribute.diagnostic(
            f"<{element.tag}>{label} has no '{attribute}' attribute, which SDFormat requires; "
            "libsdformat refuses the file",
            span_of(element), element=str(element.tag),
            help=("name the library to load, e.g. filename=\"gz-sim-diff-drive-system\""
                  if attribute == "filename" else f"write {attribute}=\"…\""),
            data={"attribute": attribute})


def _pose_frame(pose: etree._Element, version: Version, values: SdfValues) -> Diagnostic:
    """``<pose frame="…">`` in a 1.7+ file: libsdformat drops the attribute with a warning, so
    the pose is read in the default frame, not in the one named (an error unless empty)."""
    frame = (pose.get("frame") or "").strip()
    owner = pose.getparent()
    where = f"{owner.tag}[{owner.get('name') or ''}]/pose" if owner is not None else "pose"
    return UnknownAttribute.diagnostic(
        f"{where}: 'frame' is not an attribute of <pose> in SDFormat {fmt(version)} "
        "(1.7 replaced it by 'relative_to'); libsdformat ignores it"
        + (f", so the pose is not relative to '{frame}'" if frame else ""),
        values.attr_span(pose, "frame"), element=where,
        severity=Severity.ERROR if frame else None,
        help=(f'write <pose relative_to="{frame}">' if frame else 'remove frame=""'),
        data={"attribute": "frame", "frame": frame})
