"""Witness grids (``rswarp.kernels.witness``): for each pair whose relative pose depends on at
most two joints, a grid over those joints' limits; each cell holds triangle pairs that cross at the
cell's centre, found once per checker by a walk of every crossing. Verdicts stay exact (a witness
is tested at the actual pose); the grid only lets a walk be skipped."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..kernels.types import WITNESSES, Chain
from .bodies import CollisionBodies

CELLS = {0: (), 1: (256,), 2: (32, 32)}  # cells along each grid axis, by the number of joints


@dataclass(frozen=True)
class WitnessGrid:
    """Every pair's grid as the flat arrays of the ``BodyArrays`` struct (two axis slots per pair)."""

    start: np.ndarray  # (pairs,) int32: first cell, -1 for no grid
    col: np.ndarray  # (2 * pairs,) int32: q column of each axis, -1 for none
    lo: np.ndarray  # (2 * pairs,) lower limit of each axis
    scale: np.ndarray  # (2 * pairs,) cells per unit of q
    res: np.ndarray  # (2 * pairs,) int32 cells along each axis
    witness: np.ndarray  # (cells * WITNESSES, 2) int32: (A's, B's) triangle, -1 for none
    usual: np.ndarray | None = None  # (pairs,) int32: the cell of a pair's usual crossings, -1 for none



def pair_columns(chain: Chain, bodies: CollisionBodies) -> list[tuple[int, ...]]:
    """Per pair, the q columns whose joints move one body relative to the other: the joints on the
    path between their links (every joint above the link, for a body fixed in the world), and the
    active joints a passive one on that path follows."""
    cols = []
    for a, b in bodies.pairs:
        moving = chain.ancestors([bodies.bodies[a].link]) ^ chain.ancestors([bodies.bodies[b].link])
        cols.append(tuple(sorted({int(chain.qidx[k]) for k in moving if chain.qidx[k] >= 0}
                                 | {int(c) for k in moving for c in np.nonzero(chain.mimic[k])[0]})))
    return cols


def cell_centres(cols, counts, lower: np.ndarray, upper: np.ndarray, mid: np.ndarray) -> np.ndarray:
    """The configurations at the centres of a grid's cells over columns ``cols`` (``counts`` cells
    along each, between ``lower`` and ``upper``; ``mid`` elsewhere), row-major: the cell index the
    kernels compute."""
    centres = [lower[c] + (np.arange(n) + 0.5) * (upper[c] - lower[c]) / n for c, n in zip(cols, counts)]
    q = np.tile(mid, (int(np.prod(counts)), 1))
    for c, axis in zip(cols, np.meshgrid(*centres, indexing="ij")):
        q[:, c] = axis.ravel()
    return q


def witness_grid(sample: Callable[[np.ndarray, np.ndarray], np.ndarray], chain: Chain, bodies: CollisionBodies,
                 lower: np.ndarray, upper: np.ndarray) -> WitnessGrid:
    """The grids of every pair moved by at most two joints with finite limits. ``sample(q, pair)``
    gives (N, 2 * WITNESSES) crossing triangle pairs of ``pair[i]`` at ``q[i]``."""
    pairs = len(bodies.pairs)
    start = np.full(pairs, -1, np.int32)
    col, res = np.full(2 * pairs, -1, np.int32), np.ones(2 * pairs, np.int32)
    lo, scale = np.zeros(2 * pairs), np.zeros(2 * pairs)
    mid = np.where(np.isfinite(lower) & np.isfinite(upper), (lower + upper) / 2, 0.0)
    qs, ps, cells = [], [], 0
    for p, cols in enumerate(pair_columns(chain, bodies)):
        if len(cols) not in CELLS or not all(np.isfinite(lower[c]) and np.isfinite(upper[c]) for c in cols):
            continue
        counts = CELLS[len(cols)]
        for k, (c, n) in enumerate(zip(cols, counts)):
            col[2 * p + k], res[2 * p + k], lo[2 * p + k] = c, n, lower[c]
            scale[2 * p + k] = n / max(upper[c] - lower[c], 1e-12)
        q = cell_centres(cols, counts, lower, upper, mid)
        start[p] = cells
        cells += len(q)
        qs.append(q)
        ps.append(np.full(len(q), p, np.int32))
    witness = np.full((max(cells, 1) * WITNESSES, 2), -1, np.int32)
    if cells:
        witness[:cells * WITNESSES] = sample(np.concatenate(qs), np.concatenate(ps)).reshape(-1, 2)
    return WitnessGrid(start, col, lo, scale, res, witness)


USUAL_STATES = 8192  # states drawn (seeded) within the limits to find the pairs' usual crossings
USUAL_WALKS = 256  # colliding states a pair at most, each walked to its first crossing
USUAL_SEED = 1


def usual_crossings(grid: WitnessGrid, hits: Callable[[np.ndarray], np.ndarray],
                    first: Callable[[np.ndarray, np.ndarray], np.ndarray], lower: np.ndarray,
                    upper: np.ndarray) -> WitnessGrid:
    """``grid`` with one more cell a pair: the triangle pairs at which its walk first found a crossing
    most often (WITNESSES at most, each found twice or more), over a seeded sample of states within
    the limits (a joint without limits over a turn), up to USUAL_WALKS colliding states a pair. The
    sweep tries them just before a walk. ``hits(q)``: the sweep's (N, pairs) verdicts; ``first(q,
    pairs)``: (N, 2) triangles, -1 where none cross."""
    rng = np.random.default_rng(USUAL_SEED)
    lo = np.where(np.isfinite(lower), lower, -np.pi)
    hi = np.where(np.isfinite(upper), upper, np.pi)
    q = lo + (hi - lo) * rng.random((USUAL_STATES, len(lo)))
    hit = hits(q)
    pairs = hit.shape[1]
    rows = [np.sort(rng.choice(np.flatnonzero(hit[:, p]), min(USUAL_WALKS, int(hit[:, p].sum())), replace=False))
            for p in range(pairs)]
    which = np.concatenate([np.full(len(r), p, np.int32) for p, r in enumerate(rows)])
    found = first(q[np.concatenate(rows)], which) if len(which) else np.zeros((0, 2), np.int32)
    cells = len(grid.witness) // WITNESSES
    usual, extra = np.full(pairs, -1, np.int32), []
    for p in range(pairs):
        mine = found[(which == p) & (found[:, 0] >= 0)]
        if not len(mine):
            continue
        tris, count = np.unique(mine, axis=0, return_counts=True)
        order = np.lexsort((tris[:, 1], tris[:, 0], -count))  # most often first, ties by triangle
        keep = tris[order][count[order] >= 2][:WITNESSES]
        if len(keep):
            usual[p] = cells + len(extra)
            extra.append(np.vstack([keep, np.full((WITNESSES - len(keep), 2), -1, np.int32)]))
    witness = np.concatenate([grid.witness, *extra]) if extra else grid.witness
    return WitnessGrid(grid.start, grid.col, grid.lo, grid.scale, grid.res, witness, usual)
