"""Hypothesis strategies that break real robot descriptions from ``fixtures/``.

Each case starts from a URDF, xacro or SDF fixture and applies one to four
mutations: numbers replaced by hostile values (``nan``, ``inf``, ``1e309``, empty,
``1,2``, 400 digits), attributes dropped or duplicated, elements duplicated,
removed, nested in themselves or moved, the text truncated, and the whole file
re-encoded (UTF-16/32 with or without a byte-order mark or declaration).
"""

from __future__ import annotations

import re
from copy import deepcopy
from dataclasses import dataclass
from pathlib import Path

from hypothesis import strategies as st
from lxml import etree

from tests.conftest import FIXTURES

SUFFIXES = (".urdf", ".xacro", ".sdf", ".world")
#: seeds larger than this are left out (the harness must stay fast)
MAX_SEED_BYTES = 40_000


def seed_files() -> list[Path]:
    found = [
        p for p in sorted(FIXTURES.rglob("*"))
        if p.is_file() and p.name.endswith(SUFFIXES) and p.stat().st_size <= MAX_SEED_BYTES
    ]
    assert found, "fixtures/ holds URDF, xacro and SDF seeds"
    return found


SEEDS = seed_files()

HOSTILE_NUMBERS = (
    "nan", "NaN", "-nan", "inf", "-inf", "+inf", "Infinity", "1e309", "-1e309", "1e308", "-1e308",
    "", " ", "1,2", "1.2.3", "0x10", "1_000", "1e-400", "-0", "9" * 400, "1" + "0" * 320, "1e99999",
    "${x}", "$(arg x)", "1e", ".", "-", "0 0", "1e16", "-1e16", "4.9e-324", "\u0661",
)

_NUMBER = re.compile(rb"-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?")
_ATTRIBUTE = re.compile(rb"""\s[\w:.-]+\s*=\s*(?:"[^"]*"|'[^']*')""")
_DECLARATION = re.compile(rb"^\s*<\?xml[^>]*\?>")
_ENCODINGS = ("utf-16", "utf-16-le", "utf-16-be", "utf-32", "utf-32-le", "utf-32-be", "utf-8-sig")


@dataclass(frozen=True)
class Case:
    """One mutated input: the seed it came from, the bytes and the mutations applied."""

    seed: Path
    data: bytes
    mutations: tuple[str, ...]

    def __repr__(self) -> str:
        return f"Case({self.seed.relative_to(FIXTURES)}, {self.mutations!r}, {len(self.data)} bytes)"


def _replace_number(data: bytes, index: int, value: str) -> tuple[bytes, str]:
    matches = list(_NUMBER.finditer(data))
    if not matches:
        return data, "number:none"
    m = matches[index % len(matches)]
    label = f"number[{m.group().decode()}]={value!r}"
    return data[: m.start()] + value.encode("utf-8") + data[m.end():], label


def _attribute(data: bytes, index: int, duplicate: bool) -> tuple[bytes, str]:
    matches = list(_ATTRIBUTE.finditer(data))
    if not matches:
        return data, "attribute:none"
    m = matches[index % len(matches)]
    text = m.group()
    replacement = text + text if duplicate else b""
    name = text.split(b"=")[0].strip().decode("utf-8", "replace")
    return data[: m.start()] + replacement + data[m.end():], f"{'dup' if duplicate else 'drop'}-attr[{name}]"


def _structural(data: bytes, index: int, op: str) -> tuple[bytes, str]:
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, remove_comments=False)
    try:
        root = etree.fromstring(data, parser)
    except (etree.XMLSyntaxError, ValueError):
        return data, f"{op}:unparsed"
    elements = [e for e in root.iter() if isinstance(e.tag, str)]
    if len(elements) < 2:
        return data, f"{op}:tiny"
    element = elements[1 + index % (len(elements) - 1)]
    parent = element.getparent()
    assert parent is not None
    # deepcopy, not a text round trip: an element's text alone need not parse (a namespaced
    # attribute whose prefix an earlier mutation left undeclared made the 2026-11-25 run stop)
    copy = deepcopy(element)
    copy.tail = None
    tag = etree.QName(element).localname
    if op == "duplicate":
        element.addnext(copy)
    elif op == "remove":
        parent.remove(element)
    elif op == "nest":  # the element inside itself, one level deeper
        element.append(copy)
    elif op == "hoist":  # moved to the root
        root.append(copy)
    elif op == "empty":  # children and text removed
        for child in list(element):
            element.remove(child)
        element.text = None
    elif op == "rename":
        element.tag = "link" if tag != "link" else "joint"
    return etree.tostring(root, xml_declaration=False), f"{op}[{tag}]"


def _truncate(data: bytes, fraction: float) -> tuple[bytes, str]:
    cut = int(len(data) * fraction)
    return data[:cut], f"truncate@{cut}"


def _encode(data: bytes, encoding: str, drop_declaration: bool) -> tuple[bytes, str]:
    if drop_declaration:
        data = _DECLARATION.sub(b"", data, count=1)
    text = data.decode("utf-8", "replace")
    return text.encode(encoding), f"encode[{encoding}{',nodecl' if drop_declaration else ''}]"


@st.composite
def mutation(draw: st.DrawFn, data: bytes) -> tuple[bytes, str]:
    kind = draw(st.sampled_from(
        ["number", "number", "number", "drop-attr", "dup-attr", "structure", "structure", "truncate"]
    ))
    index = draw(st.integers(0, 10_000))
    if kind == "number":
        return _replace_number(data, index, draw(st.sampled_from(HOSTILE_NUMBERS)))
    if kind in ("drop-attr", "dup-attr"):
        return _attribute(data, index, kind == "dup-attr")
    if kind == "structure":
        op = draw(st.sampled_from(["duplicate", "remove", "nest", "hoist", "empty", "rename"]))
        return _structural(data, index, op)
    return _truncate(data, draw(st.floats(0.0, 1.0)))


@st.composite
def cases(draw: st.DrawFn, seeds: list[Path] | None = None) -> Case:
    seed = draw(st.sampled_from(seeds or SEEDS))
    data = seed.read_bytes()
    applied: list[str] = []
    for _ in range(draw(st.integers(1, 4))):
        data, label = draw(mutation(data))
        applied.append(label)
    if draw(st.integers(0, 9)) == 0:
        data, label = _encode(data, draw(st.sampled_from(_ENCODINGS)), draw(st.booleans()))
        applied.append(label)
    return Case(seed, data, tuple(applied))
