"""Reading a ros2_control controllers YAML (the controller manager's parameter file) with positions.

The file is a ROS 2 parameter file: each node's parameters sit under
``NODE: ros__parameters:``. A controller is a node whose ``type`` names its
plugin, written in either of two layouts, often both in one file. The
controller manager's node may list it with its type (the original layout)::

    controller_manager:
      ros__parameters:
        update_rate: 100
        arm_controller:
          type: joint_trajectory_controller/JointTrajectoryController
    arm_controller:
      ros__parameters:
        joints: [joint1, joint2]

or the controller's own parameters may hold it (ros2_control PR 1502, the
layout ros2_control_demos and gz_ros2_control's demos use since 2024: the
spawner, given the file with ``--param-file``, reads the type there)::

    arm_controller:
      ros__parameters:
        type: joint_trajectory_controller/JointTrajectoryController
        joints: [joint1, joint2]

It is read with PyYAML's safe loader; every value keeps the line and column
where it was written (:class:`Value`), so the rules in
:mod:`urdftool.rules.controllers` locate their findings in the YAML. Node
names are matched as rcl matches them: a key may carry a namespace
(``/robot/arm_controller``), nested keys are namespaces
(``robot: {arm_controller: {ros__parameters: …}}``), ``*`` stands for part of
one name and ``/**`` for any number of namespaces (``/**/controller_manager``,
``/**: ros__parameters:`` for every node). Reading never raises on content: a
YAML error becomes a ``controllers-yaml-invalid`` finding at its line.
"""

from __future__ import annotations

import functools
import re
from dataclasses import field
from typing import TYPE_CHECKING, Any, NamedTuple

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
    #: the type the controller is loaded with: its own parameters' ``type``, else the manager's
    type: Value | None = None
    #: the controller node's ``ros__parameters`` (empty when the file gives none), merged over
    #: every key that reaches it (wildcard keys first, so that the exact key wins)
    params: dict[str, Value] = field(default_factory=dict)
    #: the ``type`` the controller manager's parameters list it with (``None``: not listed there)
    listed_type: Value | None = None
    #: the namespace the file places it in (``/rrbot_1``, ``/**``; ``""`` for the root)
    namespace: str = ""

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


#: The node holding the controller manager's own parameters.
MANAGER = "controller_manager"
#: A pluginlib lookup name (``package/Class``) or C++ class (``ns::Class``): what a controller's
#: ``type`` holds. Other nodes of a shared parameter file may have a ``type`` of their own
#: (crazyswarm2's ``motion_capture_tracking`` has ``type: optitrack``); they are no controllers.
PLUGIN_NAME = re.compile(r"[\w${}.-]+(?:/|::)[\w${}.:/-]+")


class _Node(NamedTuple):
    """One ``NAME: ros__parameters:`` entry of the file, with its full name as tokens."""

    path: tuple[str, ...]
    params: dict[str, Value]
    span: Span


def _tokens(key: str) -> tuple[str, ...]:
    return tuple(token for token in key.split("/") if token)


def _wild(tokens: tuple[str, ...]) -> bool:
    return any("*" in token for token in tokens)


@functools.cache
def _pattern(tokens: tuple[str, ...]) -> re.Pattern[str]:
    """The node names a key of the file matches, as rcl reads it: ``*`` stands for any part of
    one name, ``/**`` for any number of namespaces (none included)."""
    parts = [
        "(?:/[^/]+)*" if token == "**" else "/" + re.escape(token).replace(r"\*", "[^/]*")
        for token in tokens
    ]
    return re.compile("".join(parts))


def _applies(node: tuple[str, ...], namespace: tuple[str, ...], name: str) -> bool:
    """Whether the parameters of the file's *node* key reach the controller *namespace*/*name*."""
    if _wild(namespace):
        # listed by a manager under a wildcard (`/**/controller_manager`), the controller runs in
        # the namespace the manager is started in: any namespace's parameters may be meant
        return node[-1] == "**" or _pattern(node[-1:]).fullmatch("/" + name) is not None
    return _pattern(node).fullmatch("/" + "/".join((*namespace, name))) is not None


def _nodes(document: dict[str, Value]) -> list[_Node]:
    """Every node of the file; a key whose value holds no ``ros__parameters`` is a namespace."""
    out: list[_Node] = []

    def walk(mapping: dict[str, Value], prefix: tuple[str, ...]) -> None:
        for key, node in mapping.items():
            if not isinstance(node.value, dict):
                continue
            path = (*prefix, *_tokens(key))
            params = node.get("ros__parameters")
            if params is None:
                walk(node.value, path)
            elif isinstance(params.value, dict) and path:
                out.append(_Node(path, params.value, node.span))

    walk(document, ())
    return out


def _is_plugin(value: Value | None) -> bool:
    text = value.text() if value is not None else None
    return text is not None and PLUGIN_NAME.fullmatch(text) is not None


def _identities(nodes: list[_Node]) -> dict[tuple[tuple[str, ...], str], Span]:
    """(namespace, name) of every controller the file declares, in either layout, with where.

    A controller listed under a wildcard manager (`/**/controller_manager`) whose parameters the
    file gives in concrete namespaces (`/rrbot_1/arm`, `/rrbot_2/arm`) is one controller per
    namespace: each robot's controller manager loads its own.
    """
    found: dict[tuple[tuple[str, ...], str], Span] = {}
    for node in nodes:
        if node.path[-1] == MANAGER:
            for name, entry in node.params.items():
                if entry.get("type") is not None:
                    found.setdefault((node.path[:-1], name), entry.span)
        elif not _wild(node.path[-1:]) and _is_plugin(node.params.get("type")):
            found.setdefault((node.path[:-1], node.path[-1]), node.span)
    out: dict[tuple[tuple[str, ...], str], Span] = {}
    for (namespace, name), span in found.items():
        concrete = [
            n.path[:-1] for n in nodes
            if n.path[-1] == name and not _wild(n.path) and _wild(namespace) and _applies(
                (*namespace, name), n.path[:-1], name)
        ]
        for each in concrete or [namespace]:
            out.setdefault((each, name), span)
    return out


def _controller(
    nodes: list[_Node], namespace: tuple[str, ...], name: str, span: Span
) -> Controller:
    """The controller *namespace*/*name* with the parameters and types every key gives it."""
    reaching = [n for n in nodes if n.path[-1] != MANAGER and _applies(n.path, namespace, name)]
    params: dict[str, Value] = {}
    for node in sorted(reaching, key=lambda n: not _wild(n.path)):  # exact keys win: last
        params.update(node.params)
    listed: Value | None = None
    for node in nodes:
        if node.path[-1] == MANAGER and _applies((*node.path[:-1], name), namespace, name):
            entry = node.params.get(name)
            listed = (entry.get("type") if entry is not None else None) or listed
    own = params.get("type")
    return Controller(
        name, span, own if own is not None else listed, params, listed, "/" + "/".join(namespace)
        if namespace else ""
    )


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
    nodes = _nodes(document.value)
    for (namespace, name), span in _identities(nodes).items():
        config.controllers.append(_controller(nodes, namespace, name, span))
    return config


@record(frozen=False)
class Controllers:
    """The controllers YAML files of a model, and the parameter files that did not resolve."""

    configs: list[ControllerConfig] = field(default_factory=list)
    #: ``(text written, where, places looked)`` of each ``<parameters>`` that names no readable file
    missing: list[tuple[str, Span | None, tuple[str, ...]]] = field(default_factory=list)
    #: the file came from ``--controllers`` (not from a plugin of the model)
    given: bool = False
