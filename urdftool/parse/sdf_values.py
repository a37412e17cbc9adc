"""Numbers written as element text, the SDF way (``<mass>1.2</mass>``, ``<pose>0 0 1 0 0 0</pose>``).

URDF puts numbers in attributes; SDF puts most of them in element text. The
reader here extends :class:`~urdftool.parse.values.ValueReader` with the same
behaviour for text: a malformed value is reported (``invalid-number``,
``wrong-vector-length``) at the element's position and treated as unwritten.
"""

from __future__ import annotations

import math
import re

from lxml import etree

from urdftool.catalogue.syntax import InvalidNumber, UnexpandedSubstitution, WrongVectorLength
from urdftool.diagnostics import Severity
from urdftool.model import Pose
from urdftool.model.pose import Matrix, homogeneous, quaternion_to_matrix
from urdftool.parse.locate import span_of
from urdftool.parse.values import (
    UNBOUNDED,
    ValueReader,
    clip,
    hint_for,
    number_word,
    parse_limit,
    parse_number,
)

_TRUE = {"1", "true", "True", "TRUE"}

#: The decimal number std::stod reads at the start of a text (libsdformat's scalar parse).
_LEADING_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
_INF = {"inf", "infinity"}


def _infinity(text: str) -> float:
    return -math.inf if text.startswith("-") else math.inf

_FALSE = {"0", "false", "False", "FALSE"}


