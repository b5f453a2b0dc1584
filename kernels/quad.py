"""The crossing walk four boxes at a time, as device code: a node pair opens the larger node two
levels down (``BodyArrays.quad``), and the other node's box is tested against those four at once,
lane by lane (Gottschalk's fifteen axes each), where the binary walk took two pops and up to six
tests one at a time. The leaves decide, as in ``tree``: the boxes only skip work."""

from typing import Any

import warp as wp

from .cache import cached
from .geometry import EPS_AXIS
from .tree import STACK, leaf_function
from .types import QUAD, bodies_struct, types_of


@cached
def lane_types(scalar=wp.float32):
    """(V4, M34L, M94L): four lanes of one number, of a vector, of a 3 x 3 matrix (row after row)."""
    return (wp.types.vector(QUAD, scalar), wp.types.matrix((3, QUAD), scalar), wp.types.matrix((9, QUAD), scalar))


@cached
def quad_gap_function(scalar=wp.float32):
    """quad_gaps(m, k, rq, cq, hq): record k's four boxes against one box."""
    S, V3, M33, M34, M44 = types_of(scalar)
    V4, L3, L9 = lane_types(scalar)
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def carried(m: BodyArrays, k: int, rq: M33, cq: V3) -> L9:
        """The other box's axes in each box's frame (rows 3 i + j: box axis i against its axis j)."""
        rr = L9()
        for i in range(3):
            x = m.quad_axes[k, i]
            y = m.quad_axes[k, 3 + i]
            z = m.quad_axes[k, 6 + i]
            for j in range(3):
                rr[3 * i + j] = x * rq[0, j] + y * rq[1, j] + z * rq[2, j]
        return rr

    @wp.func
    def offset(m: BodyArrays, k: int, cq: V3) -> L3:
        """The other box's centre in each box's frame."""
        c0 = V4(cq[0]) - m.quad_center[k, 0]
        c1 = V4(cq[1]) - m.quad_center[k, 1]
        c2 = V4(cq[2]) - m.quad_center[k, 2]
        d = L3()
        for i in range(3):
            d[i] = wp.cw_mul(m.quad_axes[k, i], c0) + wp.cw_mul(m.quad_axes[k, 3 + i], c1) + wp.cw_mul(
                m.quad_axes[k, 6 + i], c2)
        return d

    @wp.func
    def quad_gaps(m: BodyArrays, k: int, rq: M33, cq: V3, hq: V3) -> L3:
        """Record k's four boxes against one box (axes ``rq`` as columns, centre ``cq``, half-sizes
        ``hq``, in the four's body frame). Row 0: the face axes' gap of each (as ``box_gap`` gives
        it: it orders overlapping pairs); row 1: positive where one of the fifteen axes parts them."""
        rr = carried(m, k, rq, cq)
        d = offset(m, k, cq)
        e = wp.matrix_from_rows(m.quad_half[k, 0], m.quad_half[k, 1], m.quad_half[k, 2])
        ar = L9()
        for n in range(9):
            ar[n] = wp.abs(rr[n]) + V4(S(EPS_AXIS))
        worst = V4(S(-1.0e30))
        for i in range(3):
            ga = wp.abs(d[i]) - e[i] - (ar[3 * i] * hq[0] + ar[3 * i + 1] * hq[1] + ar[3 * i + 2] * hq[2])
            db = wp.cw_mul(rr[i], d[0]) + wp.cw_mul(rr[3 + i], d[1]) + wp.cw_mul(rr[6 + i], d[2])
            fa = wp.cw_mul(ar[i], e[0]) + wp.cw_mul(ar[3 + i], e[1]) + wp.cw_mul(ar[6 + i], e[2])
            worst = wp.max(worst, wp.max(ga, wp.abs(db) - fa - V4(hq[i])))
        apart = worst
        for i in range(3):
            i1 = (i + 1) % 3
            i2 = (i + 2) % 3
            for j in range(3):
                j1 = (j + 1) % 3
                j2 = (j + 2) % 3
                ra = wp.cw_mul(e[i1], ar[3 * i2 + j]) + wp.cw_mul(e[i2], ar[3 * i1 + j])
                rb = ar[3 * i + j2] * hq[j1] + ar[3 * i + j1] * hq[j2]
                g = wp.abs(wp.cw_mul(d[i2], rr[3 * i1 + j]) - wp.cw_mul(d[i1], rr[3 * i2 + j])) - ra - rb
                # the axis A_i x B_j parts them where g > 0 and it is not degenerate (|A_i x B_j|^2 > 1e-6)
                n2 = V4(S(1.0 - 1.0e-6)) - wp.cw_mul(rr[3 * i + j], rr[3 * i + j])
                apart = wp.max(apart, wp.min(g, n2))
        return wp.matrix_from_rows(worst, apart, V4())

    return quad_gaps


