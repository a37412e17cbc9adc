"""Records (urdftool.records): dataclass semantics, with ``__init__`` compiled ahead of time."""

from __future__ import annotations

import copy
import dataclasses
import os
import pickle
from dataclasses import field

import pytest

import urdftool
from urdftool import records, records_generate
from urdftool.model import Box, Inertial, Joint, JointType, Link, Pose
from urdftool.source import Span


def test_generated_modules_are_up_to_date() -> None:
    """``python -m urdftool.records_generate`` was run after the last change to a record."""
    expected = records_generate.render()
    written = {}
    for name in sorted(os.listdir(records_generate.TARGET)):
        if name.endswith(".py"):
            with open(os.path.join(records_generate.TARGET, name), encoding="utf-8") as handle:
                written[name] = handle.read()
    assert written == expected, "run: python -m urdftool.records_generate"


def test_every_record_of_urdftool_uses_its_compiled_init() -> None:
    records_generate.render()  # imports every module of urdftool
    assert [name for name in records.FALLBACKS if name.startswith("urdftool.")] == []
    assert len(records.REGISTERED) > 150


def test_spans_take_no_part_in_equality_or_hashing() -> None:
    a = Link("base", span=Span("a.urdf", 3, 5))
    b = Link("base", span=Span("b.urdf", 9, 1))
    assert a == b and hash(a) == hash(b)
    assert a != Link("tool") and a != "base"
    assert Inertial(1.0, Inertial.tensor(1, 0, 0, 1, 0, 1), mass_span=Span("x", 1)) == \
        Inertial(1.0, Inertial.tensor(1, 0, 0, 1, 0, 1))


def test_records_are_frozen_dataclasses() -> None:
    link = Link("base")
    with pytest.raises(dataclasses.FrozenInstanceError):
        link.name = "other"  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        del link.name  # type: ignore[misc]
    assert dataclasses.is_dataclass(link)
    assert [f.name for f in dataclasses.fields(Box)] == ["size", "span"]
    moved = dataclasses.replace(Joint("j", JointType.REVOLUTE, "a", "b"), origin=Pose((0, 0, 1), (0, 0, 0)))
    assert moved.origin.xyz == (0, 0, 1) and moved.name == "j"
    assert pickle.loads(pickle.dumps(moved)) == moved
    assert copy.deepcopy(moved) == moved
    assert repr(Box((1.0, 2.0, 3.0))) == "Box(size=(1.0, 2.0, 3.0), span=None)"


def test_frozen_records_keep_their_fields_in_slots() -> None:
    """One object per element of the file: no ``__dict__`` each, unless a cached property needs it."""
    link = Link("base", span=Span("a.urdf", 1))
    assert not hasattr(link, "__dict__") and not hasattr(link.span, "__dict__")
    assert copy.copy(link) == link and pickle.loads(pickle.dumps(link)).span == link.span
    robot = urdftool.Robot("r", links=(link,))
    assert hasattr(robot, "__dict__")  # Robot caches its lookups in cached properties


def test_spans_sort_by_file_then_place() -> None:
    spans = [Span("b.urdf", 1), Span("a.urdf", 7, 2), Span("a.urdf", 7, 1)]
    assert sorted(spans) == [Span("a.urdf", 7, 1), Span("a.urdf", 7, 2), Span("b.urdf", 1)]


def test_a_record_missing_from_the_generated_module_is_compiled_at_import() -> None:
    """A record added without regenerating still behaves, defaults, factories and all."""

    @records.record
    class Wheel:
        radius: float
        width: float = 0.05
        tags: list[str] = field(default_factory=list)
        span: Span | None = field(default=None, compare=False)
        diameter: float = field(init=False, default=0.0)

        def __post_init__(self) -> None:
            object.__setattr__(self, "diameter", 2 * self.radius)

    assert any(name.endswith("Wheel") for name in records.FALLBACKS)
    left, right = Wheel(0.1), Wheel(0.1, span=Span("w.urdf", 2))
    assert left == right and left.tags is not right.tags
    assert left.width == 0.05 and left.diameter == pytest.approx(0.2)
    with pytest.raises(TypeError):
        Wheel()  # type: ignore[call-arg]


def test_run_state_records_are_mutable_and_equal_only_to_themselves() -> None:
    @records.record(frozen=False, eq=False)
    class Counter:
        seen: dict[str, int] = field(default_factory=dict)

    one, two = Counter(), Counter()
    one.seen["a"] = 1
    assert one != two and one == one and len({one, two}) == 2

    @records.record(frozen=False)
    class Options:
        select: tuple[str, ...] = ()

    assert Options(("S",)) == Options(("S",))
    with pytest.raises(TypeError):
        hash(Options())