class SdfValues(ValueReader):
    """A :class:`ValueReader` that also reads numbers, vectors, booleans and poses from element text."""

    def child(self, parent: etree._Element | None, tag: str) -> etree._Element | None:
        """The first child element named *tag* (SDF keeps the first of a repeated element)."""
        if parent is None:
            return None
        found = parent.find(tag)
        return found if found is not None and isinstance(found.tag, str) else None

    def raw_text(self, element: etree._Element, where: str) -> str | None:
        text = (element.text or "").strip()
        if self.check_substitutions and ("${" in text or "$(" in text):
            self.diagnostics.append(
                UnexpandedSubstitution.diagnostic(
                    f"{where}: <{element.tag}>{text}</{element.tag}> contains an unexpanded substitution",
                    span_of(element),
                    element=where,
                    help="expand the file (erb, xacro or empy) before loading it, or write the value out",
                    data={"value": text},
                )
            )
            return None
        return text

    def text_numbers(
        self, element: etree._Element | None, where: str, lengths: tuple[int, ...], infinite: bool = False
    ) -> list[float] | None:
        """The element's text as numbers, when their count is one of *lengths*; else ``None`` (reported).

        NaN is never a number; ``inf`` and ``-inf`` are only where *infinite* (joint limits).
        """
        if element is None:
            return None
        raw = self.raw_text(element, where)
        if raw is None:
            return None
        parts = raw.split()
        values = [_infinity(p) if infinite and p.lower().lstrip("+-") in _INF else parse_number(p)
                  for p in parts]
        bad = next((p for p, v in zip(parts, values, strict=True) if v is None), None)
        if bad is not None and lengths == (1,) and len(parts) == 1:
            lenient = self._stod_prefix(element, where, raw)
            if lenient is not None:
                return [lenient]
        if bad is not None:
            self.diagnostics.append(
                InvalidNumber.diagnostic(
                    f"{where}: <{element.tag}>{clip(raw)}</{element.tag}> is not {number_word(bad)}"
                    + (f" ('{clip(bad)}')" if bad != raw else ""),
                    span_of(element),
                    element=where,
                    help="separate values with spaces, not commas" if "," in raw else hint_for(bad),
                    data={"value": raw},
                )
            )
            return None
        if len(values) not in lengths:
            expected = " or ".join(str(n) for n in lengths)
            self.diagnostics.append(
                WrongVectorLength.diagnostic(
                    f"{where}: <{element.tag}>{raw}</{element.tag}> has {len(values)} value"
                    f"{'s' if len(values) != 1 else ''}, expected {expected}",
                    span_of(element),
                    element=where,
                    data={"value": raw, "expected": list(lengths), "found": len(values)},
                )
            )
            return None
        return [v for v in values if v is not None]

    def _stod_prefix(self, element: etree._Element, where: str, raw: str) -> float | None:
        """The number libsdformat reads from a malformed scalar, when it loses no digit; reported
        as a warning. ``None`` (so an error) otherwise.

        libsdformat parses a ``double`` element with ``std::stod``, which reads the longest
        number at the start and ignores the rest: ``2.356194490192345"`` (a stray quote in
        Drake's iiwa14 SDF) is 2.356… to Gazebo and Drake alike. When the rest holds a digit
        (``1,5``, ``1.2.3``) part of the intended value is dropped, and that stays an error.
        """
        found = _LEADING_NUMBER.match(raw)
        if found is None:
            return None
        rest = raw[found.end():]
        value = parse_number(found.group())
        if value is None or any(c.isdigit() for c in rest):
            return None
        self.diagnostics.append(
            InvalidNumber.diagnostic(
                f"{where}: <{element.tag}>{clip(raw)}</{element.tag}> is not a number; libsdformat "
                f"reads {found.group()} and ignores '{clip(rest)}'",
                span_of(element),
                element=where,
                severity=Severity.WARNING,  # every SDF consumer (libsdformat) reads the same value
                help=f"write {found.group()}",
                data={"value": raw, "read": value},
            )
        )
        return value

    def text_number(
        self, parent: etree._Element | None, tag: str, where: str, default: float | None = None,
        infinite: bool = False,
    ) -> float | None:
        """The number in child ``<tag>`` of *parent*, or *default* when absent or malformed."""
        element = self.child(parent, tag)
        values = self.text_numbers(element, f"{where}/{tag}", (1,), infinite)
        return values[0] if values else default

    def text_limit(self, parent: etree._Element | None, tag: str, where: str) -> float | None:
        """A joint limit in child ``<tag>``: ``None`` when absent, malformed (reported) or
        infinite (``inf``, ``-inf``, ``1e400``: SDF's way to write "no limit", carried as absent)."""
        element = self.child(parent, tag)
        if element is None:
            return None
        raw = self.raw_text(element, f"{where}/{tag}")
        if raw is not None and len(raw.split()) == 1 and parse_limit(raw) is UNBOUNDED:
            return None
        return self.text_number(parent, tag, where)

    def text_vector(
        self, parent: etree._Element | None, tag: str, where: str, length: int = 3
    ) -> tuple[float, ...] | None:
        values = self.text_numbers(self.child(parent, tag), f"{where}/{tag}", (length,))
        return tuple(values) if values else None

    def text_bool(self, parent: etree._Element | None, tag: str, where: str, default: bool = False) -> bool:
        element = self.child(parent, tag)
        if element is None:
            return default
        raw = (element.text or "").strip()
        if raw in _TRUE:
            return True
        if raw in _FALSE:
            return False
        self.diagnostics.append(
            InvalidNumber.diagnostic(
                f"{where}/{tag}: <{tag}>{raw}</{tag}> is not a boolean (true, false, 1 or 0)",
                span_of(element),
                element=f"{where}/{tag}",
                data={"value": raw},
            )
        )
        return default

    def pose(self, element: etree._Element | None, where: str) -> Pose:
        """A ``<pose>`` element as a :class:`Pose` (identity when absent or malformed).

        Reads ``x y z roll pitch yaw`` (radians, or degrees with ``degrees="true"``)
        and, with ``rotation_format="quat_xyzw"`` (SDF 1.9+), ``x y z qx qy qz qw``.
        """
        if element is None or not (element.text or "").strip():
            return Pose()  # <pose/> and <pose relative_to="F"/> are the identity
        quaternion = element.get("rotation_format", "euler_rpy") == "quat_xyzw"
        values = self.text_numbers(element, where, (7,) if quaternion else (6,))
        if values is None:
            return Pose()
        xyz = (values[0], values[1], values[2])
        if quaternion:
            qx, qy, qz, qw = values[3:7]
            rotation: Matrix = quaternion_to_matrix((qw, qx, qy, qz))
            return Pose.from_matrix(homogeneous(rotation, xyz))
        rpy = (values[3], values[4], values[5])
        if element.get("degrees", "false") in _TRUE:
            rpy = (math.radians(rpy[0]), math.radians(rpy[1]), math.radians(rpy[2]))
        return Pose(xyz, rpy)

