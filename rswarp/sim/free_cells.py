"""Free cells (``rswarp.kernels.witness.free_function``): for each pair with a witness grid whose
joints are revolute, a finer grid over the same axes; a cell is certified free where the bodies are
further apart at its centre than the most any point of the moving body can travel within the cell,
plus the padding and a margin. The bodies are then apart at every pose of the cell, and the sweep
skips the walk of a pose in it; verdicts and gaps stay what the walk gives.

Containment is asked once per connected set of cells so found (at its first cell's centre): where
the surfaces stay apart, a closed body's inside cannot change, so neither can a piece's being in
it. Open meshes (inside by winding number) get no free grid.

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
from .bodies import CollisionBodies
from .witness import WitnessGrid

FREE_CELLS = {1: 1024, 2: 16384}  # cells of a pair's free grid, by the number of its joints
BLOCK = {1: 16, 2: 4}  # cells along each axis of the blocks asked first (``free_grid``)
# m: a certified cell keeps the bodies this much further apart than the padding, for the sweep's
# float32 poses and cell indices (errors of a micrometre)
MARGIN = 1e-4
# states a sweep needs before its free grids pay for their setup (a few hundredths of a second,
# against the 0.1 us or so a state they save on one core, ``benchmarks/bench_collisions.py``): a
# smaller sweep builds none
FREE_CELLS_PAY = 500_000
# a pair whose witnesses cross in more than this share of its cells mostly collides: no free grid
MOSTLY_CROSSING = 0.5


@dataclass(frozen=True)
class FreeGrid:
    """Every pair's free grid as the flat arrays of the ``BodyArrays`` struct (its axes are the
    witness grid's: ``WitnessGrid.col`` and ``lo``)."""

    start: np.ndarray  # (pairs,) int32: first cell, -1 for no grid
    scale: np.ndarray  # (2 * pairs,) cells per unit of q
    res: np.ndarray  # (2 * pairs,) int32 cells along each axis
    free: np.ndarray  # (cells,) uint8: 1 where certified free

    @staticmethod
    def none(pairs: int) -> "FreeGrid":
        return FreeGrid(np.full(pairs, -1, np.int32), np.zeros(2 * pairs), np.ones(2 * pairs, np.int32),
                        np.zeros(1, np.uint8))


def _above(chain: Chain, link: int) -> list[int]:
    out = []
    while link >= 0:
        out.append(link)
        link = int(chain.parent[link])
    return out


def moving_joints(chain: Chain, bodies: CollisionBodies, pair: int) -> tuple[int, list[int]] | None:
    """(the body the pair's joints move relative to the other, their links upstream first), or
    None unless each is a revolute joint driven by its own column (no loop, mimic or closed form)
    on one body's side."""
    a, b = bodies.pairs[pair]
    pa, pb = _above(chain, bodies.bodies[a].link), _above(chain, bodies.bodies[b].link)
    moving = set(pa) ^ set(pb)
    mover, path = (b, pb) if moving <= set(pb) else (a, pa) if moving <= set(pa) else (None, None)
    if mover is None:
        return None
    joints = [k for k in reversed(path) if k in moving and chain.qidx[k] >= 0]
    if any(k in moving and chain.qidx[k] < 0 and chain.jtype[k] != FIXED for k in path):
        return None  # a joint no column drives (a loop's passive joint)
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


