"""Witness grids, as device code: before walking two bodies' trees, try the triangle pairs that
crossed at the centre of the configuration's cell. A crossing found so is a verdict as exact as
any (two triangles that meet); a miss costs a few triangle tests and the walk goes on as before.

It pays for pairs that collide often and whose relative pose depends on one or two joints (a
wrist that always overlaps its forearm, say): the walk that finds a first crossing opens dozens
of node pairs, the witnesses of a cell a few triangles.

The same pairs also have a finer grid of free cells (``certified_free``): a cell where the bodies
stay further apart than the padding at every pose in it (the host's bound: their distance at the
cell's centre less the most any point can move within the cell). A pose in one is free with no
walk, as the walk would have found it; it pays for pairs that pass near without touching (a
lower arm swinging past its base), whose walks must open every node pair to find nothing."""


import warp as wp

from .cache import cached
from .geometry import triangle_functions
from .types import bodies_struct, types_of


@cached
def witness_functions(scalar=wp.float32):
    """(witness_cell, witness_hit): the cell of pair p at q[i] (-1: the pair has no grid), and
    whether one of the cell's witnesses crosses at x_A = r x_B + t."""
    S, V3, M33, M34, M44 = types_of(scalar)
    triangles_cross, _ = triangle_functions(scalar)
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def witness_cell(m: BodyArrays, p: int, q: wp.array2d(dtype=S), i: int) -> int:
        start = m.cell_start[p]
        if start < 0:
            return -1
        cell = int(0)
        for k in range(2 * p, 2 * p + 2):
            col = m.cell_col[k]
            if col >= 0:
                c = int((q[i, col] - m.cell_lo[k]) * m.cell_scale[k])
                cell = cell * m.cell_res[k] + wp.clamp(c, 0, m.cell_res[k] - 1)
        return start + cell

    @wp.func
    def witness_hit(m: BodyArrays, cell: int, r: M33, t: V3) -> bool:
        cells = m.cell_count.shape[0]
        for w in range(m.cell_count[cell]):
            k = 6 * (w * cells + cell)
            if triangles_cross(m.witness[k], m.witness[k + 1], m.witness[k + 2], r * m.witness[k + 3] + t,
                               r * m.witness[k + 4] + t, r * m.witness[k + 5] + t):
                return True
        return False

    return witness_cell, witness_hit


@cached
def free_function(scalar=wp.float32):
    """certified_free(m, p, q, i): whether pair p at q[i] lies in a certified free cell of its grid
    (never for a pose outside the grid: no cell is clamped to hold it)."""
    S = types_of(scalar)[0]
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def certified_free(m: BodyArrays, p: int, q: wp.array2d(dtype=S), i: int) -> bool:
        start = m.free_start[p]
        if start < 0:
            return False
        cell = int(0)
        for k in range(2 * p, 2 * p + 2):
            col = m.cell_col[k]
            if col >= 0:
                x = (q[i, col] - m.cell_lo[k]) * m.free_scale[k]
                if not (x >= S(0.0) and x < S(m.free_res[k])):
                    return False
                cell = cell * m.free_res[k] + int(x)
        return m.free[start + cell] != wp.uint8(0)

    return certified_free
