"""Element positions kept in a table (the URDF and SRDF readers) are the stamped positions.

The readers that walk a document once ask ``parse_bytes(..., table=True)`` for a
position table instead of an attribute on every element (a third of reading a
file went into writing and decoding those attributes), and its spans are looked up
only when read (``urdftool.source.deferred_span``). These tests hold the two ways to
the same spans, check that a deferred span behaves as a plain one, and that the
elements a model keeps (its ``<gazebo>``, ``<transmission>``, ``<ros2_control>``
blocks) are still located by ``span_of`` after the reading.
"""

from __future__ import annotations

import copy
import dataclasses
import gc
import glob
import pickle

import pytest
from lxml import etree

from tests.conftest import ERD, SEEDS
from urdftool.parse import read
from urdftool.parse.locate import PositionTable, position_table, span_of
from urdftool.parse.xmlio import parse_bytes
from urdftool.pipeline.check import CheckOptions, check_file
from urdftool.source import SRC_ATTRIBUTE, LinePositions, Span, element_starts, expat_element_starts

#: start tags over several lines, several on one line, non-ASCII text before a tag, a comment
#: holding '<', CDATA, and a <gazebo> block kept on the model
TRICKY = """<?xml version="1.0"?>
<!-- provenance: hand-written for urdftool's position table; a comment with <link> in it -->
<robot name="tricky">
  <link name="b\u00e4se"><visual><geometry><box size="1 1 1"/></geometry></visual></link>
  <link
      name="arm">
    <inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
  </link>
  <joint name="j" type="revolute"><parent link="b\u00e4se"/><child link="arm"/>
    <limit lower="0" upper="1" effort="1" velocity="1"/></joint>
  <gazebo reference="arm"><material>Gazebo/\u00c4</material><![CDATA[ <not-an-element/> ]]>
    <plugin name="p" filename="libp.so"><param
        name="x">1</param></plugin>
  </gazebo>
</robot>
"""


def _documents() -> list[tuple[str, bytes]]:
    found = [("tricky.urdf", TRICKY.encode("utf-8"))]
    paths = sorted(glob.glob(str(SEEDS / "**" / "*.urdf"), recursive=True))[:20]
    if ERD is not None:
        paths += sorted(glob.glob(str(ERD / "**" / "*.urdf"), recursive=True))[:10]
    for path in paths:
        with open(path, "rb") as handle:
            found.append((path, handle.read()))
    return found


@pytest.mark.parametrize(("path", "data"), _documents(), ids=lambda v: v if isinstance(v, str) else "")
def test_table_gives_the_stamped_positions(path: str, data: bytes) -> None:
    stamped, _ = parse_bytes(data, path)
    tabled, _ = parse_bytes(data, path, table=True)
    if stamped is None:  # a seed with a syntax error: refused either way
        assert tabled is None
        return
    assert tabled is not None
    assert tabled.table is not None
    elements = list(tabled.root.iter(etree.Element))
    assert all(e.get(SRC_ATTRIBUTE) is None for e in elements)  # nothing written into the tree
    expected = [span_of(e) for e in stamped.root.iter(etree.Element)]
    assert [tabled.span(e) for e in elements] == expected
    assert all(span is not None and span.column is not None for span in expected)


def _at(needle: str) -> tuple[int, int]:
    """(line, character column) of *needle* in TRICKY, counted on the text."""
    for number, line in enumerate(TRICKY.split("\n"), start=1):
        if needle in line:
            return number, line.index(needle) + 1
    raise AssertionError(needle)


def test_tricky_positions_are_exact() -> None:
    tabled, _ = parse_bytes(TRICKY.encode("utf-8"), "tricky.urdf", table=True)
    assert tabled is not None
    spans = {e.get("name") or e.tag: tabled.span(e) for e in tabled.root.iter(etree.Element)}
    found = {key: (span.line, span.column) for key, span in spans.items() if span is not None}
    assert found["arm"] == (5, 3)  # a start tag over two lines: where its '<' is
    assert found["box"] == _at("<box")  # after non-ASCII text: columns count characters, not bytes
    assert found["x"] == (_at("<param")[0], _at("<param")[1])
    assert found["limit"] == _at("<limit")


