"""Certified cells: the bound on how far a moving body's points travel within a cell holds against
forward kinematics (and is the analytic reach for a point); every APART cell is free at random
poses inside it (exact float64 distances) and every CROSSING cell collides (the exact walk); the
sweep gives the same verdicts and gaps with them as without (near misses and touches, padding and
poses past the limits included); no grid is built where the bound would not hold (a prismatic
joint, a loop), and no APART cells where the inside could change unseen (open meshes) or where
the pair mostly collides."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import rswarp
from rswarp.kernels.witness import APART, CROSSING
from rswarp.kinematics.chain import chain_of
from rswarp.sim import certified_cells
from rswarp.sim.bodies import collision_bodies
from rswarp.sim.collisions import Checker

from conftest import DATA

IRB = DATA.parent.parent / "examples" / "irb2600_12_165" / "IRB2600_12_165__01.rsxml"
FIX = DATA / "collisions"


@pytest.fixture(scope="module")
def irb():
    mech = rswarp.load(str(IRB))
    bodies = collision_bodies(mech)
    return mech, bodies, Checker(mech, bodies, certified_cells=True)


def _without_cells(mech, bodies, padding: float = 0.0) -> Checker:
    return Checker(mech, bodies, padding=padding)


def _grid_axes(checker: Checker, p: int) -> tuple[list[int], np.ndarray]:
    cols = [int(c) for c in checker.witnesses.col[2 * p:2 * p + 2] if c >= 0]
    return cols, checker.certified.res[2 * p:2 * p + len(cols)]


def _cells(checker: Checker, p: int) -> np.ndarray:
    cols, res = _grid_axes(checker, p)
    start = checker.certified.start[p]
    return checker.certified.value[start:start + int(np.prod(res))]


def _poses_in(mech, checker: Checker, p: int, cells: np.ndarray, per: int, rng, centre: bool = False) -> np.ndarray:
    """``per`` configurations in each of pair p's cells ``cells`` (random, or the centre)."""
    lower, upper = mech.bounds()
    cols, res = _grid_axes(checker, p)
    q = np.tile((lower + upper) / 2, (len(cells) * per, 1))
    for k, (c, along) in enumerate(zip(cols, np.unravel_index(cells, res))):
        x = np.repeat(along, per) + (0.5 if centre else rng.random(len(cells) * per))
        q[:, c] = lower[c] + x / checker.certified.scale[2 * p + k]
    return q


def _edge(checker: Checker, p: int, kind: int) -> np.ndarray:
    """Pair p's cells certified ``kind`` beside one that is not: where the bound is tightest."""
    flags = _cells(checker, p).reshape(*_grid_axes(checker, p)[1])
    beside = np.zeros_like(flags, bool)
    for axis in range(flags.ndim):
        for step in (1, -1):
            beside |= np.roll(flags != kind, step, axis=axis)
    return np.nonzero((flags == kind).ravel() & beside.ravel())[0]


def _kind(checker: Checker, p: int, kind: int) -> np.ndarray:
    return np.nonzero(_cells(checker, p) == kind)[0]


def test_a_point_reaches_its_distance_from_the_axes():
    """A point 0.3 m off an axis reaches 0.3 m about it; a point on a later parallel axis 0.7 m
    away reaches 0.7 m about the earlier one (the IRB 2600's axes 2 and 3)."""
    chain = chain_of(rswarp.load(str(IRB)).graph)
    u, o = chain.axis[2], chain.point[2]
    off = np.cross(u, [0.0, 0.0, 1.0])
    off /= np.linalg.norm(off)
    assert certified_cells.reaches(chain, [2], (o + 0.3 * off + 5 * u)[None]) == pytest.approx([0.3], abs=1e-12)
    on_axis3 = chain.point[3][None]
    d = float(np.linalg.norm(np.cross(chain.point[3] - chain.point[2], chain.axis[2])))
    assert certified_cells.reaches(chain, [2, 3], on_axis3) == pytest.approx([d, 0.0], abs=1e-12)


