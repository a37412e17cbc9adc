"""``urdftool collisions``: MoveIt's self-collision matrix, written as SRDF or MJCF.

:func:`collision_matrix` samples the model (see
:func:`urdftool.facts.collisions.matrix`); :func:`srdf_bytes` writes the
disabled pairs as ``<disable_collisions>`` entries, either into a new minimal
SRDF or merged into an existing one: every ``<disable_collisions>`` element of
the existing file is replaced, every other byte (declaration, comments,
groups, states, indentation, line endings) is kept. :func:`mjcf_bytes` writes
a MuJoCo ``<contact>`` block of ``<exclude>`` pairs in a ``<mujoco>`` file that
a model can ``<include>``; bodies are named after links, as the MJCF exporter
names them.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from xml.sax.saxutils import quoteattr

from urdftool.facts.collisions import Matrix, NotChecked, matrix, scene_of
from urdftool.facts.context import CheckContext
from urdftool.model import KinematicTree, Robot

#: The order MoveIt Setup Assistant's reasons are listed in the report.
REASONS = ("Adjacent", "Default", "Always", "Never")


class NoMatrix(Exception):
    """The model has no collision matrix to compute (no geometry, or a joint Pinocchio cannot model)."""


def collision_matrix(robot: Robot, samples: int = 10_000, seed: int = 0,
                     progress: Callable[[int], None] | None = None,
                     options: dict[str, object] | None = None) -> Matrix:
    """Classify every pair of *robot*'s links with collision geometry. Raises :class:`NoMatrix`."""
    ctx = CheckContext(robot, KinematicTree.of(robot), options={**(options or {}), "dynamics": True})
    # The home check's budget does not apply: the user asked for this matrix.
    scene = scene_of(ctx, limit=1 << 30)
    if isinstance(scene, NotChecked):
        raise NoMatrix(scene.reason)
    if scene is None or len(scene.links()) < 2:
        raise NoMatrix("fewer than two links have collision geometry (or Pinocchio and coal are missing)")
    return matrix(robot, scene, samples, seed, progress)


def disabled_lines(found: Matrix, indent: str) -> list[str]:
    out = []
    for (a, b), reason in sorted(found.reasons.items()):
        out.append(f"{indent}<disable_collisions link1={quoteattr(a)} link2={quoteattr(b)} "
                   f"reason={quoteattr(reason)}/>")
    return out


def new_srdf(found: Matrix, robot_name: str) -> bytes:
    lines = ['<?xml version="1.0" encoding="UTF-8"?>',
             f"<!-- Self-collision matrix written by urdftool collisions: {found.samples} samples, "
             f"seed {found.seed}. -->",
             f"<robot name={quoteattr(robot_name)}>",
             *disabled_lines(found, "    "),
             "</robot>", ""]
    return "\n".join(lines).encode("utf-8")


_COMMENT = re.compile(rb"<!--.*?-->", re.S)
_ENTRY = re.compile(
    rb"[ \t]*<disable_collisions\b[^>]*?(?:/>|>.*?</disable_collisions\s*>)[ \t]*(?:\r?\n)?", re.S)
_CLOSE = re.compile(rb"</robot\s*>")
_CHILD_INDENT = re.compile(rb"\n([ \t]+)<[A-Za-z]")


def merge_srdf(existing: bytes, found: Matrix) -> bytes:
    """*existing* with its ``<disable_collisions>`` replaced by *found*'s (the rest byte for byte)."""
    comments = [m.span() for m in _COMMENT.finditer(existing)]
    entries = [m for m in _ENTRY.finditer(existing)
               if not any(lo <= m.start() < hi for lo, hi in comments)]
    newline = b"\r\n" if b"\r\n" in existing else b"\n"
    indent_match = _CHILD_INDENT.search(existing)
    indent = indent_match.group(1).decode() if indent_match else "    "
    if entries:
        first = entries[0].group(0)
        indent = first[: len(first) - len(first.lstrip(b" \t"))].decode()
    block = newline.join(line.encode("utf-8") for line in disabled_lines(found, indent)) + newline
    if entries:
        out = bytearray()
        cursor = 0
        for index, m in enumerate(entries):
            out += existing[cursor:m.start()]
            if index == 0:
                out += block
            cursor = m.end()
        out += existing[cursor:]
        return bytes(out)
    close = None
    for m in _CLOSE.finditer(existing):
        if not any(lo <= m.start() < hi for lo, hi in comments):
            close = m
    if close is None:
        raise ValueError("the existing file has no </robot> to add the entries before")
    line_start = existing.rfind(b"\n", 0, close.start()) + 1
    if existing[line_start:close.start()].strip():
        return existing[:close.start()] + newline + block + existing[close.start():]
    return existing[:line_start] + block + existing[line_start:]


def srdf_bytes(found: Matrix, robot_name: str, existing: bytes | None = None) -> bytes:
    return new_srdf(found, robot_name) if existing is None else merge_srdf(existing, found)


def mjcf_bytes(found: Matrix, robot_name: str) -> bytes:
    """A ``<mujoco>`` file holding one ``<contact>`` block with an ``<exclude>`` per disabled pair."""
    lines = [f"<!-- Self-collision exclusions written by urdftool collisions: {found.samples} samples, "
             f"seed {found.seed}; <include file=\"…\"/> it in the robot's MJCF. -->",
             f"<mujoco model={quoteattr(robot_name)}>", "  <contact>"]
    for (a, b), reason in sorted(found.reasons.items()):
        lines.append(f"    <exclude name={quoteattr(f'{a}:{b}')} body1={quoteattr(a)} body2={quoteattr(b)}/>"
                     f"  <!-- {reason} -->")
    lines += ["  </contact>", "</mujoco>", ""]
    return "\n".join(lines).encode("utf-8")


def summary(found: Matrix) -> dict[str, int]:
    counts = {reason: 0 for reason in REASONS}
    for reason in found.reasons.values():
        counts[reason] = counts.get(reason, 0) + 1
    return counts