def test_kept_extension_elements_are_located(tmp_path: object) -> None:
    [loaded] = read(_write_tricky(tmp_path))
    assert loaded.robot is not None
    [gazebo] = loaded.robot.extensions
    assert gazebo.element is not None
    assert SRC_ATTRIBUTE not in gazebo.attributes
    located = {e.tag: span_of(e) for e in gazebo.element.iter(etree.Element)}
    assert {tag: (s.line, s.column) for tag, s in located.items() if s} == {
        tag: _at(f"<{tag}") for tag in ("gazebo", "material", "plugin", "param")
    }
    assert loaded.robot.link("arm").span.line == 5  # type: ignore[union-attr]


def _write_tricky(tmp_path: object) -> str:
    path = f"{tmp_path}/tricky.urdf"
    with open(path, "w", encoding="utf-8") as handle:
        handle.write(TRICKY)
    return path


def _table_of(span: Span) -> PositionTable:
    locate = span._locate  # type: ignore[attr-defined]  # a deferred span's lookup: the table's method
    table = locate.__self__
    assert isinstance(table, PositionTable)
    return table


def test_a_file_without_findings_is_never_scanned(tmp_path: object) -> None:
    """Spans of a tabled document are looked up when first read: reading the model and checking it
    without a finding leaves the position table unbuilt; the first span read builds it once."""
    [loaded] = read(_write_tricky(tmp_path))
    assert loaded.robot is not None and not loaded.diagnostics
    arm = loaded.robot.link("arm")
    assert arm is not None
    table = _table_of(arm.span)
    assert table._offsets is None and table._found is None  # nothing looked up
    [report] = check_file(_write_tricky(tmp_path), CheckOptions(select=("S",)))
    assert report.diagnostics == ()
    assert table._offsets is None
    assert (arm.span.line, arm.span.column) == (5, 3)
    # one scan for the start tags' offsets; the position of the one element read, and no more
    assert table._offsets is not None and table._index is None and table._found is None


def test_a_deferred_span_is_a_plain_span_in_every_way(tmp_path: object) -> None:
    [loaded] = read(_write_tricky(tmp_path))
    assert loaded.robot is not None
    span = loaded.robot.joints[0].span
    plain = Span(span.path, *_at("<joint"))
    assert type(span) is not Span and span.__class__ is Span and isinstance(span, Span)
    assert span == plain and plain == span and hash(span) == hash(plain)
    assert not span < plain and sorted([Span(span.path, 99), span, Span(span.path, 1)])[1] == plain
    assert repr(span) == repr(plain) and str(span) == str(plain)
    for copied in (pickle.loads(pickle.dumps(span)), copy.copy(span), copy.deepcopy(span),
                   dataclasses.replace(span, path=span.path)):
        assert type(copied) is Span and copied == plain
    assert dataclasses.asdict(span) == dataclasses.asdict(plain)
    with pytest.raises(dataclasses.FrozenInstanceError):
        span.line = 1  # type: ignore[misc]
    limit = loaded.robot.joints[0].limit
    assert limit is not None and limit.lower_span == Span(span.path, *_at("lower="))


def test_kept_elements_are_located_after_the_document_is_gone(tmp_path: object) -> None:
    """The model's spans keep its position table alive: a ``<gazebo>`` block's children are found
    by ``span_of`` after the reader and its document are freed, whether or not a span was read."""
    [loaded] = read(_write_tricky(tmp_path))
    assert loaded.robot is not None
    gc.collect()
    [gazebo] = loaded.robot.extensions
    [param] = gazebo.element.iter("param")
    assert span_of(param) == Span(loaded.robot.path, *_at("<param"))
    assert gazebo.span == Span(loaded.robot.path, *_at("<gazebo"))


