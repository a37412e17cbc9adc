"""What the diagram says about a link, a joint and a joint origin, in words and units.

Numbers are rounded for reading, not for computing: lengths to 0.1 mm, angles
to 1e-4 rad (and shown as fractions of π when they are one, as ``π/2``), masses
and limits to four significant figures. Units follow the joint type: rad, N·m
and rad/s for rotation; m, N and m/s for translation.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence

from urdftool.export.graph.dot import Html, html_text
from urdftool.model import Joint, JointType, Pose
from urdftool.model.robot import Limit

#: fill colour of a joint ellipse, by type (a colour-blind-safe pastel palette)
JOINT_COLOURS: dict[JointType, str] = {
    JointType.REVOLUTE: "#a6cee3",
    JointType.CONTINUOUS: "#b2df8a",
    JointType.PRISMATIC: "#fdbf6f",
    JointType.FIXED: "#e0e0e0",
    JointType.FLOATING: "#cab2d6",
    JointType.PLANAR: "#ffff99",
    JointType.SPHERICAL: "#fb9a99",
    JointType.UNIVERSAL: "#8dd3c7",
    JointType.REVOLUTE2: "#80b1d3",
    JointType.SCREW: "#bebada",
    JointType.GEARBOX: "#d9d9d9",
}

_ROTATING = {
    JointType.REVOLUTE,
    JointType.CONTINUOUS,
    JointType.SPHERICAL,
    JointType.UNIVERSAL,
    JointType.REVOLUTE2,
    JointType.GEARBOX,
}
# Joints whose motion is not about or along one axis: an axis would mislead.
_NO_AXIS = {JointType.FIXED, JointType.FLOATING, JointType.SPHERICAL}
_PI_DENOMINATORS = (1, 2, 3, 4, 6, 12)
_SMALL = 9


def number(value: float, decimals: int = 4) -> str:
    """*value* rounded to *decimals* places, trailing zeros dropped (``0.1``, ``-2``, ``0``)."""
    if not math.isfinite(value):
        return str(value)
    if value != 0 and abs(value) < 10**-decimals:
        return f"{value:.2g}"  # a tiny value is information, not zero
    text = f"{round(value, decimals):.{decimals}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def significant(value: float, digits: int = 4) -> str:
    """*value* to *digits* significant figures, without an exponent in the usual range."""
    if not math.isfinite(value):
        return str(value)
    if value == 0:
        return "0"
    if 1e-3 <= abs(value) < 1e6:
        decimals = max(0, digits - 1 - math.floor(math.log10(abs(value))))
        return number(value, decimals)
    return f"{value:.{digits}g}"


def angle(value: float) -> str:
    """Radians, as a fraction of π when it is one within 1e-4 rad (``π/2``, ``-3π/4``)."""
    for denominator in _PI_DENOMINATORS:
        numerator = value * denominator / math.pi
        whole = round(numerator)
        if whole != 0 and abs(numerator - whole) * math.pi / denominator < 1e-4:
            if math.gcd(whole, denominator) != 1:
                continue
            sign = "-" if whole < 0 else ""
            coefficient = "" if abs(whole) == 1 else str(abs(whole))
            return f"{sign}{coefficient}π" + ("" if denominator == 1 else f"/{denominator}")
    return number(value)


def vector(values: Iterable[float], fmt: Callable[[float], str] = number) -> str:
    """Space-separated numbers, as in URDF attributes."""
    return " ".join(fmt(v) for v in values)


def origin_text(pose: Pose) -> str:
    """``xyz 0.1 0 0.3`` and, when rotated, ``rpy 0 0 π/2``, on two lines; empty for identity."""
    lines = []
    if any(number(v) != "0" for v in pose.xyz):
        lines.append(f"xyz {vector(pose.xyz)}")
    if any(angle(v) != "0" for v in pose.rpy):
        lines.append(f"rpy {vector(pose.rpy, angle)}")
    return "\n".join(lines)


def units(joint_type: JointType) -> tuple[str, str, str]:
    """(position, effort, velocity) units for a joint type."""
    if joint_type in _ROTATING:
        return "rad", "N·m", "rad/s"
    return "m", "N", "m/s"


def limit_lines(joint: Joint) -> list[str]:
    """``[-1.571, 1.571] rad`` and ``30 N·m · 2 rad/s`` for the joint's limits."""
    limit: Limit | None = joint.limit
    if limit is None or joint.type is JointType.FIXED:
        return []
    position, effort, velocity = units(joint.type)
    lines = []
    if joint.type is not JointType.CONTINUOUS and (
        limit.lower is not None or limit.upper is not None
    ):
        low = significant(limit.lower) if limit.lower is not None else "?"
        high = significant(limit.upper) if limit.upper is not None else "?"
        lines.append(f"[{low}, {high}] {position}")
    rates = []
    if limit.effort is not None:
        rates.append(f"{significant(limit.effort)} {effort}")
    if limit.velocity is not None:
        rates.append(f"{significant(limit.velocity)} {velocity}")
    if rates:
        lines.append(" · ".join(rates))
    return lines


def joint_lines(joint: Joint) -> list[str]:
    """The small print under a joint's name: type, axis, limits, mimic."""
    head = joint.type.value
    if joint.type not in _NO_AXIS:
        head += f" · axis {vector(joint.axis)}"
    lines = [head, *limit_lines(joint)]
    if joint.mimic is not None:
        mimic = joint.mimic
        lines.append(
            f"mimics {mimic.joint} ×{significant(mimic.multiplier)}"
            + (
                f" {'+' if mimic.offset >= 0 else '-'}{significant(abs(mimic.offset))}"
                if mimic.offset
                else ""
            )
        )
    return lines


def mass_text(mass: float | None) -> str:
    return "no inertial" if mass is None else f"{significant(mass)} kg"


def html_label(title: str, lines: Sequence[str], notes: Sequence[tuple[str, str]] = ()) -> Html:
    """A bold *title*, smaller *lines*, and coloured *notes* ``(colour, text)``."""
    parts = [f"<B>{html_text(title)}</B>" if title else "<I>(no name)</I>"]
    parts += [f'<FONT POINT-SIZE="{_SMALL}">{html_text(line)}</FONT>' for line in lines]
    parts += [
        f'<FONT POINT-SIZE="{_SMALL}" COLOR="{colour}">{html_text(text)}</FONT>'
        for colour, text in notes
    ]
    return Html("<BR/>".join(parts))
