"""Facts the default check shares between rules give what the rules computed on their own.

The default check measures each link's geometry, decomposes each declared tensor
and finds did-you-mean suggestions once (docs/scale.md, "Fifth pass"); these
tests hold the shared answers to the per-call functions they replace, on the
robots of example-robot-data and on names made up here.
"""

from __future__ import annotations

import dataclasses
import difflib
import itertools
import random
from collections.abc import Iterator

import numpy as np
import pytest

from tests.conftest import ERD, erd_urdfs
from urdftool.catalogue.suggest import closest, did_you_mean, suggester
from urdftool.facts import link_mass
from urdftool.facts.context import CheckContext
from urdftool.model import Box, Collision, KinematicTree, Link, Robot, Visual
from urdftool.parse import read
from urdftool.parse.packages import PackageResolver
from urdftool.physics import linkmass
from urdftool.physics.inertia import MIN_MOMENT, assess

WORDS = ["left", "right", "arm", "leg", "link", "joint", "hip", "knee", "wrist", "l", "r", "1", "2"]


def _name(rng: random.Random) -> str:
    return "_".join(rng.choice(WORDS) for _ in range(rng.randint(1, 4)))


@pytest.mark.parametrize("cutoff", [0.3, 0.6, 0.8])
def test_closest_is_difflibs_best_match(cutoff: float) -> None:
    """Ties go to the later name and nothing below the cutoff is offered, as in difflib."""
    rng = random.Random(7)
    for _ in range(500):
        names = [_name(rng) for _ in range(rng.randint(0, 40))]
        word = _name(rng)
        expected = difflib.get_close_matches(word, sorted(set(names)), n=1, cutoff=cutoff)
        assert closest(word, names, cutoff) == (expected[0] if expected else None), (word, names)
        # a fixed vocabulary's answers are kept: asked twice, the same answer as for a list
        assert closest(word, frozenset(names), cutoff) == closest(word, frozenset(names), cutoff) \
            == closest(word, names, cutoff)


def test_suggester_answers_as_did_you_mean() -> None:
    """A rule's suggester answers each word once, with did_you_mean's answer among the same names."""
    rng = random.Random(11)
    for _ in range(200):
        names = [_name(rng) for _ in range(rng.randint(0, 40))]
        suggest = suggester(names)
        for word in [_name(rng) for _ in range(5)] * 2:  # each word asked twice
            assert suggest(word) == did_you_mean(word, names), (word, names)


def _robots() -> list[Robot]:
    resolver = PackageResolver.create()
    files = erd_urdfs()
    # a few robots with meshes, primitives, welded links and repeated meshes
    wanted = [p for p in files if p.endswith(("talos_reduced.urdf", "panda.urdf", "anymal.urdf", "a1.urdf"))]
    return [m.robot for path in wanted for m in read(path, {}, resolver) if m.robot is not None]


def _same(a: object, b: object) -> bool:
    if isinstance(a, np.ndarray):
        return isinstance(b, np.ndarray) and a.shape == b.shape and bool(np.array_equal(a, b))
    return a == b


@pytest.mark.skipif(ERD is None, reason="example-robot-data is not installed")
def test_link_solids_measured_once_match_the_physics_functions() -> None:
    for robot in _robots():
        ctx = CheckContext(robot, KinematicTree.of(robot))
        for link in robot.links:
            shared = list(link_mass.geometry_sources(ctx, link))
            alone = list(linkmass.geometry_sources(link))
            assert [s for s, _ in shared] == [s for s, _ in alone], link.name
            for (_, a), (_, b) in zip(shared, alone, strict=True):
                fields = [f.name for f in dataclasses.fields(a)]
                assert all(_same(getattr(a, f), getattr(b, f)) for f in fields), link.name
            # the second reader gets the very objects the first one measured
            again = list(link_mass.geometry_sources(ctx, link))
            assert all(x[1] is y[1] for x, y in zip(again, shared, strict=True))
            got, expected = link_mass.comparison(ctx, link), linkmass.compare_with_geometry(link)
            assert (got is None) == (expected is None), link.name
            if got is not None and expected is not None:
                assert (got.source, got.ratio, got.worst) == (expected.source, expected.ratio, expected.worst)
                assert np.array_equal(got.computed, expected.computed)


