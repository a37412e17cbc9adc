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
from urdftool.diagnostics import Diagnostic, FileReport, Report, Severity
from urdftool.model import Robot
from urdftool.source import Span
from urdftool.version import __version__

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
