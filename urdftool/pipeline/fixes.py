"""Fixes for findings whose repair is mechanical, as byte edits of the file the user edits.

Rules stay pure functions of the robot: they say what is wrong and where. This
module, given a finding and the text of the file its location is in, works out
the edit: the attribute value to rewrite, the attribute or element to rename,
the duplicate to drop. Each fix says how safe it is (see docs/fixes.md):

- ``safe``: cannot change what a consumer computes, or restores what the
  author evidently meant (a stray comma in a number, a misspelt attribute with
  one did-you-mean, an axis that is not unit length, a duplicate dropped);
- ``unsafe``: changes physics (limits swapped, a negative mass made positive);
- ``display-only``: shown, never applied: the value in the ``.xacro`` file is an
  expression or property (``${...}``, ``$(arg ...)``), so the literal to change
  is elsewhere, or no value can be chosen for the author.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Callable, Iterable, Sequence

from urdftool.diagnostics import Applicability, Diagnostic, Edit, Fix
from urdftool.parse.urdf_schema import ATTRIBUTES
from urdftool.pipeline.fixtext import SourceText, Tag, escape, local

Provider = Callable[[Diagnostic, SourceText], "Fix | None"]

#: rule name -> the function that proposes its fix
PROVIDERS: dict[str, Provider] = {}

_SUGGESTION = re.compile(r"did you mean '([^']+)'\?")
_FIRST_LINE = re.compile(r"\(line (\d+)\)")


def provides(name: str) -> Callable[[Provider], Provider]:
    def register(function: Provider) -> Provider:
        PROVIDERS[name] = function
        return function

    return register


def fixable_rules() -> tuple[str, ...]:
    """The names of the rules that can propose a fix."""
    return tuple(sorted(PROVIDERS))


class Texts:
    """The files fixes are computed against, each read once."""

    def __init__(self, overrides: dict[str, bytes] | None = None) -> None:
        self._texts: dict[str, SourceText | None] = {}
        self._overrides = overrides or {}

    def get(self, path: str) -> SourceText | None:
        if path not in self._texts:
            data = self._overrides.get(path)
            self._texts[path] = SourceText.of(path, data) if data is not None else SourceText.read(path)
        return self._texts[path]


def fix_for(diagnostic: Diagnostic, texts: Texts) -> Fix | None:
    """The fix for *diagnostic*, or ``None`` when its rule has none or the source does not fit."""
    provider = PROVIDERS.get(diagnostic.name)
    if provider is None or diagnostic.location is None or diagnostic.location.line is None:
        return None
    text = texts.get(diagnostic.location.path)
    if text is None:
        return None
    try:
        return provider(diagnostic, text)
    except (ValueError, IndexError, KeyError, UnicodeDecodeError):  # a source the lexer did not expect
        return None


def attach(diagnostics: Iterable[Diagnostic], texts: Texts | None = None) -> list[Diagnostic]:
    """*diagnostics* with their fixes filled in where one is known."""
    texts = texts or Texts()
    out = []
    for diagnostic in diagnostics:
        fix = diagnostic.fix or fix_for(diagnostic, texts)
        out.append(dataclasses.replace(diagnostic, fix=fix) if fix is not diagnostic.fix else diagnostic)
    return out


# -- helpers ---------------------------------------------------------------------------------


def _element_name(diagnostic: Diagnostic) -> str | None:
    if not diagnostic.element:
        return None
    return diagnostic.element.rsplit("/", 1)[-1].split("[", 1)[0] or None


def _tag(diagnostic: Diagnostic, text: SourceText) -> Tag | None:
    return text.tag_at(diagnostic.location, _element_name(diagnostic))


def _is_expression(raw: str) -> bool:
    return "${" in raw or "$(" in raw


def _value_fix(text: SourceText, tag: Tag, attribute: str, value: str, message: str,
               applicability: Applicability = Applicability.SAFE) -> Fix | None:
    """Rewrite one attribute's value; display-only when the source holds an expression."""
    attr = tag.attribute(attribute)
    if attr is None:
        return None
    edit = Edit(text.span(attr.value_start, attr.value_end), escape(value, attr.quote))
    if _is_expression(attr.raw):
        return _display_only(message, (edit,), f"{attribute}=\"{attr.raw}\" is an expression; change the "
                             "property or argument it reads")
    return Fix(message, (edit,), applicability)


def _display_only(message: str, edits: Sequence[Edit], reason: str) -> Fix:
    return Fix(f"{message} (not applied: {reason})", tuple(edits), Applicability.DISPLAY_ONLY)


