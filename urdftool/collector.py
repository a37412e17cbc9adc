"""Pausing Python's cyclic garbage collector where urdftool builds many objects and few cycles."""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def collector_paused() -> Iterator[None]:
    """Pause the cyclic collector for the block, and restore it after (if it was running).

    Two places use it: reading and checking one file (reading builds many long-lived objects
    and few cycles; the collector's full passes over them made a 100k-link model take 14× as
    long as a 10k one), and importing urdftool's modules (thousands of functions and classes
    that live as long as the process: a collection during the imports frees nothing and cost
    5 % of a small ``urdftool check``).
    """
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()
