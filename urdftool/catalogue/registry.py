"""The rule catalogue: one table of codes, names, families, severities and docs.

This layer sits below the readers and exporters, which create findings of the
rules defined here; the checks that run on a loaded robot live in
:mod:`urdftool.rules` and register into the same table.

A rule is a subclass of :class:`Rule` registered with :func:`register`. Its
docstring is its documentation and must have the sections ``What it does``,
``Why it matters``, ``Example`` and ``Fix`` (checked by the test suite, and
rendered to ``docs/rules/`` by ``python -m urdftool.rules.docs``).

Two kinds of rule share the catalogue:

* *reader* rules are reported while a file is read (syntax, numbers, unknown
  elements); the reader creates their diagnostics with :meth:`Rule.diagnostic`;
* *model* rules override :meth:`Rule.check` and run on a loaded robot.
"""

from __future__ import annotations

import enum
import re
from collections.abc import Iterable, Mapping
from typing import Any, ClassVar, Protocol

from urdftool.diagnostics import Diagnostic, Severity
from urdftool.model import KinematicTree, Robot
from urdftool.source import Span


class Family(enum.Enum):
    """Rule families, by code letter."""

    SYNTAX = ("S", "syntax and structure")
    JOINTS = ("J", "joints")
    INERTIA = ("I", "inertia")
    MESHES = ("M", "meshes and geometry")
    GAZEBO = ("G", "Gazebo and ROS extensions")
    LOOPS = ("L", "closed chains")
    XACRO = ("X", "xacro")
    DYNAMICS = ("D", "dynamics")
    RUNTIME = ("R", "runtime")
    CONVERSION = ("C", "conversion")
    SRDF = ("P", "MoveIt SRDF (planning groups, states, collision matrix)")
    INTENT = ("N", "intent: units, conventions, symmetry, self-consistency")
    TARGETS = ("T", "consumers (check --target)")

    @property
    def letter(self) -> str:
        return self.value[0]

    @property
    def title(self) -> str:
        return self.value[1]


CODE_PATTERN = re.compile(r"^[A-Z]{1,2}[0-9]{3}$")
NAME_PATTERN = re.compile(r"^[a-z][a-z0-9]*(-[a-z0-9]+)*$")
DOC_SECTIONS = ("What it does", "Why it matters", "Example", "Fix")


class ModelView(Protocol):
    """What a model check defined in the catalogue may read: the robot and its kinematic tree."""

    @property
    def robot(self) -> Robot: ...

    @property
    def tree(self) -> KinematicTree: ...


class Rule:
    """Base of every rule; subclasses set the class attributes and a docstring."""

    code: ClassVar[str]
    name: ClassVar[str]
    family: ClassVar[Family]
    severity: ClassVar[Severity]
    #: urdftool version the rule arrived in
    since: ClassVar[str] = "0.1.0"
    #: "reader" rules are emitted while reading a file; "model" rules run on a robot
    kind: ClassVar[str] = "reader"
    #: ``False`` for rules that enforce an optional convention: they run only when
    #: selected by their exact code or name (``--select N103``, ``extend-select``)
    default_enabled: ClassVar[bool] = True

    def check(self, ctx: Any) -> Iterable[Diagnostic]:
        """Yield this rule's findings on ``ctx.robot`` (model rules override this)."""
        return ()

    @classmethod
    def diagnostic(
        cls,
        message: str,
        location: Span | None = None,
        *,
        element: str | None = None,
        help: str | None = None,
        data: Mapping[str, Any] | None = None,
        severity: Severity | None = None,
    ) -> Diagnostic:
        """A finding of this rule (at its default severity unless *severity* is given)."""
        return Diagnostic(
            code=cls.code,
            name=cls.name,
            severity=severity or cls.severity,
            message=message,
            location=location,
            element=element,
            help=help,
            data=dict(data or {}),
        )

    @classmethod
    def summary(cls) -> str:
        """The first line of the docstring."""
        return (cls.__doc__ or "").strip().splitlines()[0] if cls.__doc__ else ""

    @classmethod
    def sections(cls) -> dict[str, str]:
        """The docstring's ``## Section`` blocks, by title."""
        return doc_sections(cls.__doc__ or "")


def doc_sections(doc: str) -> dict[str, str]:
    lines = _dedent(doc).splitlines()
    out: dict[str, str] = {}
    current: str | None = None
    buffer: list[str] = []
    for line in lines:
        if line.startswith("## "):
            if current is not None:
                out[current] = "\n".join(buffer).strip()
            current, buffer = line[3:].strip(), []
        elif current is not None:
            buffer.append(line)
    if current is not None:
        out[current] = "\n".join(buffer).strip()
    return out


def _dedent(doc: str) -> str:
    import inspect

    return inspect.cleandoc(doc)


#: code -> rule class, in registration order
REGISTRY: dict[str, type[Rule]] = {}
#: retired code or name -> current code, so old configurations keep working
REDIRECTS: dict[str, str] = {}


def register(rule: type[Rule]) -> type[Rule]:
    """Class decorator that adds *rule* to the catalogue, checking code and name."""
    if not CODE_PATTERN.match(rule.code):
        raise ValueError(f"rule code {rule.code!r} does not match {CODE_PATTERN.pattern}")
    if not NAME_PATTERN.match(rule.name):
        raise ValueError(f"rule name {rule.name!r} is not kebab-case")
    if not rule.code.startswith(rule.family.letter):
        raise ValueError(f"rule {rule.code} is not in family {rule.family.letter}")
    if rule.code in REGISTRY:
        raise ValueError(f"rule code {rule.code} registered twice")
    if any(r.name == rule.name for r in REGISTRY.values()):
        raise ValueError(f"rule name {rule.name} registered twice")
    if rule.check is not Rule.check:
        rule.kind = "model"
    REGISTRY[rule.code] = rule
    return rule