@cached
def quad_walk(scalar=wp.float32):
    """meshes_cross(m, a, b, r, t): whether the surfaces of bodies a and b cross (x_A = r x_B + t),
    the boxes four at a time."""
    S, V3, M33, M34, M44 = types_of(scalar)
    V4, L3, _ = lane_types(scalar)
    SL = wp.types.vector(QUAD, wp.int32)
    quad_gaps = quad_gap_function(scalar)
    leaf_distance = leaf_function(scalar)
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def opens_a(m: BodyArrays, na: int, nb: int) -> bool:
        """Whether the walk opens A's node (the larger, unless it is a leaf) rather than B's."""
        ha = m.node_half[na]
        hb = m.node_half[nb]
        return m.node_left[nb] < 0 or (m.node_left[na] >= 0 and ha[0] + ha[1] + ha[2] >= hb[0] + hb[1] + hb[2])

    @wp.func
    def pushed(stack: Any, top: int, g: L3, slots: SL, na: int, nb: int, on_a: bool) -> int:
        """The overlapping boxes' node pairs pushed, the most overlapping last (on top); returns
        the new top."""
        key = g[0]
        live = SL()
        count = int(0)
        for j in range(QUAD):
            if g[1][j] <= S(0.0) and slots[j] >= 0:
                live[j] = 1
                count += 1
        for n in range(count):
            best = int(-1)
            for j in range(QUAD):
                if live[j] != 0 and (best < 0 or key[j] > key[best]):
                    best = j
            live[best] = 0
            if on_a:
                stack[2 * (top + n)] = slots[best]
                stack[2 * (top + n) + 1] = nb
            else:
                stack[2 * (top + n)] = na
                stack[2 * (top + n) + 1] = slots[best]
        return top + count

    @wp.func
    def meshes_cross(m: BodyArrays, a: int, b: int, r: M33, t: V3) -> bool:
        """Depth first, the more overlapping boxes first; the boxes of the roots are known to
        overlap."""
        stack = wp.zeros(shape=wp.static(2 * STACK), dtype=wp.int32)
        stack[0] = m.root[a]
        stack[1] = m.root[b]
        top = int(1)
        rt = wp.transpose(r)
        while top > 0:
            top -= 1
            na = stack[2 * top]
            nb = stack[2 * top + 1]
            if m.node_left[na] < 0 and m.node_left[nb] < 0:
                if leaf_distance(m, na, nb, r, t, True) <= S(0.0):
                    return True
                continue
            if top + QUAD > STACK:  # cannot happen for trees of bvh.MAX_DEPTH; never a silent miss
                return True
            on_a = opens_a(m, na, nb)
            g = L3()
            k = int(0)
            if on_a:  # B's box carried into A's frame, against A's four
                k = m.quad[na]
                g = quad_gaps(m, k, r * m.node_axes[nb], r * m.node_center[nb] + t, m.node_half[nb])
            else:  # A's box carried into B's frame
                k = m.quad[nb]
                g = quad_gaps(m, k, rt * m.node_axes[na], rt * (m.node_center[na] - t), m.node_half[na])
            top = pushed(stack, top, g, m.quad_slot[k], na, nb, on_a)
        return False

    return meshes_cross
