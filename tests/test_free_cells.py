"""Free cells: the bound on how far a moving body's points travel within a cell holds against
forward kinematics (and is the analytic reach for a point), every certified cell is free at random
poses inside it (exact float64 distances), the sweep gives the same verdicts and gaps with them as
without (near misses, padding and poses past the limits included), and no grid is built where the
bound would not hold (a prismatic joint, a loop, open meshes, a pair that mostly collides)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import rswarp
from rswarp.kinematics.chain import chain_of
from rswarp.launch import init_warp
from rswarp.sim import free_cells
from rswarp.sim.bodies import collision_bodies
from rswarp.sim.collisions import Checker

from conftest import DATA

IRB = DATA.parent.parent / "examples" / "irb2600_12_165" / "IRB2600_12_165__01.rsxml"
FIX = DATA / "collisions"


@pytest.fixture(scope="module")
def irb():
    mech = rswarp.load(str(IRB))
    bodies = collision_bodies(mech)
    return mech, bodies, Checker(mech, bodies)


def _without_free(mech, bodies, padding: float = 0.0) -> Checker:
    checker = Checker(mech, bodies, padding=padding)
    checker._device.set_free(None, init_warp().float32)
    return checker


def _grid_axes(checker: Checker, p: int) -> tuple[list[int], np.ndarray]:
    cols = [int(c) for c in checker.witnesses.col[2 * p:2 * p + 2] if c >= 0]
    return cols, checker.free.res[2 * p:2 * p + len(cols)]


def _cells(checker: Checker, p: int) -> np.ndarray:
    cols, res = _grid_axes(checker, p)
    start = checker.free.start[p]
    return checker.free.free[start:start + int(np.prod(res))]


def _poses_in(mech, checker: Checker, p: int, cells: np.ndarray, per: int, rng, centre: bool = False) -> np.ndarray:
    """``per`` configurations in each of pair p's free cells ``cells`` (random, or the centre)."""
    lower, upper = mech.bounds()
    cols, res = _grid_axes(checker, p)
    q = np.tile((lower + upper) / 2, (len(cells) * per, 1))
    for k, (c, along) in enumerate(zip(cols, np.unravel_index(cells, res))):
        x = np.repeat(along, per) + (0.5 if centre else rng.random(len(cells) * per))
        q[:, c] = lower[c] + x / checker.free.scale[2 * p + k]
    return q


def _edge(checker: Checker, p: int) -> np.ndarray:
    """Pair p's certified cells beside an uncertified one: the nearest to touching."""
    flags = _cells(checker, p).reshape(*_grid_axes(checker, p)[1])
    beside = np.zeros_like(flags, bool)
    for axis in range(flags.ndim):
        for step in (1, -1):
            beside |= np.roll(flags == 0, step, axis=axis)
    return np.nonzero((flags == 1).ravel() & beside.ravel())[0]


def test_a_point_reaches_its_distance_from_the_axes():
    """A point 0.3 m off an axis reaches 0.3 m about it; a point on a later parallel axis 0.7 m
    away reaches 0.7 m about the earlier one (the IRB 2600's axes 2 and 3)."""
    chain = chain_of(rswarp.load(str(IRB)).graph)
    u, o = chain.axis[2], chain.point[2]
    off = np.cross(u, [0.0, 0.0, 1.0])
    off /= np.linalg.norm(off)
    assert free_cells.reaches(chain, [2], (o + 0.3 * off + 5 * u)[None]) == pytest.approx([0.3], abs=1e-12)
    on_axis3 = chain.point[3][None]
    d = float(np.linalg.norm(np.cross(chain.point[3] - chain.point[2], chain.axis[2])))
    assert free_cells.reaches(chain, [2, 3], on_axis3) == pytest.approx([d, 0.0], abs=1e-12)


def test_no_point_moves_further_than_the_bound(irb):
    """In 200 random cells of Base/Link2's grid, Link2's vertices at 20 random poses each stay
    within the bound of where they are at the cell's centre, in the Base's frame (float64 FK); and
    the bound is not loose by more than three times."""
    mech, bodies, checker = irb
    chain = chain_of(mech.graph)
    p = bodies.pair_names().index(("Base", "Link2"))
    lower, upper = mech.bounds()
    _, _, disp = free_cells._plan(chain, bodies, checker.witnesses, p, lower, upper)
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