def test_no_point_moves_further_than_the_bound(irb):
    """In 200 random cells of Base/Link2's grid, Link2's vertices at 20 random poses each stay
    within the bound of where they are at the cell's centre, in the Base's frame (float64 FK); and
    the bound is not loose by more than three times."""
    mech, bodies, checker = irb
    chain = chain_of(mech.graph)
    p = bodies.pair_names().index(("Base", "Link2"))
    lower, upper = mech.bounds()
    disp = certified_cells._plan(chain, bodies, checker.witnesses, p, lower, upper)[2]
    rng = np.random.default_rng(4)
    cells = rng.choice(len(_cells(checker, p)), 200, replace=False)
    q = _poses_in(mech, checker, p, cells, 20, rng)
    centre = np.repeat(_poses_in(mech, checker, p, cells, 1, rng, centre=True), 20, axis=0)
    kin = rswarp.Kinematics(mech)
    a, b = bodies.pairs[p]
    v = np.c_[bodies.bodies[b].vertices, np.ones(len(bodies.bodies[b].vertices))].T

    def in_base(qs):
        poses = kin.fk64(qs)
        rel = np.linalg.inv(poses[:, bodies.bodies[a].link]) @ poses[:, bodies.bodies[b].link]
        return (rel @ v)[:, :3]

    moved = np.linalg.norm(in_base(q) - in_base(centre), axis=1).max()
    assert moved <= disp
    assert moved > disp / 3


def _inside(mech, checker: Checker, p: int, kind: int, rng) -> np.ndarray:
    """Poses in pair p's cells certified ``kind``: ten in each of 200 beside another cell, three in
    each of 200 others."""
    cells, edge = _kind(checker, p, kind), _edge(checker, p, kind)
    q = [_poses_in(mech, checker, p, rng.choice(cells, min(200, len(cells)), replace=False), 3, rng)]
    if len(edge):
        q.append(_poses_in(mech, checker, p, rng.choice(edge, 200), 10, rng))
    return np.concatenate(q)


def test_every_apart_cell_is_free_inside(irb):
    """At poses in every pair's APART cells, the exact distance exceeds the margin."""
    mech, bodies, checker = irb
    rng = np.random.default_rng(7)
    grids = [p for p in range(len(bodies.pairs)) if len(_kind(checker, p, APART))]
    assert len(grids) >= 3
    for p in grids:
        q = _inside(mech, checker, p, APART, rng)
        assert checker.distances(q, np.full(len(q), p, np.int32)).min() > certified_cells.MARGIN


@pytest.fixture(scope="module")
def through():
    """An arm that swings down through its slab: APART and CROSSING cells side by side."""
    mech = rswarp.load(str(FIX / "fold_through.rsxml"))
    bodies = collision_bodies(mech)
    return mech, bodies, Checker(mech, bodies, certified_cells=True)


def test_every_crossing_cell_collides_inside(irb, through):
    """At poses in every pair's CROSSING cells (the IRB 2600's wrist in its forearm, the arm through
    its slab), the exact walk (no certified cells) finds a hit."""
    for mech, bodies, checker in (irb, through):
        rng = np.random.default_rng(8)
        bare = _without_cells(mech, bodies)
        grids = [p for p in range(len(bodies.pairs)) if len(_kind(checker, p, CROSSING))]
        assert grids
        for p in grids:
            assert bare.verdicts(_inside(mech, checker, p, CROSSING, rng))[0][:, p].all()


def test_the_arm_through_its_slab_has_the_same_verdicts_at_every_edge(through):
    """Poses crowded into the cells beside the other kind (where the arm enters the slab) and
    random ones: the same hits and gaps as without certified cells."""
    mech, bodies, checker = through
    rng = np.random.default_rng(13)
    cells = _cells(checker, 0)
    assert 0.2 < (cells == CROSSING).mean() < 0.5 and 0.5 < (cells == APART).mean() < 0.8
    lower, upper = mech.bounds()
    q = np.concatenate([_poses_in(mech, checker, 0, rng.choice(_edge(checker, 0, kind), 300), 10, rng)
                        for kind in (APART, CROSSING)] + [lower + (upper - lower) * rng.random((4000, 2))])
    hit, gap = checker.verdicts(q)
    bare_hit, bare_gap = _without_cells(mech, bodies).verdicts(q)
    np.testing.assert_array_equal(hit, bare_hit)
    np.testing.assert_array_equal(gap, bare_gap)
    assert not hit[:3000].any() and hit[3000:6000].all()