@pytest.mark.parametrize(("uri", "declared"), [
    ("http://www.ros.org/wiki/xacro", 'xmlns:xacro="{uri}"'),
    ("http://www.ros.org/wiki/&#120;acro", 'xmlns:xacro="{uri}"'),
    ("http://www.ros.org/wiki/xacro", "xmlns:x = '{uri}'"),  # another prefix, other quotes
])
def test_xacro_in_urdf_is_found_however_its_namespace_is_written(tmp_path: object, uri: str,
                                                                   declared: str) -> None:
    """The reader skips the xacro search when no tag can be in xacro's namespace (files xacro
    wrote declare it and use it nowhere); a character reference could spell it, so it does not
    skip then."""
    prefix = declared.split(":")[1].split("=")[0].strip()
    path = f"{tmp_path}/arm.urdf"
    with open(path, "w", encoding="utf-8") as handle:
        handle.write(f'<robot name="r" {declared.format(uri=uri)}>\n'
                     f'  <{prefix}:property name="l" value="1"/>\n  <link name="a"/>\n</robot>\n')
    [loaded] = read(path)
    found = [d for d in loaded.diagnostics if d.name == "xacro-in-urdf"]
    assert [(d.location.line, d.location.column) for d in found if d.location] == [(2, 3)]


def test_a_declared_but_unused_xacro_namespace_is_plain_urdf(tmp_path: object) -> None:
    path = f"{tmp_path}/arm.urdf"
    with open(path, "w", encoding="utf-8") as handle:
        handle.write('<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
                     '  <link name="a"/>\n</robot>\n')
    [loaded] = read(path)
    assert loaded.format == "urdf" and not loaded.diagnostics


#: what the scan of the bytes must step over or count as expat does: markup-like text in a
#: comment, CDATA and processing instructions, tabs, CRLF and lone CR line ends, characters of
#: two to four UTF-8 bytes before a tag, a document type declaration whose literal holds '<'
SCANNED = [
    TRICKY,
    '<?xml version="1.0"?>\r\n<robot name="r">\r\n\t<link name="a"/><link name="b"/>\r\n</robot>\r\n',
    '<robot name="r">\r<link name="a"/>\r\n<link name="b"/></robot>',
    '<robot name="\u00e4\u20ac\U0001f916"><link name="\U0001f916"/>\U0001f916<joint name="j"/></robot>',
    '<?pi <link name="no"/> ?><robot><!-- <a> --><![CDATA[<b>]]><?x <c>?><link/>'
    '<!----><link\n name="x"\n/></robot>',
    '<!DOCTYPE robot SYSTEM "<a>"><robot><link/></robot>',
]


@pytest.mark.parametrize("text", SCANNED)
def test_scan_of_the_bytes_finds_what_expat_finds(text: str) -> None:
    data = text.encode("utf-8")
    document, _ = parse_bytes(data, "scanned.urdf", table=True)
    assert document is not None  # lxml accepts it, as every document scanned has been
    assert element_starts(data) == expat_element_starts(data)
    assert len(element_starts(data)) == len(list(document.root.iter(etree.Element)))


def _expat_reads(data: bytes) -> bool:
    """Some seeds are refused by expat as written (the reader mends their quirks first): there
    is nothing to compare the scan with on those."""
    try:
        expat_element_starts(data)
    except Exception:
        return False
    return True


@pytest.mark.parametrize(("path", "data"), [(p, d) for p, d in _documents()[1:] if _expat_reads(d)],
                         ids=lambda v: v if isinstance(v, str) else "")
def test_scan_of_the_bytes_matches_expat_on_real_files(path: str, data: bytes) -> None:
    assert element_starts(data) == expat_element_starts(data)


