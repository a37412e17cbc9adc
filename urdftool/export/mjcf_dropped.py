"""The loss report: every source element MJCF does not carry, as ``conversion-dropped``.

Dropped, one finding per element: each child of a ``<gazebo>`` block
(plugins, sensors, contact and material settings) except the ``<mu1>``/``<mu2>``
written as geom friction (:func:`~urdftool.export.mjcf_geoms.carried_friction`), top-level ``<sensor>``
elements, transmissions and ``ros2_control`` blocks whose joints get no
actuator (all of them with ``--actuators none``), other top-level extensions,
and SDF-only or simulator elements inside links and joints.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Sequence

from lxml import etree

from urdftool.catalogue.conversion import ConversionDropped
from urdftool.diagnostics import Diagnostic
from urdftool.export.mjcf_geoms import carried_friction
from urdftool.model import Extension, Robot
from urdftool.parse.locate import span_of
from urdftool.source import Span


def _tag(element: etree._Element) -> str:
    return etree.QName(element).localname if isinstance(element.tag, str) else str(element.tag)


def _children(element: etree._Element) -> Iterator[etree._Element]:
    return (c for c in element if isinstance(c.tag, str))


def _drop(message: str, element: etree._Element | None, where: str, reason: str,
          fallback: Span | None = None) -> Diagnostic:
    span = span_of(element) if element is not None else None
    return ConversionDropped.diagnostic(message, span or fallback, element=where,
                                        data={"element": where, "reason": reason})


def _gazebo(ext: Extension, carried: Sequence[etree._Element]) -> Iterator[Diagnostic]:
    reference = ext.attributes.get("reference")
    block = f"gazebo[{reference}]" if reference else "gazebo"
    if ext.element is None:
        return
    for child in _children(ext.element):
        if any(child is element for element in carried):
            continue  # written as the link's geom friction (docs/mjcf.md, Mapping)
        tag = _tag(child)
        if tag in ("mu1", "mu2") and reference:
            yield _drop(f"{block}: <{tag}> {(child.text or child.get('value') or '').strip()!r} is not "
                        "carried: MuJoCo's friction is isotropic and the export writes the smaller "
                        "coefficient of mu1 and mu2 (or the value is no coefficient, or names no link)",
                        child, f"{block}/{tag}", f"Gazebo <{tag}> is not exported")
            continue
        label = child.get("name") or child.get("filename") or child.get("type")
        what = f"<{tag}{' ' + repr(label) if label else ''}>"
        yield _drop(f"{block}: {what} has no MJCF equivalent", child, f"{block}/{tag}",
                    f"Gazebo <{tag}> is not exported")


def _joint_names(element: etree._Element) -> list[str]:
    return [j.get("name", "") for j in element.iter() if isinstance(j.tag, str) and _tag(j) == "joint"]


def _control(ext: Extension, actuated: set[str]) -> Iterator[Diagnostic]:
    joints = _joint_names(ext.element) if ext.element is not None else []
    missing = [j for j in joints if j not in actuated]
    if joints and not missing:
        return
    name = ext.attributes.get("name", "")
    where = f"{ext.tag}[{name}]" if name else ext.tag
    reason = ("no actuator carries its joints (use --actuators auto)" if not actuated
              else f"joints without an actuator: {', '.join(missing) or '(none named)'}")
    yield _drop(f"{where}: {reason}", ext.element, where, reason, ext.span)


def dropped_extensions(robot: Robot, actuated: Iterable[str]) -> list[Diagnostic]:
    """``conversion-dropped`` findings for everything outside links and joints proper."""
    actuated_set = set(actuated)
    found: list[Diagnostic] = []
    carried = carried_friction(robot)
    for ext in robot.extensions:
        if ext.tag == "gazebo":
            found.extend(_gazebo(ext, carried))
        elif ext.tag in ("transmission", "ros2_control"):
            found.extend(_control(ext, actuated_set))
        else:
            name = ext.attributes.get("name")
            where = f"{ext.tag}[{name}]" if name else ext.tag
            found.append(_drop(f"<{ext.tag}> has no MJCF equivalent", ext.element, where,
                               f"<{ext.tag}> is not exported", ext.span))
    for link in robot.links:
        for ext in link.extensions:
            where = f"link[{link.name}]/{ext.tag}"
            found.append(_drop(f"{where}: <{ext.tag}> inside a link is not exported", ext.element, where,
                               "not part of URDF's link", ext.span or link.span))
    for joint in robot.joints:
        for ext in joint.extensions:
            where = f"joint[{joint.name}]/{ext.tag}"
            found.append(_drop(f"{where}: <{ext.tag}> inside a joint is not exported", ext.element, where,
                               "not part of URDF's joint", ext.span or joint.span))
    return found
