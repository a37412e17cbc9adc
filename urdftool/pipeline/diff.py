"""What a change did to the robot: a structural comparison of two descriptions.

Both sides go through the same pipeline (the same xacro arguments and packages),
then links and joints are matched by name, and what is left by position in the
tree (reported as renames). For each match the comparison says what moved:
joint type, axis, limits and dynamics; each link's pose at the zero
configuration (mm and degrees); mass, centre of mass and inertia per link and in
total; meshes swapped; Gazebo and ros2_control blocks; findings that appeared or
disappeared. Layout, attribute order and element order do not count: a
reformatted or reordered file diffs as empty.
"""

from __future__ import annotations

import contextlib
import math
import os
import re
import subprocess
import tempfile
from collections import Counter
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import field
from typing import TYPE_CHECKING, Any

from urdftool.diagnostics import Diagnostic, Severity
from urdftool.model import KinematicTree, Robot
from urdftool.model.geometry import Mesh
from urdftool.model.robot import Extension, Joint, Link
from urdftool.pipeline.check import CheckOptions, report_for
from urdftool.pipeline.load import load_one
from urdftool.records import record
from urdftool.source import SRC_ATTRIBUTE

if TYPE_CHECKING:
    import numpy as np
else:
    from urdftool.lazy import numpy as np

#: differences at or below these are rounding, not changes (m, rad, kg, kg·m²)
LENGTH_TOL = 1e-9
ANGLE_TOL = 1e-9
MASS_TOL = 1e-12
INERTIA_TOL = 1e-12


@record
class Change:
    """One thing that differs: ``kind`` (what sort), ``subject`` (the link or joint, as named in
    the new file), ``field``, the old and new values, and a size where one applies."""

    kind: str
    subject: str
    field: str = ""
    old: Any = None
    new: Any = None
    #: mm for a move, degrees for a turn, percent for a mass, kg·m² for inertia
    size: float | None = None
    unit: str = ""
    severity: str | None = None

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"kind": self.kind, "subject": self.subject, "field": self.field,
                               "old": self.old, "new": self.new}
        if self.size is not None:
            out["size"] = self.size
            out["unit"] = self.unit
        if self.severity is not None:
            out["severity"] = self.severity
        return out


@record
class RobotDiff:
    """The changes from *old* to *new*, and the renames found."""

    old: str
    new: str
    changes: tuple[Change, ...]
    link_renames: Mapping[str, str] = field(default_factory=dict)
    joint_renames: Mapping[str, str] = field(default_factory=dict)

    @property
    def empty(self) -> bool:
        return not self.changes

    def of_kind(self, *kinds: str) -> list[Change]:
        return [c for c in self.changes if c.kind in kinds]

    def to_json(self) -> dict[str, Any]:
        return {"old": self.old, "new": self.new, "empty": self.empty,
                "renames": {"links": dict(self.link_renames), "joints": dict(self.joint_renames)},
                "changes": [c.to_json() for c in self.changes]}


# -- matching --------------------------------------------------------------------------------


def match(old: Robot, new: Robot) -> tuple[dict[str, str], dict[str, str]]:
    """Old link and joint names to new ones: by name, then by position in the tree."""
    old_links, new_links = {lk.name for lk in old.links}, {lk.name for lk in new.links}
    links = {n: n for n in old_links & new_links}
    old_joints, new_joints = {j.name: j for j in old.joints}, {j.name: j for j in new.joints}
    joints = {n: n for n in old_joints.keys() & new_joints.keys()}
    old_tree, new_tree = KinematicTree.of(old), KinematicTree.of(new)
    old_roots = [r for r in old_tree.roots if r not in links]
    new_roots = [r for r in new_tree.roots if r not in links.values()]
    if len(old_roots) == 1 and len(new_roots) == 1:
        links[old_roots[0]] = new_roots[0]
    changed = True
    while changed:
        changed = False
        taken_links = set(links.values())
        for name, new_name in list(joints.items()):
            a, b = old_joints[name], new_joints[new_name]
            for end in ("parent", "child"):
                x, y = getattr(a, end), getattr(b, end)
                if x not in links and y not in taken_links and x in old_links and y in new_links:
                    links[x] = y
                    taken_links.add(y)
                    changed = True
        taken_joints = set(joints.values())
        free_new = [j for n, j in new_joints.items() if n not in taken_joints]
        for name, joint in old_joints.items():
            if name in joints:
                continue
            parent = links.get(joint.parent)
            child = links.get(joint.child)
            exact = [j for j in free_new if j.parent == parent and child is not None and j.child == child]
            if len(exact) == 1:
                candidate = exact[0]
            else:
                # the one unmatched joint under the same parent on both sides, of the same type
                siblings_old = [j for n, j in old_joints.items()
                                if n not in joints and j.parent == joint.parent]
                siblings_new = [j for j in free_new if parent is not None and j.parent == parent]
                if len(siblings_old) != 1 or len(siblings_new) != 1 or siblings_new[0].type != joint.type:
                    continue
                candidate = siblings_new[0]
            joints[name] = candidate.name
            free_new.remove(candidate)
            changed = True
    return links, joints