def test_scan_of_a_long_line_of_many_elements_is_linear_and_exact() -> None:
    """A minified document: 100,000 elements on one line after a non-ASCII character. Each
    column counts the characters before it; decoding the whole line prefix for each element
    would take minutes, the scan decodes each stretch once."""
    data = ('<robot name="\u00e4">' + '<link name="l"/>' * 100_000 + "</robot>").encode("utf-8")
    starts = element_starts(data)
    assert len(starts) == 100_001 and starts[-1] == (1, 17 + 16 * 99_999)
    assert starts == expat_element_starts(data)


def test_line_positions_asked_in_any_order_are_counted_as_from_the_start() -> None:
    """Lookups count line breaks from the nearest offset asked before: whatever the order, each
    position is the one a count from the start of the file gives."""
    links = "".join(f"  <link name=\"l{i}\"/>{' ' * (i % 5)}\n" for i in range(300))
    data = f"<robot name=\"b\u00e4se\">\n{links}</robot>\n".encode()
    starts = [i for i in range(len(data)) if data[i:i + 1] == b"<"]
    lines = LinePositions(data)
    order = starts[::-1][::2] + starts[::2]
    for offset in order:
        line_start = data.rfind(b"\n", 0, offset) + 1
        expected = (data.count(b"\n", 0, line_start) + 1, len(data[line_start:offset].decode("utf-8")) + 1)
        assert lines.position(offset) == expected


#: start tags that the line lxml records for an element does not settle: a tag over two lines
#: followed by one of the same name, '<link' in a comment beside a link, two on one line, '>'
#: in text before a tag
LINE_TRAPS = """<robot name="traps">
  <link name="a"><visual><origin
      xyz="1 0 0"/><origin xyz="2 0 0"/><geometry><box size="1 1 1"/></geometry></visual></link>
  <!-- <link name="commented"/> --><link name="b"/>
  <link name="c"/><link name="d"/>
  <gazebo reference="a"><description>a > b</description><plugin name="p" filename="p.so"/></gazebo>
  <link name="\u00e4"/>
</robot>
"""


def _lines_decide(data: bytes) -> tuple[int, int]:
    """Over every element of *data*: how many the line lookup settles, and how many of those
    differ from the full table."""
    document, _ = parse_bytes(data, "lines.urdf", table=True)
    assert document is not None and document.table is not None
    table = document.table
    full = position_table(table.root, data)
    decided = wrong = 0
    for element in table.root.iter(etree.Element):
        position = table._position_on_line(element)
        decided += position is not None
        wrong += position is not None and position != full[element]
    return decided, wrong


def test_the_line_lxml_records_settles_a_position_only_when_it_must_be_right() -> None:
    data = LINE_TRAPS.encode("utf-8")
    document, _ = parse_bytes(data, "traps.urdf", table=True)
    assert document is not None and document.table is not None
    table = document.table
    full = position_table(table.root, data)
    settled = {(e.tag, e.get("name") or e.get("xyz")): table._position_on_line(e)
               for e in table.root.iter(etree.Element)}
    # left to the start-tag offsets: the line opens inside a tag (the origins and the box after
    # them), a '<link' in a comment beside one, two links on one line
    for key in (("origin", "1 0 0"), ("origin", "2 0 0"), ("box", None), ("link", "b"), ("link", "c"),
                ("link", "d")):
        assert settled[key] is None, key
    # settled: a character of two bytes before the name, a '>' in text before the tag
    assert settled[("link", "\u00e4")] == (7, 3) and settled[("plugin", "p")] == (6, 57)
    # and whichever way each is found, every span is the full table's
    assert {e: (s.line, s.column) for e in table.root.iter(etree.Element)
            if (s := table.span(e)) is not None} == full


@pytest.mark.skipif(ERD is None, reason="example-robot-data is a test dependency")
def test_the_line_lxml_records_agrees_with_the_full_table_on_real_files() -> None:
    assert ERD is not None
    decided = wrong = 0
    for path in sorted(glob.glob(str(ERD / "**" / "*.urdf"), recursive=True)):
        with open(path, "rb") as handle:
            found = _lines_decide(handle.read())
        decided, wrong = decided + found[0], wrong + found[1]
    assert wrong == 0 and decided > 10_000
