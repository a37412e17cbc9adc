"""Modules imported on first use.

NumPy alone costs more to import than the rest of a structural ``urdftool
check``; the rule modules that need it name it through :data:`numpy`, which
imports the real module the first time an attribute is read and from then on
behaves as the module itself (its attributes are copied onto the proxy, so
later lookups cost nothing extra).

Use it as::

    if TYPE_CHECKING:
        import numpy as np
    else:
        from urdftool.lazy import numpy as np

The check path names the project modules that only some runs need the same way
(``fixes = LazyModule("urdftool.pipeline.fixes")`` beside a ``TYPE_CHECKING``
import): the import-linter contract counts ``TYPE_CHECKING`` imports, so the
dependency stays visible to the layer rules; ``tests/test_imports.py`` lists
the modules a structural check must not load.
"""

from __future__ import annotations

import importlib
import types
from typing import Any


class LazyModule(types.ModuleType):
    """A stand-in for the module *name* that imports it on first attribute access."""

    def __init__(self, name: str) -> None:
        super().__init__(name)

    def __getattr__(self, attribute: str) -> Any:
        module = importlib.import_module(self.__name__)
        self.__dict__.update(module.__dict__)
        return getattr(module, attribute)


numpy = LazyModule("numpy")
yaml = LazyModule("yaml")