def free_grid(apart: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray], chain: Chain,
              bodies: CollisionBodies, witnesses: WitnessGrid, lower: np.ndarray, upper: np.ndarray,
              padding: float) -> FreeGrid:
    """The free grids of every pair with a witness grid and revolute joints. ``apart(q, pair,
    limit, contain)`` gives 1 where the surfaces of pair ``pair[i]`` at ``q[i]`` are further apart
    than ``limit[i]`` (and with ``contain``, neither body contains the other). Blocks of BLOCK
    cells along each axis are asked first, as one cell: a block found apart holds its cells, so
    only the blocks near touching ask cell by cell."""
    pairs = len(bodies.pairs)
    grid = FreeGrid.none(pairs)
    plans = {p: plan for p in range(pairs) if (plan := _plan(chain, bodies, witnesses, p, lower, upper))}
    if not plans:
        return grid
    mid = np.where(np.isfinite(lower) & np.isfinite(upper), (lower + upper) / 2, 0.0)
    cells = 0
    for p, (cols, counts, _) in plans.items():
        for k, (c, n) in enumerate(zip(cols, counts)):
            grid.res[2 * p + k], grid.scale[2 * p + k] = n, n / (upper[c] - lower[c])
        grid.start[p] = cells
        cells += int(np.prod(counts))
    free = np.zeros(cells, np.uint8)
    asks = {p: _centres(cols, [n // BLOCK[len(cols)] for n in counts], lower, upper, mid)
            for p, (cols, counts, _) in plans.items()}
    blocks = _ask(apart, asks, {p: BLOCK[len(cols)] * disp + padding + MARGIN for p, (cols, _, disp) in plans.items()})
    asks = {}
    for p, (cols, counts, _) in plans.items():
        b = BLOCK[len(cols)]
        held = blocks[p].reshape([n // b for n in counts])
        for axis in range(len(counts)):
            held = np.repeat(held, b, axis=axis)  # each block's flag on its cells
        free[grid.start[p]:grid.start[p] + held.size] = held.ravel()
        open_cells = np.nonzero(held.ravel() == 0)[0]
        asks[p] = (_centres(cols, counts, lower, upper, mid)[open_cells], open_cells)
    found = _ask(apart, {p: q for p, (q, _) in asks.items()},
                 {p: disp + padding + MARGIN for p, (_, _, disp) in plans.items()})
    for p, (_, open_cells) in asks.items():
        free[grid.start[p] + open_cells] = found[p]
    _uncontained(apart, plans, grid.start, free, lower, upper, mid)
    return FreeGrid(grid.start, grid.scale, grid.res, free)


def _uncontained(apart, plans: dict, start: np.ndarray, free: np.ndarray, lower: np.ndarray, upper: np.ndarray,
                 mid: np.ndarray) -> None:
    """Clear the cells of every connected set found apart where one body contains the other (asked
    at the set's first cell)."""
    from scipy import ndimage

    asks, sets = {}, {}
    for p, (cols, counts, _) in plans.items():
        flags = free[start[p]:start[p] + int(np.prod(counts))].reshape(counts)
        labels, n = ndimage.label(flags)  # sets of cells sharing a face
        first = np.array([np.flatnonzero(labels.ravel() == k + 1)[0] for k in range(n)], np.int64)
        asks[p] = _centres(cols, counts, lower, upper, mid)[first]
        sets[p] = labels.ravel()
    inside = _ask(apart, asks, {p: 0.0 for p in plans}, contain=True)
    for p, labels in sets.items():
        contained = np.nonzero(inside[p] == 0)[0] + 1
        free[start[p] + np.nonzero(np.isin(labels, contained))[0]] = 0


def _centres(cols: list[int], counts: list[int], lower: np.ndarray, upper: np.ndarray,
             mid: np.ndarray) -> np.ndarray:
    """The configurations at the centres of a grid's cells, row-major (the kernel's cell index)."""
    centres = [lower[c] + (np.arange(n) + 0.5) * (upper[c] - lower[c]) / n for c, n in zip(cols, counts)]
    q = np.tile(mid, (int(np.prod(counts)), 1))
    for c, axis in zip(cols, np.meshgrid(*centres, indexing="ij")):
        q[:, c] = axis.ravel()
    return q


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
          upper: np.ndarray) -> tuple[list[int], list[int], float] | None:
    """Pair p's free grid: (its q columns in the witness grid's order, cells along each, the most a
    point moves from a cell's centre), or None for no grid."""
    start = witnesses.start[p]
    if start < 0:
        return None
    cols = [int(c) for c in witnesses.col[2 * p:2 * p + 2] if c >= 0]
    n = int(np.prod(witnesses.res[2 * p:2 * p + len(cols)]))
    if _crossing_share(witnesses, start, n) > MOSTLY_CROSSING:
        return None
    if not all(bodies.bodies[k].watertight for k in bodies.pairs[p]):
        return None  # an open mesh's inside (its winding number) may change with no surface near
    found = moving_joints(chain, bodies, p)
    if found is None:
        return None
    mover, joints = found
    if sorted(int(chain.qidx[k]) for k in joints) != sorted(cols):
        return None
    rho = dict(zip((int(chain.qidx[k]) for k in joints), reaches(chain, joints, bodies.bodies[mover].vertices)))
    reach = [float(upper[c] - lower[c]) * rho[c] for c in cols]  # how far each axis' whole range moves a point
    counts = _counts(reach)
    return cols, counts, sum(r / (2 * n) for r, n in zip(reach, counts))


def _counts(reach: list[float]) -> list[int]:
    """Cells along each axis, whole blocks of BLOCK, so each axis' half cell moves a point alike."""
    if len(reach) == 1:
        return [FREE_CELLS[1]]
    b, cells = BLOCK[2], FREE_CELLS[2]
    first = b * int(np.clip(round(np.sqrt(cells * reach[0] / max(reach[1], 1e-12)) / b), 1, cells // b ** 2))
    return [first, b * (cells // (first * b))]


def _crossing_share(witnesses: WitnessGrid, start: int, cells: int) -> float:
    """The share of a pair's witness cells that hold a witness (crossed at their centre)."""
    index = witnesses.witness.reshape(-1, WITNESSES, 2)[start:start + cells]
    return float((index[:, 0, 0] >= 0).mean()) if len(index) else 0.0
