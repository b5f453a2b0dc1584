"""Certified cells (``rswarp.kernels.witness.certified_function``): for each pair with a witness grid
whose joints are revolute, a finer grid over the same axes, each cell certified APART, CROSSING or
neither. The sweep settles a pose in a certified cell with no walk and no triangle test; verdicts
and gaps stay what the walk gives.

APART: the bodies are further apart at the cell's centre than the most any point of the moving
body can travel within the cell (the bound), plus the padding and a margin, so they are apart at
every pose of the cell. Containment is asked once per connected set of such cells (at its first
cell's centre): where the surfaces stay apart, a closed body's inside cannot change, so neither
can a piece's being in it. Open meshes (inside by winding number) and pairs that mostly collide
get no APART cells.

CROSSING: a witness of the coarse cell holding the centre crosses there so that an edge of the
moving body's triangle pierces the other's with margins beyond the bound (``pierce_function``),
so the surfaces cross at every pose of the cell.

The bound: a point p moved by joints 1..n (axis k through o_k along u_k) moves at |dp/dq_k| =
|u_k x (p - o_k)|, its distance from axis k, so within a cell its distance from the centre's
position is at most sum_k h_k rho_k (h_k the cell's half width, rho_k the most that distance can
be). The last joint's rho is the body's farthest vertex from its axis; an earlier one's, the later
axis' distance from it plus the farthest vertex from a point on that axis (both unchanged by any
joint of the path)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..kernels.types import FIXED, REVOLUTE, WITNESSES, Chain
from ..kernels.witness import APART, CROSSING
from .bodies import CollisionBodies
from .witness import WitnessGrid, cell_centres

CERTIFIED_CELLS = {1: 1024, 2: 16384}  # cells of a pair's certified grid, by the number of its joints
BLOCK = {1: 16, 2: 4}  # cells along each axis of the blocks asked first (``certified_grid``)
# m: a certified cell keeps the bodies this much further apart than the padding, for the sweep's
# float32 poses and cell indices (errors of a micrometre)
MARGIN = 1e-4
# states a sweep needs before its certified grids pay for their setup (a few hundredths of a
# second, against the tenth of a microsecond or more a state they save on one core,
# ``benchmarks/bench_collisions.py``): a smaller sweep builds none
CERTIFIED_PAY = 1_000_000
# a pair whose witnesses cross in more than this share of its cells mostly collides: no APART cells
MOSTLY_CROSSING = 0.5


@dataclass(frozen=True)
class CertifiedGrid:
    """Every pair's certified grid as the flat arrays of the ``BodyArrays`` struct (its axes are
    the witness grid's: ``WitnessGrid.col`` and ``lo``)."""

    start: np.ndarray  # (pairs,) int32: first cell, -1 for no grid
    scale: np.ndarray  # (2 * pairs,) cells per unit of q
    res: np.ndarray  # (2 * pairs,) int32 cells along each axis
    value: np.ndarray  # (cells,) uint8: APART, CROSSING, or 0

    @staticmethod
    def none(pairs: int) -> "CertifiedGrid":
        return CertifiedGrid(np.full(pairs, -1, np.int32), np.zeros(2 * pairs), np.ones(2 * pairs, np.int32),
                             np.zeros(1, np.uint8))


def moving_joints(chain: Chain, bodies: CollisionBodies, pair: int) -> tuple[int, list[int]] | None:
    """(the body the pair's joints move relative to the other, their links upstream first), or
    None unless each is a revolute joint driven by its own column (no loop, mimic or closed form)
    on one body's side."""
    a, b = bodies.pairs[pair]
    pa, pb = chain.ancestors([bodies.bodies[a].link]), chain.ancestors([bodies.bodies[b].link])
    moving = pa ^ pb
    mover = b if moving <= pb else a if moving <= pa else None
    if mover is None:
        return None
    if any(chain.qidx[k] < 0 and chain.jtype[k] != FIXED for k in moving):
        return None  # a joint no column drives (a loop's passive joint)
    joints = [int(k) for k in chain.order if k in moving and chain.qidx[k] >= 0]  # parents first
    for k in joints:
        if (chain.jtype[k] != REVOLUTE or np.any(chain.mimic[k]) or chain.closed_form[k][0] != 0
                or chain.unknown[k] >= 0 or np.any(chain.mimic[:, chain.qidx[k]])):
            return None
    return mover, joints


def reaches(chain: Chain, joints: list[int], vertices: np.ndarray) -> list[float]:
    """Per joint (upstream first), the most any vertex (world at the zero position) can be from its
    axis at any pose (the module's bound)."""

    def dist(p: np.ndarray, k: int) -> np.ndarray:
        return np.linalg.norm(np.cross(p - chain.point[k], chain.axis[k]), axis=-1)

    last = joints[-1]
    out = [float(dist(vertices, last).max())]
    if len(joints) == 2:
        o, u = chain.point[last], chain.axis[last]
        centre = (vertices.min(axis=0) + vertices.max(axis=0)) / 2
        on_axis = o + u * float(np.dot(centre - o, u))  # a point on the later axis, near the body
        out.insert(0, float(dist(on_axis, joints[0]) + np.linalg.norm(vertices - on_axis, axis=1).max()))
    return out


