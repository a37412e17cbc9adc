"""Summaries of a robot: what ``urdftool info`` prints, as data."""

from __future__ import annotations

from collections import Counter
from typing import Any

from urdftool.model import KinematicTree, Robot
from urdftool.physics.com import center_of_mass


def summarize(robot: Robot) -> dict[str, Any]:
    """Name, root, link and joint counts, DOF, total mass (kg), centre of mass (m, root frame
    at q = 0), loops, and the tree outline."""
    tree = KinematicTree.of(robot)
    types = Counter(j.type.value for j in robot.joints)
    outline = []
    for depth, link, joint in tree.walk():
        mass = link.inertial.mass if link.inertial else None
        outline.append(
            {
                "depth": depth,
                "link": link.name,
                "mass": mass,
                "joint": joint.name if joint else None,
                "joint_type": joint.type.value if joint else None,
            }
        )
    loops = [j.name for j in tree.cycle_joints] + [lc.joint.name for lc in robot.loop_closures]
    return {
        "robot": robot.name,
        "path": robot.path,
        "format": robot.format,
        "root": tree.root,
        "roots": tree.roots,
        "links": len(robot.links),
        "joints": len(robot.joints),
        "joints_by_type": dict(sorted(types.items())),
        "dof": tree.dof,
        "mimic_joints": sum(1 for j in robot.joints if j.mimic is not None),
        "total_mass": robot.total_mass,
        "center_of_mass": center_of_mass(robot, tree),
        "links_without_inertial": sum(1 for link in robot.links if link.inertial is None),
        "loops": loops,
        "tree": outline,
    }


def format_summary(summary: dict[str, Any]) -> str:
    lines = [
        f"robot:       {summary['robot']}",
        f"file:        {summary['path']} ({summary['format']})",
        f"root:        {summary['root']}"
        + (f"  (also: {', '.join(summary['roots'][1:])})" if len(summary["roots"]) > 1 else ""),
        f"links:       {summary['links']}"
        + (
            f" ({summary['links_without_inertial']} without <inertial>)"
            if summary["links_without_inertial"]
            else ""
        ),
        f"joints:      {summary['joints']}"
        + (
            " (" + ", ".join(f"{n} {t}" for t, n in summary["joints_by_type"].items()) + ")"
            if summary["joints"]
            else ""
        ),
        f"DOF:         {summary['dof']}"
        + (f" (+{summary['mimic_joints']} mimic)" if summary["mimic_joints"] else ""),
        f"total mass:  {summary['total_mass']:.6g} kg",
        f"COM:         {_com_text(summary.get('center_of_mass'))}",
        f"loops:       {len(summary['loops'])}"
        + (f" (closed by {', '.join(summary['loops'])})" if summary["loops"] else ""),
        "",
        "tree:",
    ]
    for row in summary["tree"]:
        indent = "  " * (row["depth"] + 1)
        mass = "" if row["mass"] is None else f" [{row['mass']:.4g} kg]"
        via = "" if row["joint"] is None else f"  <- {row['joint']} ({row['joint_type']})"
        lines.append(f"{indent}{row['link']}{mass}{via}")
    return "\n".join(lines) + "\n"


def _com_text(com: Any) -> str:
    if com is None:
        return "none (no link has mass)"
    return "(" + ", ".join(f"{v:.4g}" for v in com) + ") m in the root frame at q = 0"
