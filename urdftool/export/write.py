"""Writing outputs: atomically, byte-identically on reruns, and never over an input."""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING

from urdftool.safe_files import describe_path

if TYPE_CHECKING:
    import tempfile

    from urdftool.model import Robot
else:  # a check that writes no file does not import it
    from urdftool.lazy import LazyModule

    tempfile = LazyModule("tempfile")


class OutputError(Exception):
    """An output that must not be written (it would replace an input) or cannot be (no permission,
    no such folder, disk full)."""


def _same_file(a: str | os.PathLike[str], b: str | os.PathLike[str]) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return Path(a).resolve() == Path(b).resolve()


def guard_inputs(output: str | os.PathLike[str], inputs: Iterable[str | os.PathLike[str]]) -> None:
    """Raise :class:`OutputError` when *output* is one of *inputs* (the model, an included
    xacro file, a mesh; through any symlink or hard link) or an existing file that is not
    a regular file (a device such as ``/dev/full``, a FIFO, a socket, a directory), which
    an atomic rename would replace."""
    if not os.path.lexists(output):
        return

    what = describe_path(output)
    if what is not None:
        raise OutputError(f"{output}: refusing to write: it is {what}, not a regular file")
    for source in inputs:
        if _same_file(output, source):
            raise OutputError(f"{output}: refusing to write over the input file {source}")


def model_inputs(robot: Robot | None, files: Iterable[str | os.PathLike[str]] = ()) -> list[str]:
    """Every file a model was read from: *files* (the input and its includes) and its meshes."""
    out = [os.fspath(f) for f in files]
    if robot is not None:
        if robot.path:
            out.append(robot.path)
        for link in robot.links:
            for geometry in [v.geometry for v in link.visuals] + [c.geometry for c in link.collisions]:
                resolved = getattr(geometry, "resolved", None)
                if isinstance(resolved, str):
                    out.append(resolved)
    return list(dict.fromkeys(out))


def file_mode() -> int:
    """The mode a plain ``open()`` would give: 0o666 less the umask (mkstemp makes 0o600).

    Outputs are ordinary files to share, not private ones.
    """
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def reserve(path: str | os.PathLike[str], inputs: Iterable[str | os.PathLike[str]] = ()) -> str:
    """A new temporary file beside *path* to be filled and then :func:`commit`-ted over it.

    Raises :class:`OutputError` when *path* is an input or its folder cannot be written.
    """
    guard_inputs(path, inputs)
    target = Path(path)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
        os.fchmod(fd, file_mode())
        os.close(fd)
    except OSError as exc:
        raise OutputError(f"{path}: cannot write: {exc.strerror or exc}") from exc
    return tmp


def commit(tmp: str, path: str | os.PathLike[str]) -> None:
    """Move the filled temporary *tmp* over *path* in one step (readers never see half a file)."""
    try:
        os.replace(tmp, path)
    except OSError as exc:
        discard(tmp)
        raise OutputError(f"{path}: cannot write: {exc.strerror or exc}") from exc


def discard(tmp: str) -> None:
    with contextlib.suppress(OSError):
        os.unlink(tmp)


def write_bytes_atomic(
    path: str | os.PathLike[str], data: bytes, inputs: Iterable[str | os.PathLike[str]] = ()
) -> None:
    """Write *data* to *path* through a temporary file in the same folder, then rename.

    Readers never see a half-written file; an interrupted run leaves the old file.
    Raises :class:`OutputError` when *path* is an input or cannot be written.
    """
    tmp = reserve(path, inputs)
    try:
        with open(tmp, "wb") as handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
    except OSError as exc:
        discard(tmp)
        raise OutputError(f"{path}: cannot write: {exc.strerror or exc}") from exc
    except BaseException:
        discard(tmp)
        raise
    commit(tmp, path)


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