def test_every_certified_cell_is_free_inside(irb):
    """At random poses in certified cells of every free grid (ten in each of 200 beside an
    uncertified cell, where the bound is tightest, and three in each of 200 others), the exact
    distance exceeds the margin."""
    mech, bodies, checker = irb
    rng = np.random.default_rng(7)
    grids = [p for p in range(len(bodies.pairs)) if checker.free.start[p] >= 0]
    assert len(grids) >= 3
    for p in grids:
        certified, edge = np.nonzero(_cells(checker, p))[0], _edge(checker, p)
        q = [_poses_in(mech, checker, p, rng.choice(certified, min(200, len(certified)), replace=False), 3, rng)]
        if len(edge):
            q.append(_poses_in(mech, checker, p, rng.choice(edge, 200), 10, rng))
        q = np.concatenate(q)
        assert checker.distances(q, np.full(len(q), p, np.int32)).min() > free_cells.MARGIN


def test_the_lower_arm_passing_its_base_is_spared_most_walks(irb):
    """Base/Link2's cells are certified but for those near touching, and the pair that always
    collides (Link4/Link6) has no free grid."""
    _, bodies, checker = irb
    names = bodies.pair_names()
    assert 0.8 < _cells(checker, names.index(("Base", "Link2"))).mean() < 1.0
    assert checker.free.start[names.index(("Link4", "Link6"))] < 0


def test_free_cells_change_no_verdict_or_gap(irb):
    """Random states, states crowded into Base/Link2's certified cells beside uncertified ones (the
    near misses), and states past the joint limits: the same hits and gaps as without free cells."""
    mech, bodies, checker = irb
    lower, upper = mech.bounds()
    rng = np.random.default_rng(12)
    p = bodies.pair_names().index(("Base", "Link2"))
    flags = _cells(checker, p)
    edge = _edge(checker, p)
    assert len(edge) > 20
    span = upper - lower
    q = np.concatenate([lower + span * rng.random((3000, len(lower))),
                        _poses_in(mech, checker, p, rng.choice(edge, 300), 10, rng),
                        _poses_in(mech, checker, p, rng.choice(np.nonzero(flags == 0)[0], 300), 10, rng),
                        lower - 0.1 * span + 1.2 * span * rng.random((2000, len(lower)))])
    hit, gap = checker.verdicts(q)
    bare_hit, bare_gap = _without_free(mech, bodies).verdicts(q)
    np.testing.assert_array_equal(hit, bare_hit)
    np.testing.assert_array_equal(gap, bare_gap)
    assert not hit[3000:6000, p].any() and hit[6000:9000, p].any()  # certified: free; beside them, hits


def test_a_padding_certifies_fewer_cells_and_changes_nothing(irb):
    mech, bodies, checker = irb
    p = bodies.pair_names().index(("Base", "Link2"))
    padded = Checker(mech, bodies, padding=0.05)
    assert _cells(padded, p).mean() < _cells(checker, p).mean()
    lower, upper = mech.bounds()
    q = lower + (upper - lower) * np.random.default_rng(2).random((3000, len(lower)))
    for got, want in zip(padded.verdicts(q), _without_free(mech, bodies, padding=0.05).verdicts(q)):
        np.testing.assert_array_equal(got, want)


@pytest.mark.parametrize("fixture, why", [("ball.rsxml", "a prismatic joint"), ("four_bar_dead.rsxml", "a loop"),
                                          ("fold_always.rsxml", "mostly colliding")])
def test_no_free_grid_where_the_bound_does_not_hold(fixture, why):
    mech = rswarp.load(str(FIX / fixture))
    checker = Checker(mech, collision_bodies(mech))
    assert (checker.witnesses.start >= 0).any(), why  # a witness grid, but no free one
    assert (checker.free.start < 0).all(), why


def test_open_meshes_get_no_free_grid():
    """fold.rsxml has a free grid; the same bodies as open meshes (inside by winding number) none."""
    mech = rswarp.load(str(FIX / "fold.rsxml"))
    bodies = collision_bodies(mech)
    assert (Checker(mech, bodies).free.start >= 0).any()
    opened = dataclasses.replace(bodies, bodies=tuple(dataclasses.replace(b, watertight=False) for b in bodies.bodies))
    assert (Checker(mech, opened).free.start < 0).all()