def number_text(value: float) -> str:
    """The shortest text that reads back as *value* (``1`` rather than ``1.0``)."""
    if value == 0:
        return "0"
    if value == int(value) and abs(value) < 1e15:
        return str(int(value))
    return repr(value)


def _floats(raw: str) -> list[float] | None:
    try:
        values = [float(t) for t in raw.split()]
    except ValueError:
        return None
    return values if all(math.isfinite(v) for v in values) else None


# -- numbers ---------------------------------------------------------------------------------

_TRAILING_DOT = re.compile(r"([+-]?\d*\.\d+|[+-]?\d+)\.")
_LETTER_O = re.compile(r"[+-]?[\dOo]*\.?[\dOo]*(?:[eE][+-]?\d+)?")


def _repair_token(token: str) -> str | None:
    """A number token with its typo mended, or ``None`` when the intent is not clear."""
    mended = token.strip(",")
    if mended == "":
        return ""
    if _TRAILING_DOT.fullmatch(mended):
        mended = mended[:-1]
    if (_LETTER_O.fullmatch(mended) and re.search(r"\d", mended) and re.search(r"[Oo]", mended)
            and not re.match(r"[+-]?[Oo]+$", mended.split(".")[0] or "0")):
        mended = mended.replace("O", "0").replace("o", "0")
    try:
        number = float(mended)
    except ValueError:
        return None
    return mended if math.isfinite(number) else None


def repair_number(value: str) -> str | None:
    """*value* with stray commas, a trailing dot or a letter O for zero mended; ``None`` if unclear."""
    failed = False

    def one(match: re.Match[str]) -> str:
        nonlocal failed
        mended = _repair_token(match.group(0))
        if mended is None:
            failed = True
            return match.group(0)
        return mended

    mended = re.sub(r"[^\s]+", one, value)
    if failed or mended == value:
        return None
    return mended


@provides("invalid-number")
def _invalid_number(diagnostic: Diagnostic, text: SourceText) -> Fix | None:
    attribute, value = diagnostic.data.get("attribute"), diagnostic.data.get("value")
    tag = _tag(diagnostic, text)
    if tag is None or not isinstance(attribute, str) or not isinstance(value, str):
        return None
    attr = tag.attribute(attribute)
    if attr is None:
        return None
    if _is_expression(attr.raw):
        return None  # the expression's result is what is malformed: nothing literal to mend here
    if attr.value != value:
        return None
    mended = repair_number(value)
    if mended is None:
        return None
    return _value_fix(text, tag, attribute, mended, f'write {attribute}="{mended}"')


# -- names -----------------------------------------------------------------------------------


@provides("unknown-attribute")
def _unknown_attribute(diagnostic: Diagnostic, text: SourceText) -> Fix | None:
    match = _SUGGESTION.search(diagnostic.message)
    attribute = diagnostic.data.get("attribute")
    tag = _tag(diagnostic, text)
    if match is None or tag is None or not isinstance(attribute, str):
        return None
    attr = tag.attribute(attribute)
    suggestion = match.group(1)
    if attr is None or tag.attribute(suggestion) is not None:
        return None  # renaming would write the attribute twice
    return Fix(f"rename attribute '{attribute}' to '{suggestion}'",
               (Edit(text.span(attr.name_start, attr.name_end), suggestion),))


@provides("unknown-element")
def _unknown_element(diagnostic: Diagnostic, text: SourceText) -> Fix | None:
    match = _SUGGESTION.search(diagnostic.message)
    tag = _tag(diagnostic, text)
    if match is None or tag is None or ":" in tag.name:
        return None
    suggestion = match.group(1)
    allowed = ATTRIBUTES.get(suggestion)
    # Only a misspelling: the element's attributes must be the suggested element's (an <inertia>
    # under <link> is a misplaced tensor, not a misspelt <inertial>).
    if allowed is None or any(a.name not in allowed for a in tag.attributes):
        return None
    edits = [Edit(text.span(tag.start + 1, tag.name_end), suggestion)]
    end = text.element_end(tag)
    if end is None:
        return None
    closing = text.end_tag_name(tag, end)
    if closing is not None:
        edits.append(Edit(text.span(*closing), suggestion))
    return Fix(f"rename <{tag.name}> to <{suggestion}>", tuple(edits))


