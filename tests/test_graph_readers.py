"""Readers for what Graphviz wrote, used by the graph tests, with their own tests.

* PNG: the graph tests render PDFs back to PNG with poppler's ``pdftoppm`` and
  look at the pixels: a valid PDF of a tree diagram has a first page with dark
  ink (text and edges) on a light background. Only the standard library is used.
* SVG: Graphviz writes each node as ``<g class="node">`` with the node's DOT
  identifier in ``<title>`` and its label lines in ``<text>``.
"""

from __future__ import annotations

import shutil
import struct
import subprocess
import xml.etree.ElementTree as ET
import zlib
from dataclasses import dataclass
from pathlib import Path

import pytest

SIGNATURE = b"\x89PNG\r\n\x1a\n"
_CHANNELS = {0: 1, 2: 3, 4: 2, 6: 4}


@dataclass(frozen=True)
class Image:
    width: int
    height: int
    channels: int
    rows: list[bytes]

    def ink(self) -> float:
        """Fraction of pixels with a dark colour channel (< 128)."""
        dark = 0
        step = self.channels
        colour = min(step, 3)  # grey or RGB, not alpha
        for row in self.rows:
            for x in range(0, len(row), step):
                if min(row[x : x + colour]) < 128:
                    dark += 1
        return dark / (self.width * self.height)


def _paeth(a: int, b: int, c: int) -> int:
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    if pa <= pb and pa <= pc:
        return a
    return b if pb <= pc else c


def _unfilter(kind: int, row: bytearray, prior: bytes, bpp: int) -> bytearray:
    for i in range(len(row)):
        left = row[i - bpp] if i >= bpp else 0
        up = prior[i]
        corner = prior[i - bpp] if i >= bpp else 0
        predictor = (0, left, up, (left + up) // 2, _paeth(left, up, corner))[kind]
        row[i] = (row[i] + predictor) & 0xFF
    return row


def read_png(data: bytes) -> Image:
    """Decode an 8-bit, non-interlaced PNG; raises ``ValueError`` on anything malformed."""
    if not data.startswith(SIGNATURE):
        raise ValueError("not a PNG: bad signature")
    pos, header, idat = len(SIGNATURE), None, b""
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind, body = data[pos + 4 : pos + 8], data[pos + 8 : pos + 8 + length]
        (crc,) = struct.unpack(">I", data[pos + 8 + length : pos + 12 + length])
        if zlib.crc32(kind + body) != crc:
            raise ValueError(f"bad CRC in {kind!r} chunk")
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
        pos += 12 + length
    if header is None:
        raise ValueError("no IHDR chunk")
    width, height, depth, colour_type, _, _, interlace = header
    if depth != 8 or interlace or colour_type not in _CHANNELS:
        raise ValueError(f"unsupported PNG: depth {depth}, colour type {colour_type}")
    channels = _CHANNELS[colour_type]
    raw = zlib.decompress(idat)
    stride = width * channels
    if len(raw) != height * (stride + 1):
        raise ValueError("image data has the wrong size")
    rows, prior = [], bytes(stride)
    for y in range(height):
        start = y * (stride + 1)
        row = _unfilter(raw[start], bytearray(raw[start + 1 : start + 1 + stride]), prior, channels)
        rows.append(bytes(row))
        prior = bytes(row)
    return Image(width, height, channels, rows)


def first_page_png(pdf: Path, work: Path, size: int = 200) -> Image:
    """Render page 1 of *pdf* with ``pdftoppm`` (at most *size* pixels a side) and decode it."""
    pdftoppm = shutil.which("pdftoppm")
    assert pdftoppm, "pdftoppm (poppler-utils) is needed; scripts/test installs it"
    prefix = work / f"{pdf.stem}-page1"
    run = subprocess.run(
        [
            pdftoppm,
            "-png",
            "-f",
            "1",
            "-l",
            "1",
            "-singlefile",
            "-scale-to",
            str(size),
            str(pdf),
            str(prefix),
        ],
        capture_output=True,
        check=False,
    )
    assert run.returncode == 0, f"pdftoppm cannot read {pdf}: {run.stderr.decode(errors='replace')}"
    return read_png(prefix.with_suffix(".png").read_bytes())


SVG = "{http://www.w3.org/2000/svg}"


def svg_nodes(data: bytes) -> dict[str, list[str]]:
    """Node identifier (as Graphviz read it) -> the text lines drawn in the node."""
    root = ET.fromstring(data)
    nodes: dict[str, list[str]] = {}
    for group in root.iter(f"{SVG}g"):
        if group.get("class") != "node":
            continue
        title = group.find(f"{SVG}title")
        assert title is not None and title.text is not None
        nodes[title.text] = [t.text or "" for t in group.iter(f"{SVG}text")]
    return nodes


def svg_node_text(data: bytes) -> dict[str, str]:
    """Node identifier -> its label, bold and plain runs joined with spaces."""
    return {name: " ".join(texts) for name, texts in svg_nodes(data).items()}


# -- the readers' own tests -------------------------------------------------


def _dot(tmp_path: Path, fmt: str, source: str) -> Path:
    dot = shutil.which("dot")
    assert dot, "Graphviz is needed; scripts/test installs it"
    out = tmp_path / f"g.{fmt}"
    subprocess.run([dot, f"-T{fmt}", f"-o{out}"], input=source.encode(), check=True)
    return out


def test_reads_a_png_that_graphviz_drew(tmp_path: Path) -> None:
    image = read_png(_dot(tmp_path, "png", 'digraph { a -> b [label="x"] }').read_bytes())
    assert image.width > 20 and image.height > 50
    assert 0.001 < image.ink() < 0.5


def test_a_blank_page_has_no_ink(tmp_path: Path) -> None:
    pdf = _dot(tmp_path, "pdf", "digraph { a [style=invis] }")
    assert first_page_png(pdf, tmp_path).ink() == 0


def test_rejects_what_is_not_a_png(tmp_path: Path) -> None:
    data = _dot(tmp_path, "png", "digraph { a }").read_bytes()
    with pytest.raises(ValueError, match="signature"):
        read_png(b"GIF89a" + data[6:])
    corrupt = bytearray(data)
    corrupt[40] ^= 0xFF  # inside the first chunk after IHDR's start
    with pytest.raises(ValueError):
        read_png(bytes(corrupt))


def test_reads_nodes_and_labels_from_svg(tmp_path: Path) -> None:
    svg = _dot(tmp_path, "svg", 'digraph { "link:a" [label=<<B>a</B><BR/>1 kg>]; "link:a" -> b }')
    nodes = svg_nodes(svg.read_bytes())
    assert nodes == {"link:a": ["a", "1 kg"], "b": ["b"]}
