"""Facts the default check shares between rules give what the rules computed on their own.

The default check measures each link's geometry, decomposes each declared tensor
and finds did-you-mean suggestions once (docs/scale.md, "Fifth pass"); these
tests hold the shared answers to the per-call functions they replace, on the
robots of example-robot-data and on names made up here. The robot at home in
plain floats (docs/scale.md, "Eleventh pass") is held to the 4x4 forward
kinematics within 1e-12.
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
from urdftool.facts import home, link_mass
from urdftool.facts.context import CheckContext
from urdftool.model import (
    Box,
    Collision,
    Inertial,
    Joint,
    JointType,
    KinematicTree,
    Link,
    Mimic,
    Pose,
    Robot,
    Visual,
)
from urdftool.parse import read
from urdftool.parse.packages import PackageResolver
from urdftool.physics import linkmass
from urdftool.physics.inertia import MIN_MOMENT, assess
from urdftool.physics.massprops import geometry_properties
from urdftool.rules.inertia_geometry import InertiaGeometryMismatch
from urdftool.rules.intent_common import on_one_chain
from urdftool.rules.mirror_names import _TOKENS, _swap_token, mirror_names, pairs

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
        assert closest(word, set(names), cutoff) == closest(word, names, cutoff)  # a set searched as it is
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
                assert (got.source, got.ratio) == (expected.source, expected.ratio), link.name
                assert got.computed == expected.computed, link.name


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
    assert isinstance(ctx.cache["link-solids"]["l"].visual, link_mass._Unmeasured)
    assert [s for s, _ in link_mass.geometry_sources(ctx, link)] == ["collision", "visual"]


@pytest.mark.skipif(ERD is None, reason="example-robot-data is not installed")
def test_moment_factors_in_one_batch_are_the_factors_one_at_a_time() -> None:
    """Both tensors of every compared link in one eigh give each link's moment factor bit for bit."""
    resolver = PackageResolver.create()
    for path in erd_urdfs():
        for model in read(path, {}, resolver):
            robot = model.robot
            if robot is None:
                continue
            ctx = CheckContext(robot, KinematicTree.of(robot))
            compared = [(link, found) for link in robot.links
                        if (found := link_mass.comparison(ctx, link)) is not None]
            for (link, found), factor in zip(compared, link_mass.moment_factors(compared), strict=True):
                assert link.inertial is not None
                declared = linkmass.moments_of(link.inertial.inertia)
                assert factor == linkmass.moment_factor(declared, linkmass.moments_of(found.computed))
                # the ratio of the traces is a weighted mean of the moments' ratios
                assert factor >= found.factor * (1 - 1e-12), (path, link.name)


def test_a_link_that_fails_to_measure_comes_after_the_findings_of_the_links_before_it() -> None:
    """inertia-geometry-mismatch reports the links before one whose geometry fails to measure,
    those whose moments it compares after the others among them, then raises."""
    box = Box((0.5, 0.2, 0.1))
    solid = geometry_properties(box)
    assert solid is not None
    (ixx, _, _), (_, iyy, _), (_, _, izz) = solid.inertia_for_mass(1.0)  # the box's moments at 1 kg
    on_other_axes = Inertial(1.0, ((iyy, 0.0, 0.0), (0.0, ixx, 0.0), (0.0, 0.0, izz)))
    tenfold_smaller = Inertial(1.0, ((ixx / 10, 0.0, 0.0), (0.0, iyy / 10, 0.0), (0.0, 0.0, izz / 10)))
    links = [Link(f"l{k}", inertial=inertial, collisions=(Collision(box),))
             for k, inertial in enumerate((on_other_axes, tenfold_smaller, on_other_axes))]
    robot = Robot("r", links=tuple(links))
    ctx = CheckContext(robot, KinematicTree.of(robot))
    measured = link_mass.geometry_sources(ctx, links[0])  # the memo of link solids, made now
    list(measured)

    def measure(geometry: object) -> object:
        raise RuntimeError("unreadable")

    ctx.cache["link-solids"]["l2"] = link_mass._Sources(links[2], measure)  # type: ignore[arg-type]
    found = InertiaGeometryMismatch().check(ctx)
    reported = [d.message for d in itertools.islice(found, 2)]
    assert sorted(message.split("'")[1] for message in reported) == ["l0", "l1"]
    assert "wrong axes" in reported[1] and "1/10 of" in reported[0]
    with pytest.raises(RuntimeError, match="unreadable"):
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


@pytest.mark.parametrize("failing", ["collision", "visual"])
def test_a_solid_that_fails_raises_once(failing: str) -> None:
    """The rule that meets a failing measurement gets the error; the rules after it read on
    without that solid (nor the visual one, when the collision one failed)."""
    collision, visual = Box((0.5, 0.5, 0.5)), Box((1.0, 1.0, 1.0))
    link = Link("l", visuals=(Visual(visual),), collisions=(Collision(collision),))
    broken = collision if failing == "collision" else visual

    def measure(geometry: object) -> object:
        if geometry is broken:
            raise RuntimeError("unreadable")
        return geometry_properties(geometry)  # type: ignore[arg-type]

    sources = link_mass._Sources(link, measure)  # type: ignore[arg-type]
    first = sources.read()
    if failing == "visual":
        assert next(first)[0] == "collision"
    with pytest.raises(RuntimeError, match="unreadable"):
        next(first)
    assert [s for s, _ in sources.read()] == ([] if failing == "collision" else ["collision"])