@provides("repeated-element")
def _repeated_element(diagnostic: Diagnostic, text: SourceText) -> Fix | None:
    tag = _tag(diagnostic, text)
    if tag is None:
        return None
    end = text.element_end(tag)
    if end is None:
        return None
    first = _first_of(diagnostic, text, tag)
    edit = Edit(text.span(*text.removal(tag.start, end)), "")
    same = first is not None and _normalised(text, first) == _normalised(text, (tag.start, end))
    if same or local(tag.name) == "material":
        return Fix(f"drop the repeated <{tag.name}> (the first is the one read)", (edit,))
    return Fix(f"drop the repeated <{tag.name}>: it differs from the first, which urdfdom, Pinocchio and "
               "Gazebo read", (edit,), Applicability.UNSAFE)


def _first_of(diagnostic: Diagnostic, text: SourceText, tag: Tag) -> tuple[int, int] | None:
    match = _FIRST_LINE.search(diagnostic.message)
    if match is None:
        return None
    start = text.offset(int(match.group(1)), 1)
    if start is None:
        return None
    found = text.data.find(b"<" + tag.name.encode("utf-8"), start, tag.start)
    first = text.lex(found) if found >= 0 else None
    end = text.element_end(first) if first is not None else None
    return (first.start, end) if first is not None and end is not None else None


def _normalised(text: SourceText, bounds: tuple[int, int]) -> bytes:
    return b" ".join(text.data[bounds[0]:bounds[1]].split())


# -- joints ----------------------------------------------------------------------------------


@provides("non-unit-axis")
def _non_unit_axis(diagnostic: Diagnostic, text: SourceText) -> Fix | None:
    normalized = diagnostic.data.get("normalized")
    tag = _tag(diagnostic, text)
    if tag is None or not isinstance(normalized, list) or len(normalized) != 3:
        return None
    attr = tag.attribute("xyz")
    if attr is None:
        return None
    value = " ".join(number_text(float(v)) for v in normalized)
    written = _floats(attr.value)
    if not _is_expression(attr.raw) and written != [float(v) for v in diagnostic.data.get("axis", [])]:
        return None
    return _value_fix(text, tag, "xyz", value, f'write the unit axis xyz="{value}"')


@provides("inverted-limits")
def _inverted_limits(diagnostic: Diagnostic, text: SourceText) -> Fix | None:
    lower, upper = diagnostic.data.get("lower"), diagnostic.data.get("upper")
    tag = _tag(diagnostic, text)
    if tag is None or not isinstance(lower, float | int) or not isinstance(upper, float | int):
        return None
    if not lower > upper:
        return None  # equal limits: which way the joint should move is not known
    low, up = tag.attribute("lower"), tag.attribute("upper")
    if low is None or up is None:
        return None
    edits = (Edit(text.span(low.value_start, low.value_end), up.raw),
             Edit(text.span(up.value_start, up.value_end), low.raw))
    message = f"swap the limits: lower=\"{up.raw}\" upper=\"{low.raw}\""
    if _is_expression(low.raw) or _is_expression(up.raw):
        return _display_only(message, edits, "the limits are expressions; swap them where they are defined")
    return Fix(message, edits, Applicability.UNSAFE)


@provides("limit-missing-effort-or-velocity")
def _limit_missing(diagnostic: Diagnostic, text: SourceText) -> Fix | None:
    missing = diagnostic.data.get("missing")
    tag = _tag(diagnostic, text)
    if tag is None or not isinstance(missing, list) or not missing:
        return None
    insert = "".join(f' {name}="0"' for name in missing if isinstance(name, str))
    at = tag.end - (2 if tag.self_closing else 1)
    while at > tag.start and text.data[at - 1:at].isspace():
        at -= 1
    return _display_only(
        f"write {' and '.join(missing)}", (Edit(text.span(at, at), insert),),
        "there is no default that keeps the joint drivable (urdfdom rejects the limit, Gazebo and "
        "ros_control read 0): write the actuator's rated values",
    )


# -- inertia ---------------------------------------------------------------------------------


@provides("negative-mass")
def _negative_mass(diagnostic: Diagnostic, text: SourceText) -> Fix | None:
    suggested = diagnostic.data.get("suggested")
    tag = _tag(diagnostic, text)
    if tag is None or not isinstance(suggested, float | int):
        return None
    attr = tag.attribute("value")
    if attr is None:
        return None
    raw = attr.raw.strip()
    value = raw[1:] if raw.startswith("-") and not _is_expression(raw) else number_text(float(suggested))
    return _value_fix(text, tag, "value", value, f'make the mass positive: value="{value}"',
                      Applicability.UNSAFE)
