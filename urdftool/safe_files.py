"""Reading input files safely: regular files only, and no more bytes than a cap.

Robot descriptions name other files (xacro includes, meshes), and any name can
point at ``/dev/zero``, a FIFO or a socket. Reading those hangs or never ends,
so every input, include and mesh is opened here: without blocking, checked to
be a regular file, and read up to a size cap for its kind. A refusal is an
:class:`UnsafeFile`, an ``OSError`` whose ``strerror`` is a sentence, so the
callers that already turn ``OSError`` into a located finding (``mesh-unreadable``,
``xacro-error``) or an input error (exit 2) report it without new code.

Caps per kind (``model`` text, ``include`` for xacro includes, ``mesh``) can be
raised with ``--max-file-size`` (``SIZE`` for all kinds or ``KIND=SIZE``).
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import stat
from collections.abc import Iterator, Mapping
from typing import BinaryIO

MiB = 1024 * 1024

#: kind -> default cap in bytes
DEFAULT_LIMITS: dict[str, int] = {
    "model": 64 * MiB,
    "include": 16 * MiB,
    "mesh": 256 * MiB,
}

KINDS = tuple(DEFAULT_LIMITS)

_limits: dict[str, int] = dict(DEFAULT_LIMITS)


def limits() -> dict[str, int]:
    """The caps in force (the defaults unless :func:`file_limits` changed them)."""
    return dict(_limits)


def limit(kind: str) -> int:
    return _limits[kind]


def set_limits(caps: Mapping[str, int]) -> None:
    """Set the caps for the rest of the process (what ``--max-file-size`` does)."""
    _limits.update(caps)


@contextlib.contextmanager
def file_limits(overrides: Mapping[str, int] | None) -> Iterator[None]:
    """Raise (or lower) the caps for the duration of the block (process-wide)."""
    previous = dict(_limits)
    _limits.update(overrides or {})
    try:
        yield
    finally:
        _limits.clear()
        _limits.update(previous)


class UnsafeFile(OSError):
    """A file that is not read: not a regular file, or larger than its cap."""

    def __init__(self, path: str, reason: str):
        super().__init__(errno.EINVAL, reason, path)
        self.reason = reason

    def __str__(self) -> str:
        return f"{self.filename}: {self.reason}"


_SIZE = re.compile(r"^\s*(\d+(?:\.\d+)?)\s*([kKmMgG]?)(i?[bB])?\s*$")
_UNITS = {"": 1, "k": 1024, "m": MiB, "g": 1024 * MiB}


def parse_size(text: str) -> int:
    """``"64M"``, ``"1G"``, ``"500k"``, ``"1048576"`` → bytes. Raises ``ValueError``."""
    match = _SIZE.match(text)
    if not match:
        raise ValueError(f"'{text}' is not a size (write e.g. 512M, 2G or a number of bytes)")
    return int(float(match.group(1)) * _UNITS[match.group(2).lower()])


def parse_limits(specs: tuple[str, ...] | list[str]) -> dict[str, int]:
    """``--max-file-size`` values (``SIZE`` or ``KIND=SIZE``) → ``{kind: bytes}``. Raises ``ValueError``."""
    out: dict[str, int] = {}
    for spec in specs:
        if "=" in spec:
            kind, _, size = spec.partition("=")
            kind = kind.strip()
            if kind not in DEFAULT_LIMITS:
                raise ValueError(f"unknown file kind '{kind}' (choose {', '.join(KINDS)})")
            out[kind] = parse_size(size)
        else:
            value = parse_size(spec)
            out.update(dict.fromkeys(KINDS, value))
    return out


def describe(mode: int) -> str | None:
    """What a non-regular file is, in words; ``None`` for a regular file."""
    if stat.S_ISREG(mode):
        return None
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISCHR(mode):
        return "a character device"
    if stat.S_ISBLK(mode):
        return "a block device"
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def human(size: int) -> str:
    if size >= MiB:
        return f"{size / MiB:.0f} MiB" if size % MiB == 0 else f"{size / MiB:.1f} MiB"
    return f"{size} bytes"


def _refuse_kind(path: str, mode: int, kind: str) -> None:
    what = describe(mode)
    if what is not None:
        raise UnsafeFile(path, f"is {what}, not a regular file; urdftool reads {kind} files only "
                               "from regular files")


def _refuse_size(path: str, size: int, kind: str) -> None:
    cap = limit(kind)
    if size > cap:
        raise UnsafeFile(path, f"{kind} file is {human(size)}, over the {human(cap)} cap; "
                               f"raise it with --max-file-size {kind}=SIZE if the file is right")


def check_regular(path: str | os.PathLike[str], kind: str = "mesh", check_size: bool = True,
                  status: os.stat_result | None = None) -> None:
    """Raise :class:`UnsafeFile` unless *path* is a regular file within *kind*'s cap
    (``OSError`` when it does not exist). For readers that open the file themselves.
    *status*: its ``os.stat``, when the caller has it."""
    path = os.fspath(path)
    info = os.stat(path) if status is None else status
    _refuse_kind(path, info.st_mode, kind)
    if check_size:
        _refuse_size(path, info.st_size, kind)


def is_regular(path: str | os.PathLike[str]) -> bool:
    try:
        return stat.S_ISREG(os.stat(path).st_mode)
    except OSError:
        return False


def open_regular(path: str | os.PathLike[str], kind: str = "mesh", check_size: bool = True) -> BinaryIO:
    """Open *path* for binary reading if it is a regular file within *kind*'s cap.

    The open never blocks (a FIFO with no writer would hang a plain ``open``);
    the checks run on the opened descriptor, so a swapped file cannot slip in.
    """
    fd, _ = _open_descriptor(os.fspath(path), kind, check_size)
    try:
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def _open_descriptor(path: str, kind: str, check_size: bool) -> tuple[int, os.stat_result]:
    """A blocking descriptor of *path* opened without blocking, and its status, once it is known to
    be a regular file (within *kind*'s cap with *check_size*). Raises ``OSError``/:class:`UnsafeFile`."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0))
    try:
        info = os.fstat(fd)
        _refuse_kind(path, info.st_mode, kind)
        if check_size:
            _refuse_size(path, info.st_size, kind)
        if hasattr(os, "set_blocking"):
            os.set_blocking(fd, True)
        return fd, info
    except BaseException:
        os.close(fd)
        raise


def read_up_to(path: str | os.PathLike[str], kind: str, check_size: bool = False,
               cap: int | None = None) -> bytes:
    """At most one byte more than *cap* (*kind*'s cap by default) of the regular file *path*, so
    the caller can tell an oversized file; with *check_size*, a file already over *kind*'s cap
    is refused before it is read. Read on the descriptor, to the size the file has: a buffered
    file object cost more than reading a small file, and asking it for ``cap + 1`` bytes
    allocated that much (64 MiB for every model) before reading. A file that grows while read
    is read on up to the cap. Raises ``OSError``/:class:`UnsafeFile`."""
    path = os.fspath(path)
    cap = limit(kind) if cap is None else cap
    fd, info = _open_descriptor(path, kind, check_size)
    try:
        data = _read(fd, min(cap, info.st_size) + 1)
        if len(data) > info.st_size:  # the file grew while read: the rest, up to the cap
            data += _read(fd, cap + 1 - len(data))
        return data
    finally:
        os.close(fd)


def _read(fd: int, size: int) -> bytes:
    """Up to *size* bytes from *fd*: a read may return less than asked for, the end b""."""
    chunks = []
    while size > 0 and (chunk := os.read(fd, min(size, 1 << 24))):
        chunks.append(chunk)
        size -= len(chunk)
    return chunks[0] if len(chunks) == 1 else b"".join(chunks)


def read_regular(path: str | os.PathLike[str], kind: str = "mesh") -> bytes:
    """The bytes of *path*, if it is a regular file within *kind*'s cap (a file growing
    while read is cut at the cap and refused). Raises ``OSError``/:class:`UnsafeFile`."""
    data = read_up_to(path, kind, check_size=True)
    if len(data) > limit(kind):
        _refuse_size(os.fspath(path), len(data), kind)
    return data


def read_head(path: str | os.PathLike[str], size: int, kind: str = "mesh") -> bytes:
    """The first *size* bytes of a regular file (for sniffing formats)."""
    with open_regular(path, kind) as handle:
        return handle.read(size)


def describe_path(path: str | os.PathLike[str]) -> str | None:
    """What an existing non-regular file is ("a character device"…); ``None`` for a regular
    file or a path where nothing exists."""
    try:
        return describe(os.stat(path).st_mode)
    except OSError:
        return None