# -- comparison ------------------------------------------------------------------------------


def _close(a: Sequence[float], b: Sequence[float], tol: float) -> bool:
    return all(abs(x - y) <= tol for x, y in zip(a, b, strict=True))


def _rounded(values: Sequence[float]) -> list[float]:
    return [float(v) for v in values]


def _joint_changes(a: Joint, b: Joint, links: Mapping[str, str],
                   joints: Mapping[str, str]) -> Iterator[Change]:
    name = b.name
    if a.type != b.type:
        yield Change("joint", name, "type", a.type.value, b.type.value)
    if links.get(a.parent, a.parent) != b.parent:
        yield Change("joint", name, "parent", a.parent, b.parent)
    if links.get(a.child, a.child) != b.child:
        yield Change("joint", name, "child", a.child, b.child)
    if not _close(a.axis, b.axis, ANGLE_TOL):
        yield Change("joint", name, "axis", _rounded(a.axis), _rounded(b.axis))
    if (not _close(a.origin.xyz, b.origin.xyz, LENGTH_TOL)
            or not _close(a.origin.rpy, b.origin.rpy, ANGLE_TOL)):
        yield Change("joint", name, "origin", {"xyz": list(a.origin.xyz), "rpy": list(a.origin.rpy)},
                     {"xyz": list(b.origin.xyz), "rpy": list(b.origin.rpy)})
    for part, fields in (("limit", ("lower", "upper", "effort", "velocity")),
                         ("dynamics", ("damping", "friction")),
                         ("mimic", ("joint", "multiplier", "offset"))):
        x, y = getattr(a, part), getattr(b, part)
        for key in fields:
            u = getattr(x, key) if x is not None else None
            v = getattr(y, key) if y is not None else None
            if part == "mimic" and key == "joint" and isinstance(u, str):
                u = joints.get(u, u)
            if u != v and not (isinstance(u, float) and isinstance(v, float) and abs(u - v) <= 1e-12):
                yield Change("joint", name, f"{part}.{key}", u, v)


def _rotation_angle(r: Any) -> float:
    cos = max(-1.0, min(1.0, (float(np.trace(r)) - 1.0) / 2.0))
    return math.acos(cos)


def _inertia_world(link: Link) -> Any:
    assert link.inertial is not None
    return link.inertial.inertia_in_link_frame


def _link_changes(a: Link, b: Link, pose_a: Any, pose_b: Any) -> Iterator[Change]:
    name = b.name
    if pose_a is not None and pose_b is not None:
        moved = float(np.linalg.norm(pose_b[:3, 3] - pose_a[:3, 3]))
        turned = _rotation_angle(pose_a[:3, :3].T @ pose_b[:3, :3])
        if moved > LENGTH_TOL:
            yield Change("pose", name, "position", _rounded(pose_a[:3, 3]), _rounded(pose_b[:3, 3]),
                         moved * 1000.0, "mm")
        if turned > ANGLE_TOL:
            yield Change("pose", name, "orientation", None, None, math.degrees(turned), "deg")
    ma = a.inertial.mass if a.inertial else None
    mb = b.inertial.mass if b.inertial else None
    if (ma is None) != (mb is None) or (ma is not None and mb is not None and abs(ma - mb) > MASS_TOL):
        size = abs((mb or 0.0) - (ma or 0.0)) / abs(ma) * 100.0 if ma else math.inf
        yield Change("mass", name, "mass", ma, mb, size, "%")
    if a.inertial and b.inertial:
        ca, cb = a.inertial.origin.xyz, b.inertial.origin.xyz
        if not _close(ca, cb, LENGTH_TOL):
            moved = math.dist(ca, cb)
            yield Change("com", name, "com", list(ca), list(cb), moved * 1000.0, "mm")
        ia, ib = _inertia_world(a), _inertia_world(b)
        worst = float(np.max(np.abs(ia - ib)))
        if worst > INERTIA_TOL:
            yield Change("inertia", name, "inertia", ia.round(15).tolist(), ib.round(15).tolist(),
                         worst, "kg·m²")
    for role in ("visual", "collision"):
        old, new = _meshes(a, role), _meshes(b, role)
        if old != new:
            yield Change("mesh", name, role, [list(m) for m in old], [list(m) for m in new])