def test_the_arm_past_its_base_and_the_wrist_in_its_forearm_are_mostly_certified(irb):
    """Base/Link2's cells are APART but for those near touching, and the pair that always collides
    (Link4/Link6) has CROSSING cells and no APART ones."""
    _, bodies, checker = irb
    names = bodies.pair_names()
    base, wrist = _cells(checker, names.index(("Base", "Link2"))), _cells(checker, names.index(("Link4", "Link6")))
    assert 0.8 < (base == APART).mean() < 1.0
    assert (wrist == CROSSING).mean() > 0.4 and not (wrist == APART).any()


def test_certified_cells_change_no_verdict_or_gap(irb):
    """Random states; states crowded into Base/Link2's APART cells beside others (near misses) and
    its uncertified cells; states past the joint limits: the same hits and gaps as without
    certified cells."""
    mech, bodies, checker = irb
    lower, upper = mech.bounds()
    rng = np.random.default_rng(12)
    p = bodies.pair_names().index(("Base", "Link2"))
    apart, neither = _edge(checker, p, APART), _kind(checker, p, 0)
    assert len(apart) > 20
    span = upper - lower
    q = np.concatenate([_poses_in(mech, checker, p, rng.choice(cells, 300), 10, rng) for cells in (apart, neither)] +
                       [lower + span * rng.random((3000, len(lower))),
                        lower - 0.1 * span + 1.2 * span * rng.random((2000, len(lower)))])
    hit, gap = checker.verdicts(q)
    bare_hit, bare_gap = _without_cells(mech, bodies).verdicts(q)
    np.testing.assert_array_equal(hit, bare_hit)
    np.testing.assert_array_equal(gap, bare_gap)
    assert not hit[:3000, p].any() and hit[3000:6000, p].any()


def test_a_padding_certifies_fewer_cells_and_changes_nothing(irb):
    mech, bodies, checker = irb
    p = bodies.pair_names().index(("Base", "Link2"))
    padded = Checker(mech, bodies, padding=0.05, certified_cells=True)
    assert (_cells(padded, p) == APART).mean() < (_cells(checker, p) == APART).mean()
    lower, upper = mech.bounds()
    q = lower + (upper - lower) * np.random.default_rng(2).random((3000, len(lower)))
    for got, want in zip(padded.verdicts(q), _without_cells(mech, bodies, padding=0.05).verdicts(q)):
        np.testing.assert_array_equal(got, want)


@pytest.mark.parametrize("fixture, why", [("ball.rsxml", "a prismatic joint"), ("four_bar_dead.rsxml", "a loop")])
def test_no_grid_where_the_bound_does_not_hold(fixture, why):
    mech = rswarp.load(str(FIX / fixture))
    checker = Checker(mech, collision_bodies(mech), certified_cells=True)
    assert (checker.witnesses.start >= 0).any(), why  # a witness grid, but no certified one
    assert (checker.certified.start < 0).all(), why


def test_no_apart_cells_for_open_meshes_or_a_pair_that_mostly_collides():
    """The arm through its slab has APART cells; the same bodies as open meshes (inside by winding
    number) have none (their CROSSING cells stay), nor has fold_always.rsxml, whose arm lies in the
    slab."""
    mech = rswarp.load(str(FIX / "fold_through.rsxml"))
    bodies = collision_bodies(mech)
    assert (Checker(mech, bodies, certified_cells=True).certified.value == APART).any()
    opened = dataclasses.replace(bodies, bodies=tuple(dataclasses.replace(b, watertight=False) for b in bodies.bodies))
    cells = Checker(mech, opened, certified_cells=True).certified.value
    assert not (cells == APART).any() and (cells == CROSSING).any()
    always = rswarp.load(str(FIX / "fold_always.rsxml"))
    assert not (Checker(always, collision_bodies(always), certified_cells=True).certified.value == APART).any()
