"""The robot's ``<gazebo>`` blocks and the plugins in them, found once per model.

The reader keeps ``<gazebo>``, ``<plugin>``, ``<transmission>`` and ``<ros2_control>`` as
:class:`~urdftool.model.Extension` elements in the robot's list of extensions. A dozen Gazebo
rules (reference names, plugin joints and frames, drive geometry, gz-sim systems, ros2_control
sensors) walked that list, and every block's subtree for its plugins, each on its own; here the
walk is made once per model and the rules read its result. What the blocks mean is in
:mod:`urdftool.rules.gazebo_plugins`.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from urdftool.facts.context import CheckContext
from urdftool.model import Robot


def blocks_of(robot: Robot) -> Iterator[Any]:
    """Every top-level ``<gazebo>`` element of *robot*, as lxml elements, in document order."""
    for extension in robot.extensions:
        if extension.tag == "gazebo" and extension.element is not None:
            yield extension.element


def plugins_of(robot: Robot) -> Iterator[Any]:
    """Every ``<plugin>`` in *robot*'s ``<gazebo>`` blocks (at any depth: sensors carry plugins
    too), then those at the top level of the robot."""
    for block in blocks_of(robot):
        yield from block.iter("plugin")
    for extension in robot.extensions:
        if extension.tag == "plugin" and extension.element is not None:
            yield extension.element


def gazebo_blocks(ctx: CheckContext) -> tuple[Any, ...]:
    """:func:`blocks_of` the robot under check, found once per model."""
    key = ("gazebo-blocks",)
    if key not in ctx.cache:
        ctx.cache[key] = tuple(blocks_of(ctx.robot))
    return ctx.cache[key]  # type: ignore[no-any-return]


def plugins(ctx: CheckContext) -> tuple[Any, ...]:
    """:func:`plugins_of` the robot under check, found once per model."""
    key = ("gazebo-plugins",)
    if key not in ctx.cache:
        ctx.cache[key] = tuple(plugins_of(ctx.robot))
    return ctx.cache[key]  # type: ignore[no-any-return]


def preserved_fixed_joints(ctx: CheckContext) -> frozenset[str]:
    """Fixed joints that Gazebo keeps: the ``reference`` of every ``<gazebo>`` block that sets
    ``preserveFixedJoint`` or ``disableFixedJointLumping`` (as text or ``value``) to true."""
    key = ("gazebo-preserved-joints",)
    if key not in ctx.cache:
        kept: set[str] = set()
        for block in gazebo_blocks(ctx):
            reference = block.get("reference")
            if not reference:
                continue
            # lxml's tag filter: the block's other children (most of them) are not built
            for child in block.iterchildren("preserveFixedJoint", "disableFixedJointLumping"):
                value = (child.get("value") or (child.text or "").strip()).lower()
                if value in ("true", "yes", "1"):
                    kept.add(reference)
        ctx.cache[key] = frozenset(kept)
    return ctx.cache[key]  # type: ignore[no-any-return]


def defined_joints(ctx: CheckContext) -> frozenset[str]:
    """Joints defined in SDF inside ``<gazebo>`` blocks (Gazebo adds them to the model)."""
    key = ("gazebo-defined-joints",)
    if key not in ctx.cache:
        ctx.cache[key] = frozenset(
            name for block in gazebo_blocks(ctx) for child in block.iterchildren("joint")
            if (name := child.get("name"))
        )
    return ctx.cache[key]  # type: ignore[no-any-return]


__all__ = [
    "blocks_of",
    "defined_joints",
    "gazebo_blocks",
    "plugins",
    "plugins_of",
    "preserved_fixed_joints",
]
