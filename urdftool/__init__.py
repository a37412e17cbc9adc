"""urdftool: a compiler and checker for robot descriptions (xacro, URDF, SDF).

The public API::

    robot = urdftool.load("arm.urdf.xacro", xacro_args={"prefix": "left_"})
    report = urdftool.check("arm.urdf.xacro", ignore=["I"])
    if not report.ok:
        for d in report.errors:
            print(d.location, d.message)

Nothing here prints or exits; heavy engines (trimesh, Pinocchio, MuJoCo,
PyBullet) are imported only by the functions that need them.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from urdftool.diagnostics import Diagnostic, FileReport, Report, Severity
from urdftool.model import Robot
from urdftool.source import Span
from urdftool.version import __version__

if TYPE_CHECKING:
    from urdftool.api import (
        ConversionRefused,
        LoadError,
        check,
        check_many,
        diff,
        load,
        simulate,
        to_dot,
        to_mjcf,
        to_sdf,
        to_urdf,
    )

#: The API's functions load the pipeline (readers, rules, exporters) on first use, so that
#: ``import urdftool`` and the CLI's start (which imports this package first) stay fast.
_API = frozenset({
    "ConversionRefused", "LoadError", "check", "check_many", "diff", "load", "simulate",
    "to_dot", "to_mjcf", "to_sdf", "to_urdf",
})


def __getattr__(name: str) -> Any:
    if name not in _API:
        raise AttributeError(f"module 'urdftool' has no attribute '{name}'")
    value = getattr(importlib.import_module("urdftool.api"), name)
    globals()[name] = value
    return value


__all__ = [
    "ConversionRefused",
    "Diagnostic",
    "FileReport",
    "LoadError",
    "Report",
    "Robot",
    "Severity",
    "Span",
    "__version__",
    "check",
    "check_many",
    "diff",
    "load",
    "simulate",
    "to_dot",
    "to_mjcf",
    "to_sdf",
    "to_urdf",
]
