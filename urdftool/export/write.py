"""Writing outputs: atomically, byte-identically on reruns, and never over an input."""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterable
from pathlib import Path


class OutputError(Exception):
    """An output that must not or cannot be written (it would replace an input)."""


def _same_file(a: str | os.PathLike[str], b: str | os.PathLike[str]) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return Path(a).resolve() == Path(b).resolve()


def guard_inputs(output: str | os.PathLike[str], inputs: Iterable[str | os.PathLike[str]]) -> None:
    """Raise :class:`OutputError` when *output* is one of *inputs*."""
    if not os.path.exists(output):
        return
    for source in inputs:
        if _same_file(output, source):
            raise OutputError(f"{output}: refusing to write over the input file")


def write_bytes_atomic(
    path: str | os.PathLike[str], data: bytes, inputs: Iterable[str | os.PathLike[str]] = ()
) -> None:
    """Write *data* to *path* through a temporary file in the same folder, then rename.

    Readers never see a half-written file; an interrupted run leaves the old file.
    """
    guard_inputs(path, inputs)
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    try:
        # mkstemp creates 0600; outputs are ordinary files, so apply the user's umask.
        os.fchmod(fd, 0o666 & ~_umask())
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_text_atomic(
    path: str | os.PathLike[str], text: str, inputs: Iterable[str | os.PathLike[str]] = ()
) -> None:
    write_bytes_atomic(path, text.encode("utf-8"), inputs)


def is_stale(path: str | os.PathLike[str], data: bytes) -> bool:
    """True when *path* does not hold exactly *data* (for ``convert --check``)."""
    try:
        return Path(path).read_bytes() != data
    except OSError:
        return True