def _meshes(link: Link, role: str) -> list[tuple[str, list[float]]]:
    items = link.visuals if role == "visual" else link.collisions
    out = []
    for item in items:
        geometry = item.geometry
        if isinstance(geometry, Mesh):
            out.append((geometry.filename, [float(s) for s in geometry.scale]))
    return sorted(out)


def _totals(robot: Robot, tree: KinematicTree, poses: Mapping[str, Any]) -> tuple[float, Any]:
    mass = 0.0
    moment = np.zeros(3)
    for link in robot.links:
        if link.inertial is None or link.name not in poses:
            continue
        com = poses[link.name] @ np.array([*link.inertial.origin.xyz, 1.0])
        mass += link.inertial.mass
        moment += link.inertial.mass * com[:3]
    return mass, (moment / mass if mass > 0 else moment)


def _extension_key(extension: Extension) -> str:
    def canon(element: Any) -> str:
        tag = element.tag if isinstance(element.tag, str) else ""
        attrs = sorted((k, v) for k, v in element.attrib.items() if k != SRC_ATTRIBUTE)
        text = (element.text or "").strip()
        children = "".join(canon(child) for child in element if isinstance(child.tag, str))
        return f"<{tag} {attrs}>{text}{children}</{tag}>"

    if extension.element is None:
        return f"{extension.tag}{sorted(extension.attributes.items())}"
    return canon(extension.element)


def _extension_changes(old: Robot, new: Robot) -> Iterator[Change]:
    def all_extensions(robot: Robot) -> Counter[tuple[str, str, str]]:
        found: Counter[tuple[str, str, str]] = Counter()
        owners = [("robot", robot.extensions)] + [(lk.name, lk.extensions) for lk in robot.links] + [
            (j.name, j.extensions) for j in robot.joints]
        for owner, extensions in owners:
            for extension in extensions:
                reference = extension.attributes.get("reference") or extension.attributes.get("name") or owner
                found[(extension.tag, reference, _extension_key(extension))] += 1
        return found

    a, b = all_extensions(old), all_extensions(new)
    for tag, reference, _key in sorted((a - b).elements()):
        yield Change("extension", reference, tag, "removed or changed", None)
    for tag, reference, _key in sorted((b - a).elements()):
        yield Change("extension", reference, tag, None, "added or changed")


_LINE_NUMBERS = re.compile(r"\(?\blines? \d+\)?")


def _finding_key(diagnostic: Diagnostic, links: Mapping[str, str]) -> tuple[str, str]:
    return diagnostic.code, _LINE_NUMBERS.sub("", diagnostic.message)


def _finding_changes(old: Sequence[Diagnostic], new: Sequence[Diagnostic],
                     links: Mapping[str, str]) -> Iterator[Change]:
    a = Counter(_finding_key(d, links) for d in old)
    b = Counter(_finding_key(d, links) for d in new)
    severity = {_finding_key(d, links): d.severity for d in [*old, *new]}
    appeared, gone = list((b - a).elements()), list((a - b).elements())
    # A finding reported once per file for the first element that shows it (a mesh used by two
    # links), or about a renamed link, moves to another name without anything changing: pair those.
    loose = Counter(_loose(k) for k in gone)
    kept_new = []
    for key in appeared:
        if loose[_loose(key)]:
            loose[_loose(key)] -= 1
            gone.remove(next(g for g in gone if _loose(g) == _loose(key)))
        else:
            kept_new.append(key)
    for key in sorted(kept_new):
        yield Change("finding-new", key[0], severity[key].value, None, key[1], severity=severity[key].value)
    for key in sorted(gone):
        yield Change("finding-gone", key[0], severity[key].value, key[1], None, severity=severity[key].value)


_NAMED = re.compile(r"\b(link|joint|links|joints) '[^']*'")


def _loose(key: tuple[str, str]) -> tuple[str, str]:
    return key[0], _NAMED.sub(r"\1 '…'", key[1])


