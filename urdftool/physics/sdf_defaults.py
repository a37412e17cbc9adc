"""SDFormat's default ``<inertial>``: what every SDF reader gives a link that declares none.

libsdformat, gz-sim and Gazebo classic give such a link 1 kg and a unit inertia
(1 kg·m² about each axis of the link frame, centre of mass at the link origin).
The dynamics pass computes with it, and the exports to formats without that
default (MJCF, PyBullet's URDF, URDF) write it out, so the exported robot weighs
what the SDF robot weighs in its own simulator. ``missing-inertial`` still says
the mass is not the author's.
"""

from __future__ import annotations

from dataclasses import replace

from urdftool.model import Inertial, Link, Robot

#: SDFormat's ``<inertial>`` when a link has none: 1 kg, a unit inertia (kg·m²) at the link origin
SDF_DEFAULT_INERTIAL = Inertial(1.0, ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)))


def defaulted_links(robot: Robot) -> list[Link]:
    """The links of an SDF *robot* that take SDFormat's default inertial (none for other formats;
    never ``world``, which is not a body)."""
    if robot.format != "sdf":
        return []
    return [link for link in robot.links if link.inertial is None and link.name != "world"]


def sdf_default_inertials(robot: Robot) -> Robot:
    """*robot* with SDFormat's default inertial on every SDF link that has none."""
    defaulted = {link.name for link in defaulted_links(robot)}
    if not defaulted:
        return robot
    links = tuple(replace(link, inertial=SDF_DEFAULT_INERTIAL) if link.name in defaulted else link
                  for link in robot.links)
    return replace(robot, links=links)
