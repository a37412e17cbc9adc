"""Reading a ros2_control controllers YAML (the controller manager's parameter file) with positions.

The file is a ROS 2 parameter file: each node's parameters sit under
``NODE: ros__parameters:``. The controller manager's node lists the
controllers by name with their ``type``; each controller's own node holds its
parameters (``joints``, ``command_interfaces``, ``wheel_separation``, …)::

    controller_manager:
      ros__parameters:
        update_rate: 100
        arm_controller:
          type: joint_trajectory_controller/JointTrajectoryController
    arm_controller:
      ros__parameters:
        joints: [joint1, joint2]

It is read with PyYAML's safe loader; every value keeps the line and column
where it was written (:class:`Value`), so the rules in
:mod:`urdftool.rules.controllers` locate their findings in the YAML. Node names
may carry a namespace (``/robot/arm_controller``, ``/**/controller_manager``):
the last path element is the name. Reading never raises on content: a YAML
error becomes a ``controllers-yaml-invalid`` finding at its line.
"""

from __future__ import annotations

import functools
from dataclasses import field
from typing import TYPE_CHECKING, Any

from urdftool.catalogue.ros2_control import ControllersYamlInvalid
from urdftool.diagnostics import Diagnostic
from urdftool.records import record
from urdftool.safe_files import read_regular
from urdftool.source import Span

if TYPE_CHECKING:
    import yaml  # type: ignore[import-untyped]  # no stubs in the runtime environment
else:  # PyYAML costs more to import than a structural check: only a controllers file loads it
    from urdftool.lazy import yaml


@record
class Value:
    """A YAML value and where it was written.

    ``value`` is a plain scalar (str, int, float, bool, None), a list of
    :class:`Value` or a dict of str to :class:`Value`.
    """

    value: Any
    span: Span

    def text(self) -> str | None:
        """The scalar as text, or ``None`` for a list, a mapping or null."""
        if self.value is None or isinstance(self.value, (list, dict)):
            return None
        return str(self.value)

    def items(self) -> list[Value]:
        """A list's items; a single scalar is a list of one (ROS parameters accept neither, but
        the controller would read nothing)."""
        if isinstance(self.value, list):
            return list(self.value)
        return [self] if self.text() is not None else []

    def number(self) -> float | None:
        if isinstance(self.value, bool) or not isinstance(self.value, (int, float)):
            return None
        return float(self.value)

    def get(self, key: str) -> Value | None:
        return self.value.get(key) if isinstance(self.value, dict) else None


@record
class Controller:
    """One controller: its name, its declared ``type`` and its own parameters."""

    name: str
    span: Span
    type: Value | None = None
    #: the controller node's ``ros__parameters`` (empty when the file gives none)
    params: dict[str, Value] = field(default_factory=dict)

    def param(self, key: str) -> Value | None:
        return self.params.get(key)


@record(frozen=False)
class ControllerConfig:
    """A controllers YAML as read: the controllers it declares and the reader's findings."""

    path: str
    controllers: list[Controller] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)

    def controller(self, name: str) -> Controller | None:
        return next((c for c in self.controllers if c.name == name), None)


@functools.cache
def _located_loader() -> Any:
    """PyYAML's safe loader building :class:`Value` trees (a class made on first use, as PyYAML is
    imported then)."""

    class LocatedLoader(yaml.SafeLoader):  # type: ignore[misc]
        """PyYAML's safe loader building :class:`Value` trees that record each node's start mark."""

        path = ""

        def located(self, node: yaml.Node) -> Value:
            span = Span(self.path, node.start_mark.line + 1, node.start_mark.column + 1)
            if isinstance(node, yaml.MappingNode):
                self.flatten_mapping(node)  # YAML merge keys (<<: *defaults)
                out: dict[str, Value] = {}
                for key_node, value_node in node.value:
                    key = self.construct_object(key_node, deep=True)
                    out[str(key)] = self.located(value_node)
                return Value(out, span)
            if isinstance(node, yaml.SequenceNode):
                return Value([self.located(item) for item in node.value], span)
            return Value(self.construct_object(node, deep=True), span)

    return LocatedLoader


def load_located(text: str, path: str) -> Value | None:
    """The document in *text* as a :class:`Value` tree (``None`` for an empty document)."""
    loader = _located_loader()(text)
    loader.path = path
    try:
        node = loader.get_single_node()
        return loader.located(node) if node is not None else None
    finally:
        loader.dispose()


def _node_name(key: str) -> str:
    return key.rstrip("/").rsplit("/", 1)[-1]


def read_controllers(path: str) -> ControllerConfig:
    """Read the controllers YAML at *path* (raises :class:`OSError` when it cannot be read)."""
    config = ControllerConfig(path)
    raw = read_regular(path, "include")
    try:
        document = load_located(raw.decode("utf-8", errors="replace"), path)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
        span = Span(path, mark.line + 1, mark.column + 1) if mark is not None else Span(path)
        problem = getattr(exc, "problem", None) or str(exc)
        config.diagnostics.append(
            ControllersYamlInvalid.diagnostic(f"the controllers YAML does not parse: {problem}", span)
        )
        return config
    if document is None or not isinstance(document.value, dict):
        config.diagnostics.append(
            ControllersYamlInvalid.diagnostic(
                "the controllers YAML is not a mapping of node names to parameters",
                document.span if document else Span(path),
            )
        )
        return config
    nodes: dict[str, dict[str, Value]] = {}
    for key, node in document.value.items():
        params = node.get("ros__parameters")
        if params is not None and isinstance(params.value, dict):
            nodes.setdefault(_node_name(key), {}).update(params.value)
    manager = nodes.get("controller_manager", {})
    for name, entry in manager.items():
        declared = entry.get("type")
        if declared is None:
            continue  # update_rate and the manager's other parameters
        config.controllers.append(Controller(name, entry.span, declared, nodes.get(name, {})))
    return config


@record(frozen=False)
class Controllers:
    """The controllers YAML files of a model, and the parameter files that did not resolve."""

    configs: list[ControllerConfig] = field(default_factory=list)
    #: ``(text written, where, places looked)`` of each ``<parameters>`` that names no readable file
    missing: list[tuple[str, Span | None, tuple[str, ...]]] = field(default_factory=list)
    #: the file came from ``--controllers`` (not from a plugin of the model)
    given: bool = False
