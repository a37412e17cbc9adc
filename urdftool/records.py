"""Records: urdftool's dataclasses, with their methods compiled ahead of time.

``@record`` makes a class a frozen dataclass, as ``@dataclass(frozen=True)`` does: typed
fields, ``dataclasses.fields``/``replace``/``asdict``, value equality and hashing over the
fields that take part in comparison (``field(compare=False)`` leaves spans out), assignment
refused with :class:`dataclasses.FrozenInstanceError`, and ``order=True`` for sorting.
``@record(frozen=False, eq=False)`` is one run's mutable state, equal only to itself.

Why not ``@dataclass`` itself: on Python 3.10–3.12 the standard decorator writes each
class's methods as source text and compiles them one by one every time the module is
imported, 0.5–1 ms a class; the ~70 records a ``check`` imports cost more than reading a
small file (docs/scale.md, "Fourth pass"). Here:

- ``__init__`` is the same code ``dataclasses`` would write (fields set with
  ``object.__setattr__``, defaults, ``default_factory``, ``init=False``, ``__post_init__``),
  but it is written once into the generated package :mod:`urdftool.records_compiled` (one
  module per package of urdftool, read with the first record of that package), so Python's
  bytecode cache keeps it. ``python -m urdftool.records_generate`` rewrites that
  module; ``tests/test_records.py`` fails when it is out of date. A class whose shape is not
  in it (a record added or changed without regenerating) gets its ``__init__`` compiled at
  import, as ``dataclasses`` would: slower, never wrong.
- ``__eq__``, ``__hash__``, ``__repr__``, ordering and the frozen ``__setattr__`` are
  shared functions that read the class's field list, so nothing is compiled per class.
"""

from __future__ import annotations

import dataclasses
import functools
import importlib
import inspect
import operator
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypeVar, overload

if TYPE_CHECKING:
    from typing_extensions import dataclass_transform
else:  # the marker only informs type checkers; typing_extensions is slow to import

    def dataclass_transform(**_: Any) -> Callable[[Any], Any]:
        return lambda decorator: decorator


T = TypeVar("T", bound=type)

_MISSING = dataclasses.MISSING


class _DefaultFactory:
    """Marks an argument left to its ``default_factory`` (as dataclasses' own sentinel)."""

    def __repr__(self) -> str:
        return "<factory>"


DEFAULT_FACTORY = _DefaultFactory()

#: every record class, in definition order (what ``python -m urdftool.records_generate`` compiles)
REGISTERED: list[type] = []
#: records whose ``__init__`` was compiled at import because the generated module lacks them
FALLBACKS: list[str] = []


def qualified_name(cls: type) -> str:
    return f"{cls.__module__}.{cls.__qualname__}"


def init_shape(cls: type) -> str:
    """What the generated ``__init__`` depends on: field names in order, each marked ``=``
    (has a default), ``*`` (has a default factory) and ``!`` (not an argument), and
    ``|post_init``."""
    parts = []
    for f in dataclasses.fields(cls):
        if f.kw_only:
            raise TypeError(f"{qualified_name(cls)}.{f.name}: records take their fields positionally")
        mark = "*" if f.default_factory is not _MISSING else "=" if f.default is not _MISSING else ""
        parts.append(f.name + mark + ("" if f.init else "!"))
    return ",".join(parts) + ("|post_init" if hasattr(cls, "__post_init__") else "") + f"|{_storage(cls)}"


def _storage(cls: type) -> str:
    """How the ``__init__`` stores a field: ``slots`` (through the slot's own descriptor, half the
    cost of ``object.__setattr__``), ``frozen`` (``object.__setattr__``, past the frozen
    ``__setattr__``) or ``plain`` (an assignment, as dataclasses writes for a mutable class)."""
    if "__slots__" in cls.__dict__:
        return "slots"
    return "frozen" if cls.__dict__.get("__record_frozen__") else "plain"