@pytest.mark.skipif(ERD is None, reason="example-robot-data is not installed")
def test_declared_verdict_is_assess() -> None:
    for robot, abs_tol in itertools.product(_robots(), (0.0, MIN_MOMENT)):
        ctx = CheckContext(robot, KinematicTree.of(robot))
        for link in robot.links:
            if link.inertial is not None:
                expected = assess(link.inertial.inertia_matrix, abs_tol=abs_tol)
                assert link_mass.declared_verdict(ctx, link.inertial, abs_tol) == expected, link.name


def test_geometry_sources_stay_lazy() -> None:
    """A rule that stops at the collision solid does not make the visual one be measured."""
    link = Link("l", visuals=(Visual(Box((1.0, 1.0, 1.0))),), collisions=(Collision(Box((0.5, 0.5, 0.5))),))
    robot = Robot("r", links=(link,))
    ctx = CheckContext(robot, KinematicTree.of(robot))
    first = next(link_mass.geometry_sources(ctx, link))
    assert first[0] == "collision"
    assert len(ctx.cache["link-solids"]["l"].measured) == 1
    assert [s for s, _ in link_mass.geometry_sources(ctx, link)] == ["collision", "visual"]


@pytest.mark.skipif(ERD is None, reason="example-robot-data is not installed")
def test_comparisons_in_one_batch_are_the_comparisons_one_at_a_time() -> None:
    """The geometry's moments of every link in one eigh give the comparisons bit for bit."""
    resolver = PackageResolver.create()
    for path in erd_urdfs():
        for model in read(path, {}, resolver):
            robot = model.robot
            if robot is None:
                continue
            batch = CheckContext(robot, KinematicTree.of(robot))
            alone = CheckContext(robot, KinematicTree.of(robot))
            found = list(link_mass.comparisons(batch, robot.links))
            assert [link for link, _ in found] == list(robot.links)
            for link, got in found:
                expected = link_mass.comparison(alone, link)
                assert (got is None) == (expected is None), (path, link.name)
                if got is not None and expected is not None:
                    assert (got.source, got.ratio) == (expected.source, expected.ratio)
                    assert got.worst == expected.worst
                    assert got.computed.tobytes() == expected.computed.tobytes()


def test_comparisons_raise_where_one_at_a_time_would() -> None:
    """An error while listing the links comes after the comparisons of the links before it."""
    links = [Link(f"l{k}", collisions=(Collision(Box((0.5, 0.5, 0.5))),)) for k in range(3)]
    robot = Robot("r", links=tuple(links))
    ctx = CheckContext(robot, KinematicTree.of(robot))

    def listed() -> Iterator[Link]:
        yield links[0]
        yield links[1]
        raise RuntimeError("listing failed")

    found = link_mass.comparisons(ctx, listed())
    assert [link.name for link, _ in itertools.islice(found, 2)] == ["l0", "l1"]
    with pytest.raises(RuntimeError, match="listing failed"):
        next(found)


@pytest.mark.skipif(ERD is None, reason="example-robot-data is not installed")
def test_declared_moments_of_the_whole_robot_are_each_tensors() -> None:
    """One stacked eigh of every declared tensor gives each tensor's own eigenvalues."""
    for robot in _robots():
        ctx = CheckContext(robot, KinematicTree.of(robot))
        for link in robot.links:
            if link.inertial is not None:
                tensor = link.inertial.inertia_matrix
                values, _ = np.linalg.eigh(0.5 * (tensor + tensor.T))
                assert link_mass.declared_moments(ctx, link.inertial) == tuple(values.tolist()), link.name
