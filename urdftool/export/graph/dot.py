"""The DOT language: quoting identifiers, escaping labels, writing statements.

Three kinds of text go into a DOT file and each has its own escaping rules:

* identifiers (node names): a double-quoted string in which only ``\\"`` is an
  escape; backslashes are doubled so that a name ending in ``\\`` cannot swallow
  the closing quote;
* escString attributes (``tooltip``): Graphviz also reads ``\\n``, ``\\N``, ...;
* HTML-like labels (``<...>``): XML text, so ``& < > "`` become entities.

Names from robot files may hold any of these (``::`` from SDF nested models,
quotes, unicode), so nothing is written unescaped.
"""

from __future__ import annotations

import re
from collections.abc import Mapping

# XML 1.0 forbids most C0 controls; Graphviz's HTML parser rejects them.
_CONTROL = re.compile(r"[\x00-\x08\x0b\x0c\x0e-\x1f\x7f]")


def _printable(text: str) -> str:
    """Control characters shown as ``\\xNN`` so a label stays legible and valid."""
    return _CONTROL.sub(lambda m: f"\\x{ord(m.group()):02x}", text)


def quote_id(name: str) -> str:
    """A DOT identifier for *name*, always quoted (``"link:base"``)."""
    text = _printable(name).replace("\\", "\\\\").replace('"', '\\"')
    return f'"{text}"'


def esc_string(text: str) -> str:
    """A quoted escString attribute value (for ``tooltip``); newlines become ``\\n``."""
    body = _printable(text.replace("\r", "")).replace("\\", "\\\\").replace('"', '\\"')
    return '"' + body.replace("\n", "\\n") + '"'


def html_text(text: str) -> str:
    """*text* escaped for the inside of an HTML-like label."""
    return (
        _printable(text)
        .replace("&", "&amp;")
        .replace("<", "&lt;")
        .replace(">", "&gt;")
        .replace('"', "&quot;")
    )


class Html(str):
    """A label already in HTML-like markup: written as ``<...>``, not quoted."""


def attribute_value(value: str | float | bool) -> str:
    """One attribute value in DOT syntax."""
    if isinstance(value, Html):
        return f"<{value}>"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return f"{value:g}"
    return esc_string(value)


def attribute_list(attributes: Mapping[str, str | float | bool]) -> str:
    """``[key=value, ...]`` in the order given (callers pass a stable order)."""
    if not attributes:
        return ""
    body = ", ".join(f"{key}={attribute_value(value)}" for key, value in attributes.items())
    return f" [{body}]"


class DotWriter:
    """Collects the statements of one ``digraph``; :meth:`text` is deterministic."""

    def __init__(self, name: str) -> None:
        self._name = name
        self._lines: list[str] = []

    def comment(self, text: str) -> None:
        for line in text.splitlines():
            self._lines.append(f"  // {_printable(line)}")

    def defaults(self, kind: str, attributes: Mapping[str, str | float | bool]) -> None:
        """``graph``/``node``/``edge`` default attributes."""
        self._lines.append(f"  {kind}{attribute_list(attributes)};")

    def node(self, node_id: str, attributes: Mapping[str, str | float | bool]) -> None:
        self._lines.append(f"  {quote_id(node_id)}{attribute_list(attributes)};")

    def edge(self, tail: str, head: str, attributes: Mapping[str, str | float | bool]) -> None:
        self._lines.append(f"  {quote_id(tail)} -> {quote_id(head)}{attribute_list(attributes)};")

    def blank(self) -> None:
        self._lines.append("")

    def text(self) -> str:
        return f"digraph {quote_id(self._name)} {{\n" + "\n".join(self._lines) + "\n}\n"
