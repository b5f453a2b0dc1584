"""Witness grids, as device code: before walking two bodies' trees, try the triangle pairs that
crossed at the centre of the configuration's cell. A crossing found so is a verdict as exact as
any (two triangles that meet); a miss costs a few triangle tests and the walk goes on as before.

It pays for pairs that collide often and whose relative pose depends on one or two joints (a
wrist that always overlaps its forearm, say): the walk that finds a first crossing opens dozens
of node pairs, the witnesses of a cell a few triangles.

The same pairs also have a finer grid of certified cells (``certified``). APART: the bodies stay
further apart than the padding at every pose in it (the host's bound: their distance at the
cell's centre less the most any point can move within the cell); a pose in one is free with no
walk, as the walk would have found it. It pays for pairs that pass near without touching (a lower
arm swinging past its base), whose walks must open every node pair to find nothing. CROSSING: an
edge of one body pierces a triangle of the other at the centre with margins beyond that bound
(``pierced``), so they cross at every pose in it; a pose in one collides with no triangle test.
It pays for pairs that always overlap (a wrist and its forearm)."""


import warp as wp

from .cache import cached
from .geometry import triangle_functions
from .quad import crossing_walk
from .types import bodies_struct, types_of


@cached
def grid_function(scalar=wp.float32):
    """grid_cell(m, p, q, i, scale, res, clamp): the row-major cell of q[i] in a grid over pair p's
    axes (``cell_col``, from ``cell_lo``), ``scale`` cells a unit and ``res`` along each; a pose
    outside it is clamped to the nearest cell, or with no ``clamp`` gives -1."""
    S = types_of(scalar)[0]
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def grid_cell(m: BodyArrays, p: int, q: wp.array2d(dtype=S), i: int, scale: wp.array(dtype=S),
                  res: wp.array(dtype=wp.int32), clamp: bool) -> int:
        cell = int(0)
        for k in range(2 * p, 2 * p + 2):
            col = m.cell_col[k]
            if col >= 0:
                x = (q[i, col] - m.cell_lo[k]) * scale[k]
                c = wp.clamp(int(x), 0, res[k] - 1)
                if not clamp and not (x >= S(0.0) and x < S(res[k])):
                    return -1
                cell = cell * res[k] + c
        return cell

    return grid_cell


@cached
def witness_functions(scalar=wp.float32):
    """(witness_cell, witness_hit): the cell of pair p at q[i] (-1: the pair has no grid), and
    whether one of the cell's witnesses crosses at x_A = r x_B + t."""
    S, V3, M33, M34, M44 = types_of(scalar)
    triangles_cross, _ = triangle_functions(scalar)
    grid_cell = grid_function(scalar)
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def witness_cell(m: BodyArrays, p: int, q: wp.array2d(dtype=S), i: int) -> int:
        start = m.cell_start[p]
        if start < 0:
            return -1
        return start + grid_cell(m, p, q, i, m.cell_scale, m.cell_res, True)

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


APART, CROSSING = 1, 2  # a certified cell's value: the bodies apart, or crossing, at every pose in it


@cached
def certified_function(scalar=wp.float32):
    """certified(m, p, q, i): what pair p's certified cell holding q[i] says: APART, CROSSING, or 0
    (none, or a pose outside the grid: no cell is clamped to hold it)."""
    S = types_of(scalar)[0]
    grid_cell = grid_function(scalar)
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def certified(m: BodyArrays, p: int, q: wp.array2d(dtype=S), i: int) -> int:
        start = m.cert_start[p]
        if start < 0:
            return 0
        cell = grid_cell(m, p, q, i, m.cert_scale, m.cert_res, False)
        if cell < 0:
            return 0
        return int(m.cert[start + cell])

    return certified


@cached
def pierce_function(scalar=wp.float64):
    """pierced(a0, a1, a2, p, q, move): whether segment pq passes through triangle a0 a1 a2 so that it
    still does when each of its ends moves by up to ``move`` (the triangle fixed): both ends further
    than ``move`` from its plane, on either side, and the crossing point further inside every edge
    than it can slide (``move``, plus the crossing's travel along pq: its parameter moves by at most
    ``move`` over the ends' separation across the plane)."""
    S, V3, M33, M34, M44 = types_of(scalar)

    @wp.func
    def inside_by(a0: V3, a1: V3, a2: V3, n: V3, x: V3) -> S:
        """The least in-plane distance from x to the triangle's edge lines, positive inside (n the
        unit normal of a0 a1 a2 counter-clockwise)."""
        d0 = wp.dot(x - a0, wp.normalize(wp.cross(n, a1 - a0)))
        d1 = wp.dot(x - a1, wp.normalize(wp.cross(n, a2 - a1)))
        d2 = wp.dot(x - a2, wp.normalize(wp.cross(n, a0 - a2)))
        return wp.min(d0, wp.min(d1, d2))

    @wp.func
    def pierced(a0: V3, a1: V3, a2: V3, p: V3, q: V3, move: S) -> bool:
        n = wp.cross(a1 - a0, a2 - a0)
        area = wp.length(n)
        if not (area > S(0.0)):
            return False
        n = n / area
        sp = wp.dot(p - a0, n)
        sq = wp.dot(q - a0, n)
        if sp < S(0.0):
            sp = -sp
            sq = -sq
        if not (sp > move and sq < -move):
            return False
        across = sp - sq
        x = p + (sp / across) * (q - p)
        return inside_by(a0, a1, a2, n, x) > move + move / across * wp.length(q - p)

    return pierced


@cached
def first_crossing_function(scalar=wp.float32):
    """first_triangles(m, p, rel): the triangles (A's, B's; -1 where none cross) at which the
    sweep's walk of pair p first finds a crossing, B's frame in A's being ``rel``: what a pair's
    usual crossings are drawn from (``sim.witness``)."""
    S, V3, M33, M34, M44 = types_of(scalar)
    BodyArrays = bodies_struct(scalar)
    first_crossing = crossing_walk(scalar)

    @wp.func
    def first_triangles(m: BodyArrays, p: int, rel: M34) -> wp.vec2i:
        r = M33(rel[0, 0], rel[0, 1], rel[0, 2], rel[1, 0], rel[1, 1], rel[1, 2], rel[2, 0], rel[2, 1], rel[2, 2])
        leaves = first_crossing(m, m.pair_a[p], m.pair_b[p], r, V3(rel[0, 3], rel[1, 3], rel[2, 3]))
        if leaves[0] < 0:
            return wp.vec2i(-1, -1)
        return wp.vec2i(-1 - m.nodes[leaves[0]].left, -1 - m.nodes[leaves[1]].left)  # a leaf's (first) triangle

    return first_triangles
