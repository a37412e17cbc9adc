"""Reading attribute values with located diagnostics.

A malformed value never stops the reader: it is reported at the attribute's
position and the attribute is treated as if it had not been written, so the
rest of the file is still read and checked.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Callable
from dataclasses import field
from typing import Literal, overload

from lxml import etree

from urdftool.catalogue.syntax import (
    InvalidNumber,
    MissingAttribute,
    UnexpandedSubstitution,
    WrongVectorLength,
)
from urdftool.diagnostics import Diagnostic
from urdftool.parse.locate import span_of
from urdftool.records import record
from urdftool.source import SourceIndex, Span, deferred_span

_NUMBER = re.compile(r"^[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?$")
_SUBSTITUTION = re.compile(r"\$[({]")


#: Longest number text read (a double needs at most 17 significant digits; padding beyond is hostile).
MAX_NUMBER_CHARS = 400

#: Largest magnitude read. Nothing in a robot description comes near it, and it keeps
#: every product the rules form (inertia × length², volumes, eigenvalues) finite:
#: ``1e308`` is a finite double, but its square is not.
MAX_MAGNITUDE = 1e50

_INFINITY = {"inf", "+inf", "infinity", "+infinity", "-inf", "-infinity"}


def parse_number(text: str) -> float | None:
    """A finite decimal number, or ``None``.

    The one gate every numeric field of every format goes through: no NaN, no
    infinity, no value that overflows to infinity (``1e309``) or lies beyond
    :data:`MAX_MAGNITUDE` (``1e308``, whose square overflows), no underscores,
    commas or hex. What it refuses is reported as ``invalid-number`` by the
    readers and treated as unwritten, so no model object holds a non-finite value.
    """
    # Robot descriptions repeat a few hundred number texts ("0", "1", "0.05") many times over.
    if text in _NUMBER_TEXTS:
        return _NUMBER_TEXTS[text]
    return _remember(text)


#: Number texts up to this length are memoised (longer ones are rare, or hostile).
_CACHED_CHARS = 40


def _parse(text: str) -> float | None:
    text = text.strip()
    if len(text) > MAX_NUMBER_CHARS or not _NUMBER.match(text):
        return None
    value = float(text)
    return value if abs(value) <= MAX_MAGNITUDE else None


#: Number texts read so far, and what they read as (``None``: not a number), for
#: :func:`parse_number` and :meth:`ValueReader.number`: a dict's lookup costs half a call of an
#: ``lru_cache``, and a reader asks ~20,000 times a pass over example-robot-data.
_NUMBER_TEXTS: dict[str, float | None] = {}
#: Texts kept at most; past it, a new text is read each time.
_NUMBER_TEXTS_KEPT = 16384


def _remember(text: str) -> float | None:
    """:func:`_parse` of a text not in :data:`_NUMBER_TEXTS`, kept there while there is room."""
    value = _parse(text)
    if len(text) <= _CACHED_CHARS and len(_NUMBER_TEXTS) < _NUMBER_TEXTS_KEPT:
        _NUMBER_TEXTS[text] = value
    return value


@functools.lru_cache(maxsize=16384)
def _numbers(raw: str) -> tuple[tuple[float | None, ...], str | None]:
    """Each whitespace-separated part of *raw* read by :func:`parse_number`, and the first part
    that is not a number (``None`` when all are): memoised, since ``xyz="0 0 0"`` is written
    thousands of times."""
    parts = raw.split()
    values = tuple(parse_number(p) for p in parts)
    return values, next((p for p, v in zip(parts, values, strict=True) if v is None), None)


def parse_limit(text: str) -> float | Unbounded | None:
    """A finite number, :data:`UNBOUNDED` for an infinity the format allows as "no limit"
    (``inf``, ``-inf``, or a value beyond :data:`MAX_MAGNITUDE`), or ``None`` when it is not a number."""
    stripped = text.strip()
    if stripped.lower() in _INFINITY:
        return UNBOUNDED
    value = parse_number(stripped)
    if value is None and len(stripped) <= MAX_NUMBER_CHARS and _NUMBER.match(stripped):
        return UNBOUNDED  # out of range: 1e400, 1e300
    return value


class Unbounded:
    """Marker for a limit written as infinite; readers carry it as an absent (unbounded) limit."""

    def __repr__(self) -> str:
        return "UNBOUNDED"


UNBOUNDED = Unbounded()


def _attribute_span(sources: SourceIndex, key: tuple[Span, str]) -> Span:
    return sources.attribute_span(*key)


@record(frozen=False, eq=False)  # one run's state, equal only to itself
class ValueReader:
    """Reads numbers and vectors from elements, collecting diagnostics."""

    sources: SourceIndex
    diagnostics: list[Diagnostic] = field(default_factory=list)
    #: whether ``${…}``/``$(…)`` in values is an error (not after xacro expansion)
    check_substitutions: bool = True
    #: where an element's start tag was written (``XmlDocument.span`` for a document whose
    #: positions are in a table)
    locate: Callable[[etree._Element], Span | None] = span_of
    _attribute_lookup: Callable[[tuple[Span, str]], Span] = field(init=False)

    def __post_init__(self) -> None:
        # The lookup holds the sources, not this reader: a finding in the reader's own list holding
        # the reader would make a cycle, which keeps the document until the collector runs. One
        # lookup per reader, not one per attribute span (every joint limit has two).
        self._attribute_lookup = functools.partial(_attribute_span, self.sources)

    def span(self, element: etree._Element) -> Span | None:
        return self.locate(element)

    def attr_span(self, element: etree._Element, attribute: str, span: Span | None = None) -> Span | None:
        """Where ``attribute=`` is written in *element*'s start tag (looked up when first read);
        *span* is the element's own, when the caller has it already."""
        if span is None:
            span = self.locate(element)
            if span is None:
                return None
        return deferred_span(span.path, self._attribute_lookup, (span, attribute))

    def text(self, element: etree._Element, attribute: str, where: str, required: bool = False) -> str | None:
        value: str | None = element.get(attribute)
        if value is None:
            if required:
                self.diagnostics.append(
                    MissingAttribute.diagnostic(
                        f"{where}: <{element.tag}> needs a '{attribute}' attribute",
                        self.span(element),
                        element=where,
                    )
                )
            return None
        if self.check_substitutions and "$" in value and _SUBSTITUTION.search(value):
            self.diagnostics.append(
                UnexpandedSubstitution.diagnostic(
                    f"{where}: {attribute}=\"{value}\" contains an unexpanded substitution",
                    self.attr_span(element, attribute),
                    element=where,
                    help="expand the file with xacro, or write the value out",
                    data={"attribute": attribute, "value": value},
                )
            )
            return None
        return value

    def number(
        self,
        element: etree._Element,
        attribute: str,
        where: str,
        required: bool = False,
    ) -> float | None:
        """The attribute as a finite float; ``None`` when absent or invalid (reported)."""
        raw = element.get(attribute)
        if raw is None or "$" in raw:  # absent or a substitution: :meth:`text` decides and reports
            raw = self.text(element, attribute, where, required)
            if raw is None:
                return None
        value = _NUMBER_TEXTS[raw] if raw in _NUMBER_TEXTS else _remember(raw)  # parse_number, inlined
        if value is None:
            self._invalid(element, attribute, where, raw)
        return value

    @overload
    def vector(
        self, element: etree._Element, attribute: str, where: str, length: Literal[3] = 3,
        required: bool = False,
    ) -> tuple[float, float, float] | None: ...

    @overload
    def vector(
        self, element: etree._Element, attribute: str, where: str, length: int, required: bool = False,
    ) -> tuple[float, ...] | None: ...

    def vector(
        self,
        element: etree._Element,
        attribute: str,
        where: str,
        length: int = 3,
        required: bool = False,
    ) -> tuple[float, ...] | None:
        """The attribute as *length* finite floats; ``None`` when absent or invalid (reported)."""
        raw = element.get(attribute)
        if raw is None or "$" in raw:  # absent or a substitution: :meth:`text` decides and reports
            raw = self.text(element, attribute, where, required)
            if raw is None:
                return None
        values, bad = _numbers(raw) if len(raw) <= _CACHED_CHARS * 4 else _numbers.__wrapped__(raw)
        if bad is not None:
            self._invalid(element, attribute, where, raw, bad)
            return None
        if len(values) != length:
            self.diagnostics.append(
                WrongVectorLength.diagnostic(
                    f"{where}: {attribute}=\"{raw}\" has {len(values)} value"
                    f"{'s' if len(values) != 1 else ''}, expected {length}",
                    self.attr_span(element, attribute),
                    element=where,
                    data={"attribute": attribute, "value": raw, "expected": length, "found": len(values)},
                )
            )
            return None
        return values  # type: ignore[return-value]  # no None in it (tested above); cast() costs a call

    def _invalid(
        self, element: etree._Element, attribute: str, where: str, raw: str, bad: str | None = None
    ) -> None:
        token = bad if bad is not None else raw
        hint = hint_for(token)
        self.diagnostics.append(
            InvalidNumber.diagnostic(
                f"{where}: {attribute}=\"{clip(raw)}\" is not {number_word(token)}"
                + (f" ('{token}')" if bad is not None and bad != raw else ""),
                self.attr_span(element, attribute),
                element=where,
                help=hint,
                data={"attribute": attribute, "value": raw},
            )
        )


def number_word(token: str) -> str:
    """What *token* failed to be, for messages: a finite number (NaN, infinity), one in range
    (``1e309``, ``1e300``), or a number at all."""
    stripped = token.strip()
    if stripped.lower() in {"nan", "+nan", "-nan", *_INFINITY}:
        return "a finite number"
    if _NUMBER.match(stripped):
        return "a finite number in range"
    return "a number"


def clip(raw: str, limit: int = 80) -> str:
    """*raw* shortened for a message (hostile values can be megabytes long)."""
    return raw if len(raw) <= limit else raw[:limit] + "…"


def hint_for(token: str) -> str | None:
    stripped = token.strip().rstrip(".,;")
    if stripped != token.strip() and parse_number(stripped) is not None:
        return f"did you mean {stripped}? (stray '{token.strip()[len(stripped):]}')"
    if "," in token:
        return "separate values with spaces, not commas"
    if token.strip().lower() in {"nan", "+nan", "-nan", *_INFINITY}:
        return "use a finite value"
    if _NUMBER.match(token.strip()):
        return f"the value is out of range (beyond ±{MAX_MAGNITUDE:g}); use a finite value"
    return None
