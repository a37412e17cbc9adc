"""What a world's ``<state>`` block may hold, per SDFormat version, and the elements it may not.

Gazebo (classic) writes a ``<state>`` block when a world is saved from its GUI:
a snapshot of every model's pose, each link's velocity, acceleration and
wrench, joint angles and light poses. Its ``<model>`` and ``<link>`` are not
the ``<model>`` and ``<link>`` of ``model.sdf``/``link.sdf`` but the state
elements of ``state.sdf``, ``model_state.sdf``, ``link_state.sdf`` and
``light_state.sdf`` (1.4 defines them inline in ``state.sdf``). The table
below was read off those descriptions (``sdf/1.x/*state.sdf`` in libsdformat).
Versions 1.4 to 1.11; SDFormat 1.12 renames the state elements
(``<model_state>``, ``<link_state>``, ...), and urdftool reads 1.12 files with
the rules of 1.11.

``<insertions>`` holds whole models and lights (``model.sdf``, ``light.sdf``):
the structural pass checks those as it checks any model.
"""

from __future__ import annotations

from collections.abc import Iterator

from lxml import etree

from urdftool.catalogue.suggest import did_you_mean
from urdftool.catalogue.syntax import UnknownElement
from urdftool.diagnostics import Diagnostic
from urdftool.parse.locate import span_of

Version = tuple[int, int]
_ALL: tuple[Version, Version] = ((1, 4), (1, 11))

#: state context -> child tag -> (first and last version defining it, the child's own context or None)
STATE: dict[str, dict[str, tuple[tuple[Version, Version], str | None]]] = {
    "state": {
        "sim_time": (_ALL, None), "wall_time": (_ALL, None), "real_time": (_ALL, None),
        "iterations": (((1, 5), (1, 11)), None), "insertions": (_ALL, "insertions"),
        "deletions": (_ALL, "deletions"), "model": (_ALL, "model"),
        "light": (((1, 5), (1, 11)), "light"),
    },
    #: whole models and lights: their contents are checked as any model's
    "insertions": {"model": (_ALL, None), "light": (((1, 6), (1, 11)), None)},
    "deletions": {"name": (_ALL, None)},
    "model": {
        "pose": (_ALL, None), "joint": (_ALL, "joint"), "link": (_ALL, "link"),
        "model": (((1, 5), (1, 11)), "model"), "frame": (((1, 5), (1, 11)), None),
        "scale": (((1, 6), (1, 11)), None),
    },
    "joint": {"angle": (_ALL, None)},
    "link": {
        "pose": (_ALL, None), "velocity": (_ALL, None), "acceleration": (_ALL, None),
        "wrench": (_ALL, None), "collision": (_ALL, "collision"), "frame": (((1, 5), (1, 6)), None),
    },
    "collision": {"pose": (((1, 4), (1, 4)), None)},
    "light": {"pose": (((1, 5), (1, 11)), None), "frame": (((1, 5), (1, 6)), None)},
}


def _fmt(version: Version) -> str:
    return f"{version[0]}.{version[1]}"


def state_findings(state: etree._Element, version: Version) -> list[Diagnostic]:
    """``unknown-element`` warnings for what ``<state>`` holds that its version does not define."""
    return list(_walk(state, "state", version))


def _walk(element: etree._Element, context: str, version: Version) -> Iterator[Diagnostic]:
    allowed = STATE[context]
    for child in element:
        if not isinstance(child.tag, str) or ":" in child.tag or child.tag.startswith("{"):
            continue  # comments, and custom elements (1.6+), which libsdformat keeps for their tool
        tag = child.tag
        known = allowed.get(tag)
        if known is None:
            message = (f"<{tag}> is not an SDFormat element of a <{context}> in <state>"
                       + did_you_mean(tag, list(allowed)))
            versions = None
        elif not known[0][0] <= version <= known[0][1]:
            first, last = known[0]
            versions = [_fmt(first), _fmt(last)]
            message = (f"<{tag}> in a <{context}> of <state> is SDFormat {_fmt(first)}+, but the file "
                       f"declares version {_fmt(version)}" if first > version else
                       f"<{tag}> in a <{context}> of <state> was removed after SDFormat {_fmt(last)}; "
                       f"the file declares version {_fmt(version)}")
        else:
            if known[1] is not None:
                yield from _walk(child, known[1], version)
            continue
        yield UnknownElement.diagnostic(
            message, span_of(child), element=f"state/{context}",
            help="libsdformat copies the element and otherwise ignores it",
            data={"element": tag, "parent": f"state/{context}", "versions": versions})


def in_state(element: etree._Element) -> bool:
    """Whether *element* is part of a ``<state>`` snapshot (not of a model ``<insertions>`` holds)."""
    for ancestor in element.iterancestors():
        if ancestor.tag == "insertions":
            return False
        if ancestor.tag == "state":
            world = ancestor.getparent()
            return world is not None and world.tag == "world"
    return False
