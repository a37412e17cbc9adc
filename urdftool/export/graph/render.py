"""Rendering DOT text to PDF, SVG or PNG with Graphviz's ``dot`` program.

``dot`` is run with an argument list (no shell), reading the DOT text on stdin
and writing each format to a temporary file beside its output, which replaces
the output only when Graphviz succeeded: an interrupted or failed run leaves no
half-written diagram and never a file that claims to be one.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from collections.abc import Iterable, Mapping
from pathlib import Path

from urdftool.export.write import commit, discard, reserve

#: output suffix -> Graphviz output format
RENDERED_SUFFIXES: dict[str, str] = {".pdf": "pdf", ".svg": "svg", ".png": "png"}
#: output suffixes written as DOT text, no Graphviz needed
DOT_SUFFIXES = (".dot", ".gv")
#: seconds before a layout is given up (a very large graph can take minutes)
TIMEOUT = 300

INSTALL_HINTS = """\
Graphviz's `dot` program was not found on PATH; it renders .pdf, .svg and .png.
Install Graphviz:
  Debian/Ubuntu:  sudo apt-get install graphviz
  Fedora/RHEL:    sudo dnf install graphviz
  macOS:          brew install graphviz
  conda:          conda install -c conda-forge graphviz
  Windows:        winget install graphviz
or write a .dot/.gv file (no Graphviz needed) and render it elsewhere."""

# cairo stamps the time into every PDF; a fixed stamp keeps reruns byte-identical.
_PDF_DATE = re.compile(rb"(/(?:CreationDate|ModDate) \(D:)(\d{14})")


class GraphvizNotFound(RuntimeError):
    """``dot`` is not installed; the message says how to install it."""

    def __init__(self) -> None:
        super().__init__(INSTALL_HINTS)


class GraphvizFailed(RuntimeError):
    """``dot`` ran but produced no output; the message is Graphviz's."""


def find_dot() -> str | None:
    """The path of Graphviz's ``dot``, or ``None``."""
    return shutil.which("dot")


def graphviz_format(path: str | os.PathLike[str]) -> str | None:
    """``pdf``/``svg``/``png`` for a rendered output, ``None`` for anything else."""
    return RENDERED_SUFFIXES.get(Path(path).suffix.lower())


def _stamp() -> bytes:
    """The PDF date: ``SOURCE_DATE_EPOCH`` when set (reproducible builds), else 1970-01-01."""
    import time

    epoch = int(os.environ.get("SOURCE_DATE_EPOCH", "0") or 0)
    return time.strftime("%Y%m%d%H%M%S", time.gmtime(epoch)).encode()


def _normalise(fmt: str, path: str) -> None:
    if fmt != "pdf":
        return
    data = Path(path).read_bytes()
    # Same length replacement: the PDF's cross-reference offsets stay valid.
    fixed = _PDF_DATE.sub(lambda m: m.group(1) + _stamp(), data)
    if fixed != data:
        Path(path).write_bytes(fixed)


def render_files(
    dot_text: str,
    outputs: Mapping[str | os.PathLike[str], str],
    inputs: Iterable[str | os.PathLike[str]] = (),
) -> list[str]:
    """Render *dot_text* once into every ``path -> format`` of *outputs*.

    One ``dot`` run lays the graph out once for all formats. Returns Graphviz's
    warnings. Raises :class:`GraphvizNotFound`, :class:`GraphvizFailed`, or
    :class:`~urdftool.export.write.OutputError` when an output is an input.
    """
    exe = find_dot()
    if exe is None:
        raise GraphvizNotFound()
    sources = list(inputs)
    temporary: dict[Path, tuple[str, str]] = {}
    try:
        for out, fmt in outputs.items():
            temporary[Path(out)] = (reserve(out, sources), fmt)
        command = [exe]
        for tmp, fmt in temporary.values():
            command += [f"-T{fmt}", f"-o{tmp}"]
        try:
            run = subprocess.run(
                command,
                input=dot_text.encode("utf-8"),
                capture_output=True,
                timeout=TIMEOUT,
                check=False,
            )
        except subprocess.TimeoutExpired as exc:
            raise GraphvizFailed(f"Graphviz took longer than {TIMEOUT} s") from exc
        messages = run.stderr.decode("utf-8", "replace").strip()
        if run.returncode != 0 or any(os.path.getsize(tmp) == 0 for tmp, _ in temporary.values()):
            raise GraphvizFailed(messages or f"dot exited with status {run.returncode}")
        for target, (tmp, fmt) in temporary.items():
            _normalise(fmt, tmp)
            commit(tmp, target)
        return [line for line in messages.splitlines() if line.strip()]
    finally:
        for tmp, _ in temporary.values():
            discard(tmp)