def compare(old: Robot, new: Robot, old_findings: Sequence[Diagnostic] = (),
            new_findings: Sequence[Diagnostic] = ()) -> RobotDiff:
    """Every change from *old* to *new* (see the module docstring)."""
    links, joints = match(old, new)
    changes: list[Change] = []
    new_links = {lk.name: lk for lk in new.links}
    new_joints = {j.name: j for j in new.joints}
    matched_new_links = set(links.values())
    matched_new_joints = set(joints.values())
    for link in old.links:
        if link.name not in links:
            changes.append(Change("link-removed", link.name))
        elif links[link.name] != link.name:
            changes.append(Change("link-renamed", links[link.name], "name", link.name, links[link.name]))
    changes += [Change("link-added", lk.name) for lk in new.links if lk.name not in matched_new_links]
    for joint in old.joints:
        if joint.name not in joints:
            changes.append(Change("joint-removed", joint.name))
        elif joints[joint.name] != joint.name:
            renamed = joints[joint.name]
            changes.append(Change("joint-renamed", renamed, "name", joint.name, renamed))
    changes += [Change("joint-added", j.name) for j in new.joints if j.name not in matched_new_joints]
    for joint in old.joints:
        if joint.name in joints:
            changes += _joint_changes(joint, new_joints[joints[joint.name]], links, joints)
    old_tree, new_tree = KinematicTree.of(old), KinematicTree.of(new)
    old_poses, new_poses = old_tree.forward_kinematics(), new_tree.forward_kinematics()
    for link in old.links:
        if link.name in links:
            changes += _link_changes(link, new_links[links[link.name]], old_poses.get(link.name),
                                     new_poses.get(links[link.name]))
    mass_a, com_a = _totals(old, old_tree, old_poses)
    mass_b, com_b = _totals(new, new_tree, new_poses)
    if abs(mass_a - mass_b) > MASS_TOL:
        size = abs(mass_b - mass_a) / mass_a * 100.0 if mass_a else math.inf
        changes.append(Change("total-mass", new.name or "robot", "mass", mass_a, mass_b, size, "%"))
    if mass_a > 0 and mass_b > 0 and not _close(com_a, com_b, LENGTH_TOL):
        changes.append(Change("total-com", new.name or "robot", "com", _rounded(com_a), _rounded(com_b),
                              float(np.linalg.norm(com_b - com_a)) * 1000.0, "mm"))
    changes += _extension_changes(old, new)
    changes += _finding_changes(old_findings, new_findings, links)
    return RobotDiff(old.path, new.path, tuple(changes),
                     {k: v for k, v in links.items() if k != v}, {k: v for k, v in joints.items() if k != v})


# -- --fail-on -------------------------------------------------------------------------------

_THRESHOLD = re.compile(r"^(pose|rotation|mass|com|inertia)\s*>\s*([0-9.eE+-]+)\s*(mm|cm|m|deg|%|kg)?$")
_LENGTH_MM = {"mm": 1.0, "cm": 10.0, "m": 1000.0, None: 1.0}
_FLAGS = {"new-errors", "new-warnings", "new-findings", "structure", "any"}


class FailOnError(ValueError):
    """A ``--fail-on`` term that is not understood."""


def parse_fail_on(spec: str) -> list[tuple[str, float | None, str | None]]:
    """``pose>1mm,mass>1%,new-errors`` as (what, threshold, unit) terms."""
    terms: list[tuple[str, float | None, str | None]] = []
    for raw in (t.strip() for t in spec.split(",")):
        if not raw:
            continue
        if raw in _FLAGS:
            terms.append((raw, None, None))
            continue
        found = _THRESHOLD.match(raw)
        if found is None:
            raise FailOnError(f"--fail-on: cannot read '{raw}' (e.g. pose>1mm, rotation>0.5deg, mass>1%, "
                              "mass>0.1kg, com>2mm, new-errors, new-warnings, structure, any)")
        what, number, unit = found.group(1), float(found.group(2)), found.group(3)
        if what in ("pose", "com") and unit not in _LENGTH_MM:
            raise FailOnError(f"--fail-on: '{raw}': {what} takes mm, cm or m")
        if what == "rotation" and unit not in (None, "deg"):
            raise FailOnError(f"--fail-on: '{raw}': rotation takes deg")
        if what == "mass" and unit not in (None, "%", "kg"):
            raise FailOnError(f"--fail-on: '{raw}': mass takes % or kg")
        terms.append((what, number, unit))
    return terms