def certified_grid(apart: Callable, cross: Callable, chain: Chain, bodies: CollisionBodies, witnesses: WitnessGrid,
                   lower: np.ndarray, upper: np.ndarray, padding: float) -> CertifiedGrid:
    """The certified grids of every pair with a witness grid and revolute joints. ``apart(q, pair,
    limit, contain)`` gives 1 where the surfaces of pair ``pair[i]`` at ``q[i]`` are further apart
    than ``limit[i]`` (and with ``contain``, neither body contains the other); ``cross(q, pair,
    pairs, move, a_moves)`` 1 where one of the triangle pairs ``pairs[i]`` crosses beyond
    ``move[i]`` (``rswarp.kernels.witness.pierce_function``)."""
    pairs = len(bodies.pairs)
    grid = CertifiedGrid.none(pairs)
    plans = {p: plan for p in range(pairs) if (plan := _plan(chain, bodies, witnesses, p, lower, upper))}
    if not plans:
        return grid
    mid = np.where(np.isfinite(lower) & np.isfinite(upper), (lower + upper) / 2, 0.0)
    cells = 0
    for p, (cols, counts, *_) in plans.items():
        for k, (c, n) in enumerate(zip(cols, counts)):
            grid.res[2 * p + k], grid.scale[2 * p + k] = n, n / (upper[c] - lower[c])
        grid.start[p] = cells
        cells += int(np.prod(counts))
    value = np.zeros(cells, np.uint8)
    centres = {p: cell_centres(cols, counts, lower, upper, mid) for p, (cols, counts, *_) in plans.items()}
    apart_plans = {p: plan for p, plan in plans.items() if plan[3]}
    _apart_cells(apart, apart_plans, grid.start, value, centres, lower, upper, mid, padding)
    _uncontained(apart, apart_plans, grid.start, value, centres)
    _crossing_cells(cross, plans, grid.start, value, witnesses, centres)
    return CertifiedGrid(grid.start, grid.scale, grid.res, value)


