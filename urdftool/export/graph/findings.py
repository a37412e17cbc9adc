"""Which links and joints the findings are about, for colouring the diagram.

A :class:`~urdftool.diagnostics.Diagnostic` names its element as a path in the
robot's terms: ``link[forearm]/inertial``, ``joint[elbow]/limit``, ``robot``.
Names may themselves hold ``]`` or ``/``, so the name is matched against the
robot's own link and joint names rather than cut at the first bracket.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import field

from urdftool.diagnostics import Diagnostic, Severity
from urdftool.model import Robot
from urdftool.records import record

#: border and text colour of a node with findings, by worst severity
SEVERITY_COLOURS = {Severity.ERROR: "#d62728", Severity.WARNING: "#e08000"}


@record(frozen=False)
class Findings:
    """Error and warning findings grouped by the link or joint they are about."""

    links: dict[str, list[Diagnostic]] = field(default_factory=dict)
    joints: dict[str, list[Diagnostic]] = field(default_factory=dict)
    #: about the robot as a whole, or about nothing drawn (materials, unknown paths)
    other: list[Diagnostic] = field(default_factory=list)

    @classmethod
    def of(cls, robot: Robot, diagnostics: Iterable[Diagnostic]) -> Findings:
        """Group the error and warning findings; infos are not drawn."""
        found = cls()
        names = {"link": {link.name for link in robot.links}, "joint": _joint_names(robot)}
        for diagnostic in diagnostics:
            if diagnostic.severity not in SEVERITY_COLOURS:
                continue
            target = element_target(diagnostic.element, names)
            if target is None:
                found.other.append(diagnostic)
            else:
                kind, name = target
                bucket = found.links if kind == "link" else found.joints
                bucket.setdefault(name, []).append(diagnostic)
        return found

    def for_links(self, names: Iterable[str]) -> list[Diagnostic]:
        return [d for name in names for d in self.links.get(name, [])]

    def for_joint(self, name: str) -> list[Diagnostic]:
        return list(self.joints.get(name, []))


def _joint_names(robot: Robot) -> set[str]:
    names = {joint.name for joint in robot.joints}
    names.update(closure.joint.name for closure in robot.loop_closures)
    return names


def element_target(element: str | None, names: dict[str, set[str]]) -> tuple[str, str] | None:
    """``("link", "forearm")`` for ``link[forearm]/inertial``; ``None`` when nothing drawn matches.

    The longest known name wins, so ``link[a]b]/x`` finds a link named ``a]b``.
    """
    if not element:
        return None
    for kind in ("link", "joint"):
        prefix = f"{kind}["
        if not element.startswith(prefix):
            continue
        rest = element[len(prefix) :]
        candidates = [
            i
            for i, char in enumerate(rest)
            if char == "]" and (i + 1 == len(rest) or rest[i + 1] == "/")
        ]
        for end in reversed(candidates):
            if rest[:end] in names[kind]:
                return kind, rest[:end]
    return None


def worst(diagnostics: Iterable[Diagnostic]) -> Severity | None:
    """The highest severity among *diagnostics*, or ``None`` when there are none."""
    ranked = sorted((d.severity for d in diagnostics), key=lambda s: s.rank, reverse=True)
    return ranked[0] if ranked else None


def code_notes(diagnostics: Iterable[Diagnostic]) -> list[tuple[str, str]]:
    """``(colour, "error: I003 S015")`` lines, errors first, codes sorted and unique."""
    notes = []
    found = list(diagnostics)
    for severity, colour in SEVERITY_COLOURS.items():
        codes = sorted({d.code for d in found if d.severity is severity})
        for start in range(0, len(codes), 4):  # four codes a line keeps nodes narrow
            chunk = " ".join(codes[start : start + 4])
            notes.append((colour, f"{severity.value}: {chunk}" if start == 0 else chunk))
    return notes


def tooltip(diagnostics: Iterable[Diagnostic], limit: int = 8) -> str:
    """The messages, one per line, for hovering in SVG viewers."""
    found = list(diagnostics)
    lines = [f"{d.code} {d.name}: {d.message}" for d in found[:limit]]
    if len(found) > limit:
        lines.append(f"... and {len(found) - limit} more")
    return "\n".join(lines)