def init_source(cls: type, function_name: str = "make_init") -> str:
    """Source of a function that returns *cls*'s ``__init__``, as ``dataclasses`` writes it.

    The outer function takes the class's defaults and factories by field name, the
    factory sentinel, ``object.__setattr__`` and a function that gives a slot's setter
    (see :func:`_storage`); defaults and setters are bound when it runs, at import.
    A field with ``init=False`` is set from its default or factory, if it has one.
    """
    storage = _storage(cls)
    arguments, body, setters = ["self"], [], []

    def store(name: str, value: str) -> str:
        if storage == "slots":
            setters.append(name)
            return f"_set_{name}(self, {value})"
        if storage == "frozen":
            return f"__set__(self, {name!r}, {value})"
        return f"self.{name} = {value}"

    for f in dataclasses.fields(cls):
        name = f.name
        if not f.init:
            if f.default_factory is not _MISSING:
                body.append(store(name, f"__factories__[{name!r}]()"))
            elif f.default is not _MISSING:
                body.append(store(name, f"__defaults__[{name!r}]"))
            continue
        if f.default_factory is not _MISSING:
            arguments.append(f"{name}=__sentinel__")
            body.append(store(name, f"__factories__[{name!r}]() if {name} is __sentinel__ else {name}"))
        elif f.default is not _MISSING:
            arguments.append(f"{name}=__defaults__[{name!r}]")
            body.append(store(name, name))
        else:
            arguments.append(name)
            body.append(store(name, name))
    if hasattr(cls, "__post_init__"):
        body.append("self.__post_init__()")
    # every slot's setter bound in one line: a record of ten fields is not ten lines longer
    bound = ([f"    ({', '.join(f'_set_{n}' for n in setters)},) = map(__slot__, {tuple(setters)!r})"]
             if setters else [])
    lines = [f"def {function_name}(__defaults__, __factories__, __sentinel__, __set__, __slot__):",
             *bound,
             f"    def __init__({', '.join(arguments)}):",
             *(f"        {line}" for line in body or ["pass"]),
             "    return __init__"]
    return "\n".join(lines) + "\n"


def package_of(module: str) -> str:
    """The package of urdftool that *module* belongs to (``urdftool.model.robot`` -> ``model``,
    ``urdftool.source`` -> ``source``); ``""`` outside urdftool."""
    return module.split(".")[1] if module.startswith("urdftool.") else ""


def compiled_module(module: str) -> str:
    """The module of :mod:`urdftool.records_compiled` for records defined in *module*: its
    package's, unless the generator gave the module's family one of its own
    (``records_compiled.MODULES``, for a package too large for one module)."""
    return _split_modules().get(module) or package_of(module)


@functools.cache
def _split_modules() -> dict[str, str]:
    """``records_compiled.MODULES``: record module -> generated module, where a package is split."""
    try:
        package = importlib.import_module("urdftool.records_compiled")
    except ModuleNotFoundError:  # not generated yet
        return {}
    split: dict[str, str] = getattr(package, "MODULES", {})
    return split


@functools.cache
def _compiled(package: str) -> dict[str, tuple[str, Callable[..., Callable[..., None]]]]:
    """The generated entries for the records of *package*, read with its first record."""
    try:
        module = importlib.import_module(f"urdftool.records_compiled.{package}")
    except (ModuleNotFoundError, ValueError):  # not generated yet, or a record outside urdftool
        return {}
    entries: dict[str, tuple[str, Callable[..., Callable[..., None]]]] = module.COMPILED
    return entries


def _make_init(cls: type) -> Callable[..., None]:
    fields = dataclasses.fields(cls)
    defaults = {f.name: f.default for f in fields if f.default is not _MISSING}
    factories = {f.name: f.default_factory for f in fields if f.default_factory is not _MISSING}
    compiled = _compiled(compiled_module(cls.__module__)).get(qualified_name(cls))
    make_init: Callable[..., Callable[..., None]]
    if compiled is not None and compiled[0] == init_shape(cls):
        make_init = compiled[1]
    else:  # not generated yet: compile it now, as dataclasses does for every class
        FALLBACKS.append(qualified_name(cls))
        namespace: dict[str, Any] = {}
        exec(init_source(cls), {}, namespace)
        make_init = namespace["make_init"]
    init: Callable[..., None] = make_init(defaults, factories, DEFAULT_FACTORY, object.__setattr__,
                                          functools.partial(_slot_setter, cls))
    init.__qualname__ = f"{cls.__qualname__}.__init__"
    return init


def _slot_setter(cls: type, name: str) -> Callable[[Any, Any], None]:
    """The ``__set__`` of *cls*'s slot *name* (defined on *cls* or a base)."""
    for klass in cls.__mro__:
        if name in klass.__dict__:
            setter: Callable[[Any, Any], None] = klass.__dict__[name].__set__
            return setter
    raise AttributeError(f"{qualified_name(cls)} has no slot {name!r}")


def _compared(cls: type) -> Callable[[Any], tuple[Any, ...]]:
    """The key equality, hashing and ordering read: the compared fields, as a tuple."""
    names = [f.name for f in dataclasses.fields(cls) if f.compare]
    if len(names) == 1:
        name = names[0]
        return lambda record: (getattr(record, name),)
    if not names:
        return lambda record: ()
    return operator.attrgetter(*names)


def _eq(self: Any, other: Any) -> Any:
    if other.__class__ is self.__class__:
        key = self.__class__.__record_key__
        return key(self) == key(other)
    return NotImplemented


def _hash(self: Any) -> int:
    return hash(self.__class__.__record_key__(self))