def _home_robots() -> Iterator[Robot]:
    """Every robot of example-robot-data, and one whose mimic joints sit away from 0 at home."""
    resolver = PackageResolver.create()
    for path in erd_urdfs():
        yield from (m.robot for m in read(path, {}, resolver) if m.robot is not None)
    links = tuple(Link(f"l{k}") for k in range(5))
    turn = Pose((0.1, -0.2, 0.3), (0.4, -0.5, 0.6))
    yield Robot("mimics", links=links, joints=(
        Joint("lead", JointType.REVOLUTE, "l0", "l1", turn, (0.0, 0.0, 1.0)),
        Joint("turned", JointType.REVOLUTE, "l1", "l2", turn, (1.0, 2.0, 2.0), mimic=Mimic("lead", 2.0, 0.3)),
        Joint("slid", JointType.PRISMATIC, "l2", "l3", turn, (0.0, 3.0, 4.0),
              mimic=Mimic("turned", 1.0, -0.2)),
        Joint("welded", JointType.FIXED, "l3", "l4", turn),
    ))


@pytest.mark.skipif(ERD is None, reason="example-robot-data is not installed")
def test_home_frames_in_floats_are_the_forward_kinematics() -> None:
    """The rules' robot at home, in plain floats, is the exporters' 4x4 forward kinematics to the
    last digit or two (the products are summed in another order)."""
    for robot in _home_robots():
        ctx = CheckContext(robot, KinematicTree.of(robot))
        frames, poses = home.home_frames(ctx), ctx.tree.forward_kinematics()
        assert frames.keys() == poses.keys(), robot.name
        for name, (rotation, origin) in frames.items():
            pose = poses[name]
            scale = max(1.0, float(np.abs(pose[:3, 3]).max()))
            np.testing.assert_allclose(rotation, pose[:3, :3], rtol=0, atol=1e-12, err_msg=name)
            np.testing.assert_allclose(origin, pose[:3, 3], rtol=0, atol=1e-12 * scale, err_msg=name)


def _mirror_names_as_written(name: str) -> list[str]:
    """:func:`mirror_names` as first written: every token's swaps, then every marker swapped
    (when that changes the name), then each swap one at a time."""
    parts = _TOKENS.split(name)
    tokens = [_swap_token(part) if i % 2 == 0 else [] for i, part in enumerate(parts)]
    if not any(tokens):
        return []
    out: list[str] = []
    every = [(swaps or [part])[0] for part, swaps in zip(parts, tokens, strict=True)]
    if every != parts:
        out.append("".join(every))
    for i, swaps in enumerate(tokens):
        for swapped in swaps:
            out.append("".join((*parts[:i], swapped, *parts[i + 1 :])))
    return out


def _pairs_unfiltered(names: list[str]) -> list[tuple[str, str]]:
    """:func:`pairs` as first written: every name's mirror names, without the letters test and
    without skipping a name already paired with all its look-alikes."""
    known, seen, out = set(names), set(), []
    for name in names:
        for other in _mirror_names_as_written(name):
            key = frozenset((name, other))
            if other in known and other != name and key not in seen:
                seen.add(key)
                out.append((name, other))
    return out


def test_mirror_pairs_skip_only_names_without_a_mirror() -> None:
    """Names left alone once their side letters are deleted are skipped, and nothing else."""
    rng = random.Random(11)
    tokens = ["l", "r", "L", "R", "left", "Right", "LEFT", "leftL", "FL", "RR", "lF", "Hl", "hip", "tight"]
    for _ in range(3000):
        names = ["".join(rng.choice(tokens) + rng.choice("_-.") for _ in range(rng.randint(1, 3)))
                 for _ in range(rng.randint(2, 30))]
        names += [rng.choice(mirror_names(n) or [n]) for n in names[:8]]
        assert pairs(names) == _pairs_unfiltered(names), names
        for name in names:
            assert mirror_names(name) == _mirror_names_as_written(name), name


@pytest.mark.skipif(ERD is None, reason="example-robot-data is not installed")
def test_mirror_names_and_pairs_of_real_robots() -> None:
    """The mirror names and pairs of every joint and link name of example-robot-data, as first written."""
    for robot in _robots():
        for names in ([j.name for j in robot.joints], [k.name for k in robot.links]):
            assert pairs(names) == _pairs_unfiltered(names), robot.name
            for name in names:
                assert mirror_names(name) == _mirror_names_as_written(name), name


@pytest.mark.skipif(ERD is None, reason="example-robot-data is not installed")
def test_links_on_one_chain_by_walking_up_are_lineal() -> None:
    """The mirror rules' walk up the tree answers as the tree's numbering of subtrees does."""
    rng = random.Random(5)
    for robot in _robots():
        tree = KinematicTree.of(robot)
        names = [link.name for link in robot.links] + ["no_such_link"]
        for _ in range(2000):
            a, b = rng.choice(names), rng.choice(names)
            assert on_one_chain(tree, a, b) == tree.lineal(a, b), (robot.name, a, b)
