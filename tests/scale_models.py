"""Large generated robots (long chains, wide trees) for depth and scale tests and benchmarks."""

from __future__ import annotations

_INERTIAL = (
    '<inertial><mass value="1"/><inertia ixx="0.00167" iyy="0.00167" izz="0.00167"'
    ' ixy="0" ixz="0" iyz="0"/></inertial>'
)
_BOX = '<geometry><box size="0.1 0.1 0.1"/></geometry>'


def _link(i: int) -> str:
    return f'<link name="l{i}">{_INERTIAL}<visual>{_BOX}</visual><collision>{_BOX}</collision></link>'


def _joint(i: int, parent: int, joint_type: str) -> str:
    extra = ""
    if joint_type in ("revolute", "prismatic"):
        extra = '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="1"/>'
    elif joint_type == "continuous":
        extra = '<axis xyz="0 0 1"/>'
    return (
        f'<joint name="j{i}" type="{joint_type}"><parent link="l{parent}"/><child link="l{i}"/>'
        f'<origin xyz="0 0 0.1" rpy="0 0 0.01"/>{extra}</joint>'
    )


def chain_urdf(links: int, joint_type: str = "fixed") -> str:
    """A serial chain of *links* links, each hanging from the previous one."""
    parts = ['<?xml version="1.0"?>', '<robot name="chain">']
    parts += [_link(i) for i in range(links)]
    parts += [_joint(i, i - 1, joint_type) for i in range(1, links)]
    parts.append("</robot>\n")
    return "\n".join(parts)


def tree_urdf(links: int, joint_type: str = "revolute", branching: int = 3) -> str:
    """A balanced tree of *links* links: link i hangs from link (i - 1) // branching."""
    parts = ['<?xml version="1.0"?>', '<robot name="tree">']
    parts += [_link(i) for i in range(links)]
    parts += [_joint(i, (i - 1) // branching, joint_type) for i in range(1, links)]
    parts.append("</robot>\n")
    return "\n".join(parts)
