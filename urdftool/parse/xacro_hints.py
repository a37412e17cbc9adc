"""Help for a xacro failure whose cause sits elsewhere than where xacro stopped.

``<xacro:property name="base_mass" value="0.3,"/>`` is text to xacro, so it fails
later, where ``${base_mass / 12.0}`` is evaluated: "unsupported operand type(s)
for /: 'str' and 'float'". The help names the property whose value is not a
number, where it is written, and the number it was probably meant to be.

"name 'shoulder_rpy' is not defined" has two causes written elsewhere, both from
xacro files of the Kinetic era that the in-order xacro of Noetic and ROS 2 stops
on: the property is written ``<property>``, without the ``xacro:`` prefix (plain
XML since Noetic), or it is defined after its first use (read in document order
since Melodic). The help names which, and where.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Iterator

#: the expression xacro names in its message, and the names in it
_EXPRESSION = re.compile(r"when evaluating expression '([^']*)'")
_NAME = re.compile(r"[A-Za-z_]\w*")
#: a text value where a number was expected: Python's words for that
_TEXT_AS_NUMBER = re.compile(r"'str'|could not convert string|must be real number, not str")
_PROPERTY = r"""<[\w.-]+:property\b[^>]*?\bname\s*=\s*["']{name}["'][^>]*?\bvalue\s*=\s*["']([^"']*)["']"""
#: the name xacro could not find, and any definition of it: prefixed (group 1) or not
_UNDEFINED = re.compile(r"name '(\w+)' is not defined")
_DEFINITION = r"""<([\w.-]+:)?property\b[^>]*?\bname\s*=\s*["']{name}["']"""


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def text_property_help(message: str, files: Iterable[str]) -> str | None:
    """``property 'base_mass' is '0.3,' (file:line), text, not a number; did you mean 0.3?`` when
    *message* is a type error in an expression using such a property, else ``None``."""
    expression = _EXPRESSION.search(message)
    if expression is None or not _TEXT_AS_NUMBER.search(message):
        return None
    names = list(dict.fromkeys(_NAME.findall(expression.group(1))))
    for path, text in _texts(files):
        for name in names:
            found = re.search(_PROPERTY.format(name=re.escape(name)), text)
            if found is None:
                continue
            value = found.group(1).strip()
            if _is_number(value) or "${" in value or "$(" in value:
                continue
            line = text.count("\n", 0, found.start()) + 1
            meant = value.rstrip(",.;")
            guess = f"; did you mean {meant}?" if meant != value and _is_number(meant) else ""
            where = f"{os.path.basename(path)}:{line}"
            return f"property '{name}' is '{value}' ({where}), text, not a number{guess}"
    return None


def undefined_property_help(message: str, files: Iterable[str]) -> str | None:
    """Where the property that xacro calls undefined in *message* is written, and why xacro did
    not see it there (no ``xacro:`` prefix, or defined after its use), else ``None``."""
    undefined = _UNDEFINED.search(message)
    if undefined is None:
        return None
    name = undefined.group(1)
    for path, text in _texts(files):
        found = re.search(_DEFINITION.format(name=re.escape(name)), text)
        if found is None:
            continue
        where = f"{os.path.basename(path)}:{text.count(chr(10), 0, found.start()) + 1}"
        if found.group(1) is None:
            return (f"'{name}' is written <property> ({where}), without the xacro: prefix, which "
                    f"xacro reads only before ROS Noetic: write <xacro:property>")
        return (f"'{name}' is defined at {where}, after its use or in another macro's scope: xacro "
                f"reads in document order (Melodic and later, ROS 2), so define it before it is used")
    return None


def _texts(files: Iterable[str]) -> Iterator[tuple[str, str]]:
    """Each readable file of *files* with its text (a file that cannot be read is passed over:
    the hint is a courtesy)."""
    for path in files:
        try:
            with open(path, encoding="utf-8", errors="replace") as handle:
                yield path, handle.read()
        except OSError:
            continue