def _apart_cells(apart, plans: dict, start: np.ndarray, value: np.ndarray, centres: dict, lower: np.ndarray,
                 upper: np.ndarray, mid: np.ndarray, padding: float) -> None:
    """Mark APART the cells whose centre is further apart than the bound, the padding and the
    margin. Blocks of BLOCK cells along each axis are asked first, as one cell: a block found apart
    holds its cells, so only the blocks near touching ask cell by cell."""
    asks = {p: cell_centres(cols, [n // BLOCK[len(cols)] for n in counts], lower, upper, mid)
            for p, (cols, counts, *_) in plans.items()}
    blocks = _ask(apart, asks, {p: BLOCK[len(plan[0])] * plan[2] + padding + MARGIN for p, plan in plans.items()})
    asks = {}
    for p, (cols, counts, *_) in plans.items():
        b = BLOCK[len(cols)]
        held = blocks[p].reshape([n // b for n in counts])
        for axis in range(len(counts)):
            held = np.repeat(held, b, axis=axis)  # each block's flag on its cells
        value[start[p]:start[p] + held.size] = held.ravel() * APART
        open_cells = np.nonzero(held.ravel() == 0)[0]
        asks[p] = (centres[p][open_cells], open_cells)
    found = _ask(apart, {p: q for p, (q, _) in asks.items()},
                 {p: plan[2] + padding + MARGIN for p, plan in plans.items()})
    for p, (_, open_cells) in asks.items():
        value[start[p] + open_cells] = found[p] * APART


def _crossing_cells(cross, plans: dict, start: np.ndarray, value: np.ndarray, witnesses: WitnessGrid,
                    centres: dict) -> None:
    """Mark CROSSING the cells where a witness of the coarse cell holding their centre crosses at
    the centre with margins beyond the bound and the margin."""
    qs, ps, tris, moves, movers, where = [], [], [], [], [], []
    index = witnesses.witness.reshape(-1, WITNESSES, 2)
    for p, (cols, _, disp, _, a_moves) in plans.items():
        q = centres[p]
        coarse = witnesses.start[p] + _witness_cells(witnesses, p, cols, q)
        ask = np.nonzero((index[coarse, 0, 0] >= 0) & (value[start[p]:start[p] + len(q)] == 0))[0]
        qs.append(q[ask])
        ps.append(np.full(len(ask), p, np.int32))
        tris.append(index[coarse[ask]].reshape(len(ask), 2 * WITNESSES))
        moves.append(np.full(len(ask), disp + MARGIN))
        movers.append(np.full(len(ask), int(a_moves), np.int32))
        where.append(start[p] + ask)
    if sum(len(q) for q in qs):
        found = cross(np.concatenate(qs), np.concatenate(ps), np.concatenate(tris), np.concatenate(moves),
                      np.concatenate(movers))
        value[np.concatenate(where)[found.astype(bool)]] = CROSSING


def _witness_cells(witnesses: WitnessGrid, p: int, cols: list[int], q: np.ndarray) -> np.ndarray:
    """(len(q),) the witness cell holding each configuration of pair p, as the kernel computes it."""
    cell = np.zeros(len(q), np.int64)
    for k, c in enumerate(cols):
        n = witnesses.res[2 * p + k]
        cell = cell * n + np.clip(((q[:, c] - witnesses.lo[2 * p + k]) * witnesses.scale[2 * p + k]).astype(np.int64),
                                  0, n - 1)
    return cell


def _uncontained(apart, plans: dict, start: np.ndarray, value: np.ndarray, centres: dict) -> None:
    """Clear the cells of every connected set found apart where one body contains the other (asked
    at the set's first cell)."""
    from scipy import ndimage

    asks, sets = {}, {}
    for p, (_, counts, *_) in plans.items():
        # sets of cells sharing a face
        labels, _ = ndimage.label(value[start[p]:start[p] + int(np.prod(counts))].reshape(counts))
        labels = labels.ravel()
        _, first = np.unique(labels, return_index=True)  # each set's first cell (label 0: not apart)
        asks[p] = centres[p][first[1:] if labels[first[0]] == 0 else first]
        sets[p] = labels
    inside = _ask(apart, asks, {p: 0.0 for p in plans}, contain=True)
    for p, labels in sets.items():
        contained = np.nonzero(inside[p] == 0)[0] + 1
        value[start[p] + np.nonzero(np.isin(labels, contained))[0]] = 0


def _ask(apart, qs: dict[int, np.ndarray], limit: dict[int, float], contain: bool = False) -> dict[int, np.ndarray]:
    """``apart`` of every pair's configurations at its limit, in one launch; per pair its flags."""
    order = [p for p in qs if len(qs[p])]
    out = {p: np.zeros(0, np.uint8) for p in qs}
    if not order:
        return out
    flags = apart(np.concatenate([qs[p] for p in order]),
                  np.concatenate([np.full(len(qs[p]), p, np.int32) for p in order]),
                  np.concatenate([np.full(len(qs[p]), limit[p]) for p in order]), contain).astype(np.uint8)
    for p, part in zip(order, np.split(flags, np.cumsum([len(qs[p]) for p in order])[:-1])):
        out[p] = part
    return out


def _plan(chain: Chain, bodies: CollisionBodies, witnesses: WitnessGrid, p: int, lower: np.ndarray,
          upper: np.ndarray) -> tuple[list[int], list[int], float, bool, bool] | None:
    """Pair p's certified grid: (its q columns in the witness grid's order, cells along each, the
    most a point moves from a cell's centre, whether APART cells are asked, whether the moving body
    is the pair's first), or None for no grid."""
    start = witnesses.start[p]
    if start < 0:
        return None
    cols = [int(c) for c in witnesses.col[2 * p:2 * p + 2] if c >= 0]
    n = int(np.prod(witnesses.res[2 * p:2 * p + len(cols)]))
    # APART cells only where they may pay and where the inside cannot change unseen (an open
    # mesh's winding number may, with no surface near)
    apart_ok = _crossing_share(witnesses, start, n) <= MOSTLY_CROSSING and \
        all(bodies.bodies[k].watertight for k in bodies.pairs[p])
    found = moving_joints(chain, bodies, p)
    if found is None:
        return None
    mover, joints = found
    if sorted(int(chain.qidx[k]) for k in joints) != sorted(cols):
        return None
    rho = dict(zip((int(chain.qidx[k]) for k in joints), reaches(chain, joints, bodies.bodies[mover].vertices)))
    reach = [float(upper[c] - lower[c]) * rho[c] for c in cols]  # how far each axis' whole range moves a point
    counts = _counts(reach)
    return cols, counts, sum(r / (2 * n) for r, n in zip(reach, counts)), apart_ok, mover == bodies.pairs[p][0]


def _counts(reach: list[float]) -> list[int]:
    """Cells along each axis, whole blocks of BLOCK, so each axis' half cell moves a point alike."""
    if len(reach) == 1:
        return [CERTIFIED_CELLS[1]]
    b, cells = BLOCK[2], CERTIFIED_CELLS[2]
    first = b * int(np.clip(round(np.sqrt(cells * reach[0] / max(reach[1], 1e-12)) / b), 1, cells // b ** 2))
    return [first, b * (cells // (first * b))]


def _crossing_share(witnesses: WitnessGrid, start: int, cells: int) -> float:
    """The share of a pair's witness cells that hold a witness (crossed at their centre)."""
    index = witnesses.witness.reshape(-1, WITNESSES, 2)[start:start + cells]
    return float((index[:, 0, 0] >= 0).mean()) if len(index) else 0.0