def tripped(diff: RobotDiff, terms: Sequence[tuple[str, float | None, str | None]]) -> list[str]:
    """The ``--fail-on`` terms that *diff* trips, as text."""
    out = []
    for what, limit, unit in terms:
        if what == "any" and not diff.empty:
            out.append("any")
        elif what == "structure" and diff.of_kind("link-added", "link-removed", "link-renamed", "joint-added",
                                                  "joint-removed", "joint-renamed"):
            out.append("structure")
        elif what.startswith("new-"):
            wanted = {"new-errors": {Severity.ERROR.value},
                      "new-warnings": {Severity.ERROR.value, Severity.WARNING.value}}.get(what)
            if any(wanted is None or c.severity in wanted for c in diff.of_kind("finding-new")):
                out.append(what)
        elif limit is not None and _exceeds(diff, what, limit, unit):
            out.append(f"{what}>{limit:g}{unit or ''}")
    return out


def _exceeds(diff: RobotDiff, what: str, limit: float, unit: str | None) -> bool:
    if what in ("pose", "com"):
        kinds = ("pose",) if what == "pose" else ("com", "total-com")
        mm = limit * _LENGTH_MM[unit]
        return any(c.size is not None and c.field != "orientation" and c.size > mm
                   for c in diff.of_kind(*kinds))
    if what == "rotation":
        return any(c.size is not None and c.size > limit
                   for c in diff.of_kind("pose") if c.field == "orientation")
    if what == "mass":
        changes = diff.of_kind("mass", "total-mass")
        if unit == "kg":
            return any(abs((c.new or 0.0) - (c.old or 0.0)) > limit for c in changes)
        return any(c.size is not None and c.size > limit for c in changes)
    if what == "inertia":
        return any(c.size is not None and c.size > limit for c in diff.of_kind("inertia"))
    return False


# -- files -----------------------------------------------------------------------------------


class DiffError(ValueError):
    """A side of the comparison that cannot be read into a robot; carries the reader's findings."""

    def __init__(self, message: str, diagnostics: Sequence[Diagnostic] = ()):
        super().__init__(message)
        self.diagnostics = tuple(diagnostics)


def _side(path: str, options: CheckOptions, model: str | None,
          findings: bool) -> tuple[Robot, list[Diagnostic]]:
    loaded = load_one(path, options, model)
    if loaded.robot is None:
        errors = [d for d in loaded.diagnostics if d.severity is Severity.ERROR]
        raise DiffError(f"{path}: cannot be read as a robot"
                        + (f": {errors[0].message}" if errors else ""), loaded.diagnostics)
    if not findings:
        return loaded.robot, []
    rule_options = {**options.rule_options, "resolver": options.resolver()}
    return loaded.robot, list(report_for(loaded, options.selection(), rule_options).diagnostics)


def diff_files(old: str, new: str, options: CheckOptions | None = None, model: str | None = None,
               findings: bool = True) -> RobotDiff:
    """Compare the robots in two files, both read with the same *options* (xacro arguments,
    packages, rule selection). Raises :class:`DiffError`, :class:`~urdftool.parse.InputError`."""
    options = options or CheckOptions()
    old_robot, old_findings = _side(old, options, model, findings)
    new_robot, new_findings = _side(new, options, model, findings)
    result = compare(old_robot, new_robot, old_findings, new_findings)
    return RobotDiff(old, new, result.changes, result.link_renames, result.joint_renames)


@contextlib.contextmanager
def revision(rev: str, path: str) -> Iterator[str]:
    """*path* as it was at git revision *rev*, in a temporary file beside it (so that relative
    includes and ``$(find)`` resolve as they do for the working copy; included files are read
    from the working tree). Raises :class:`DiffError` when git cannot show it."""
    folder, name = os.path.split(os.path.abspath(path))
    try:
        shown = subprocess.run(["git", "-C", folder, "show", f"{rev}:./{name}"], capture_output=True,
                               check=False, timeout=60)
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise DiffError(f"git show {rev}:{path}: {exc}") from exc
    if shown.returncode != 0:
        raise DiffError(f"git show {rev}:{path}: {shown.stderr.decode('utf-8', 'replace').strip()}")
    suffix = ".urdf.xacro" if name.endswith(".urdf.xacro") else os.path.splitext(name)[1]
    fd, tmp = tempfile.mkstemp(prefix=f".{name}.", suffix=suffix, dir=folder)
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(shown.stdout)
        yield tmp
    finally:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
