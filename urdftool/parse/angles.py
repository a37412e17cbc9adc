"""SDF ``<pose>`` angles that read as degrees (``angle-looks-like-degrees``), in an SDF document
and in the ``<gazebo>`` blocks of a URDF: the one scan both readers share."""

from __future__ import annotations

from collections.abc import Callable, Iterator

from lxml import etree

from urdftool.catalogue.units import ONE_TURN, AngleLooksLikeDegrees
from urdftool.diagnostics import Diagnostic
from urdftool.parse.values import parse_number
from urdftool.source import Span

#: what libsdformat reads as true in a ``degrees`` attribute (as :meth:`SdfValues.pose` does)
_TRUE = frozenset({"1", "true", "True", "TRUE"})


def degree_poses(
    element: etree._Element, locate: Callable[[etree._Element], Span | None]
) -> Iterator[Diagnostic]:
    """A finding for every ``<pose>`` at or below *element* whose roll, pitch or yaw reads as
    degrees. A pose with ``degrees="true"`` or a quaternion is what it says; a malformed pose is
    the model reader's to report (``invalid-number``), not this scan's."""
    for pose in element.iter("pose"):
        if pose.get("degrees", "false") in _TRUE or pose.get("rotation_format") == "quat_xyzw":
            continue
        words = (pose.text or "").split()
        if len(words) != 6:
            continue
        angles = [v for v in (parse_number(w) for w in words[3:]) if v is not None]
        if len(angles) != 3 or max(abs(v) for v in angles) <= ONE_TURN:
            continue
        parent = pose.getparent()
        owner = parent.tag if parent is not None and isinstance(parent.tag, str) else "sdf"
        name = parent.get("name") if parent is not None else None
        where = f"{owner}[{name}]/pose" if name else f"{owner}/pose"
        written = f"<{owner} name={name!r}><pose>" if name else f"<{owner}><pose>"
        found = AngleLooksLikeDegrees.judge(angles, locate(pose), where, written, sdf=True)
        if found is not None:
            yield found
