"""The frame graph of one SDF model: every named frame, where it is, and what it moves with.

An SDF model names frames: the model frame ``__model__``, each link, each
joint, each ``<frame>`` and each nested model (``nested::__model__``, reached
also as ``nested``). Every frame has a pose written relative to another frame
(``relative_to``, or the version's default) and moves with one link (its
attachment). This module resolves all of them into the top model's frame and
reports unknown names (``unknown-frame-reference``) and cycles (``frame-cycle``)
at the attribute that causes them.
"""

from __future__ import annotations

from dataclasses import field

import numpy as np

from urdftool.catalogue.sdf import FrameCycle, UnknownFrameReference
from urdftool.catalogue.suggest import did_you_mean
from urdftool.diagnostics import Diagnostic
from urdftool.model import Pose
from urdftool.model.pose import Matrix
from urdftool.records import record
from urdftool.source import Span

MODEL_FRAME = "__model__"
WORLD_FRAME = "world"


@record(frozen=False)
class FrameNode:
    """One named frame: its pose as written, relative to ``relative_to`` (a scoped name)."""

    name: str
    kind: str  # "model" | "link" | "joint" | "frame"
    pose: Pose
    relative_to: str
    #: the frame this one moves with, before resolution (a link's is itself)
    attached_to: str
    #: where a bad ``relative_to``/``attached_to`` is reported
    span: Span | None = None
    attached_span: Span | None = None


@record(frozen=False)
class FrameGraph:
    """All frames of one model, by scoped name (``nested::link``)."""

    nodes: dict[str, FrameNode] = field(default_factory=dict)
    #: scoped alias -> scoped name (``nested`` -> ``nested::__model__``)
    aliases: dict[str, str] = field(default_factory=dict)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    _poses: dict[str, Matrix] = field(default_factory=dict)
    _links: dict[str, str | None] = field(default_factory=dict)
    _reported: set[str] = field(default_factory=set)

    def add(self, node: FrameNode) -> None:
        self.nodes.setdefault(node.name, node)

    def canonical(self, name: str) -> str:
        return self.aliases.get(name, name)

    def known(self, name: str) -> bool:
        name = self.canonical(name)
        return name in self.nodes or name == WORLD_FRAME

    def check_reference(self, name: str, span: Span | None, where: str) -> bool:
        """True when *name* is a frame; otherwise report it once and return False."""
        if self.known(name):
            return True
        key = f"{where}:{name}"
        if key not in self._reported:
            self._reported.add(key)
            self.diagnostics.append(
                UnknownFrameReference.diagnostic(
                    f"{where}: there is no frame '{name}' in this model"
                    + did_you_mean(name, [n for n in self.nodes if not n.endswith(MODEL_FRAME)]),
                    span,
                    element=where,
                    data={"frame": name},
                )
            )
        return False

    # -- poses -------------------------------------------------------------------

    def pose_in_model(self, name: str) -> Matrix:
        """The 4×4 pose of frame *name* in the top model frame (identity where unknowable)."""
        return self._resolve(self.canonical(name), [])

    def _resolve(self, name: str, chain: list[str]) -> Matrix:
        if name in self._poses:
            return self._poses[name]
        node = self.nodes.get(name)
        if node is None or name == MODEL_FRAME:
            return np.eye(4)
        if name in chain:
            self._report_cycle(chain[chain.index(name):], "relative_to")
            return np.eye(4)
        target = self.canonical(node.relative_to)
        if target == WORLD_FRAME or not self.check_reference(
            node.relative_to, node.span, f"{node.kind}[{name}]/pose"
        ):
            base = np.eye(4)
        else:
            base = self._resolve(target, [*chain, name])
        pose = base @ node.pose.matrix
        self._poses[name] = pose
        return pose

    # -- attachment --------------------------------------------------------------

    def link_of(self, name: str) -> str | None:
        """The link that frame *name* moves with, or ``None`` (unknown, cycle, or the world)."""
        return self._attach(self.canonical(name), [])

    def _attach(self, name: str, chain: list[str]) -> str | None:
        if name in self._links:
            return self._links[name]
        node = self.nodes.get(name)
        if node is None:
            return None
        if node.kind == "link":
            return name
        if name in chain:
            self._report_cycle(chain[chain.index(name):], "attached_to")
            return None
        target = self.canonical(node.attached_to)
        if target == WORLD_FRAME:
            found: str | None = None
        elif not self.check_reference(node.attached_to, node.attached_span, f"{node.kind}[{name}]"):
            found = None
        else:
            found = self._attach(target, [*chain, name])
        self._links[name] = found
        return found

    def _report_cycle(self, cycle: list[str], via: str) -> None:
        key = "cycle:" + ",".join(sorted(cycle))
        if key in self._reported:
            return
        self._reported.add(key)
        first = self.nodes[cycle[0]]
        loop = " → ".join(f"'{n}'" for n in [*cycle, cycle[0]])
        self.diagnostics.append(
            FrameCycle.diagnostic(
                f"frames refer to each other through {via} in a cycle: {loop}",
                first.span if via == "relative_to" else (first.attached_span or first.span),
                element=f"{first.kind}[{first.name}]",
                help="express one of these poses relative to a link or to __model__",
                data={"cycle": cycle, "via": via},
            )
        )