def _repr(self: Any) -> str:
    shown = ", ".join(f"{f.name}={getattr(self, f.name)!r}" for f in dataclasses.fields(self) if f.repr)
    return f"{self.__class__.__qualname__}({shown})"


def _frozen_setattr(self: Any, name: str, value: Any) -> None:
    raise dataclasses.FrozenInstanceError(f"cannot assign to field {name!r}")


def _frozen_delattr(self: Any, name: str) -> None:
    raise dataclasses.FrozenInstanceError(f"cannot delete field {name!r}")


def _ordering(compare: Callable[[Any, Any], bool]) -> Callable[[Any, Any], Any]:
    def method(self: Any, other: Any) -> Any:
        if other.__class__ is self.__class__:
            key = self.__class__.__record_key__
            return compare(key(self), key(other))
        return NotImplemented

    return method


_ORDER = {"__lt__": _ordering(operator.lt), "__le__": _ordering(operator.le),
          "__gt__": _ordering(operator.gt), "__ge__": _ordering(operator.ge)}


def _needs_dict(cls: type) -> bool:
    """Whether instances keep a ``__dict__``: for a ``cached_property`` of the class or a base."""
    return any(isinstance(value, functools.cached_property)
               for klass in cls.__mro__ for value in vars(klass).values())


def _getstate(self: Any) -> list[Any]:
    return [getattr(self, f.name) for f in dataclasses.fields(self)]


def _setstate(self: Any, state: list[Any]) -> None:
    for f, value in zip(dataclasses.fields(self), state, strict=True):
        object.__setattr__(self, f.name, value)


def _with_slots(cls: T) -> T:
    """*cls* rebuilt with ``__slots__`` for its fields, as ``dataclass(slots=True)`` does: a
    frozen record holds its fields in slots, not in a ``__dict__`` per instance, so building one
    and reading a field is cheaper (the model holds one per element of the file). Pickling and
    copying go through :func:`_getstate`/:func:`_setstate`, past the frozen ``__setattr__``."""
    names = [f.name for f in dataclasses.fields(cls)]
    inherited = {name for base in cls.__mro__[1:] for name in getattr(base, "__slots__", ())}
    namespace = {key: value for key, value in vars(cls).items()
                 if key not in names and key not in ("__dict__", "__weakref__")}
    namespace["__slots__"] = tuple(name for name in names if name not in inherited)
    namespace.update(__getstate__=_getstate, __setstate__=_setstate)
    slotted = type(cls)(cls.__name__, cls.__bases__, namespace)
    slotted.__qualname__ = cls.__qualname__
    return slotted


def _build(cls: T, frozen: bool, eq: bool, order: bool) -> T:
    if not cls.__doc__:
        # dataclasses would write the signature as the docstring, through inspect and tokenize
        names = ", ".join(inspect.get_annotations(cls))
        cls.__doc__ = f"{cls.__name__}({names})"
    dataclasses.dataclass(init=False, repr=False, eq=False)(cls)
    if frozen and not _needs_dict(cls):
        cls = _with_slots(cls)
    cls.__record_frozen__ = frozen  # type: ignore[attr-defined]
    cls.__init__ = _make_init(cls)  # type: ignore[misc]
    cls.__record_key__ = staticmethod(_compared(cls))  # type: ignore[attr-defined]
    own = cls.__dict__
    methods: dict[str, Any] = {}
    if "__repr__" not in own:
        methods["__repr__"] = _repr
    if eq and "__eq__" not in own:
        methods["__eq__"] = _eq
    if eq and own.get("__hash__") is None:
        # as dataclasses: frozen and compared means hashable; compared but mutable, unhashable
        methods["__hash__"] = _hash if frozen else None
    if frozen:
        methods.update(__setattr__=_frozen_setattr, __delattr__=_frozen_delattr)
    if order:
        methods.update(_ORDER)
    for name, method in methods.items():
        setattr(cls, name, method)
    REGISTERED.append(cls)
    return cls


@overload
def record(cls: T, /) -> T: ...


@overload
def record(*, frozen: bool = True, eq: bool = True, order: bool = False) -> Callable[[T], T]: ...


@dataclass_transform(frozen_default=True, field_specifiers=(dataclasses.field, dataclasses.Field))
def record(cls: T | None = None, /, *, frozen: bool = True, eq: bool = True,
           order: bool = False) -> T | Callable[[T], T]:
    """Make *cls* a dataclass: ``@record``, or ``@record(order=True)`` to sort records.

    ``@record(frozen=False, eq=False)`` is for one run's mutable state (a reader, a resolver):
    equal only to itself, as ``@dataclass(eq=False)``.
    """
    if cls is None:
        return lambda inner: _build(inner, frozen, eq, order)
    return _build(cls, frozen, eq, order)
