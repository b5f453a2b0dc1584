"""The crossing walk four boxes at a time, as device code: a node pair opens the larger node two
levels down (its record, ``Node.quad``), and the other node's box is tested against those four at
once, lane by lane (Gottschalk's fifteen axes each), where a binary walk takes two pops and up to
six tests one at a time. The boxes that overlap are walked nearest centres first: there crossing
triangles are likeliest, and a walk that finds one stops. The leaves decide, as in ``tree``: the
boxes only skip work."""

from typing import Any

import warp as wp

from .cache import cached
from .geometry import EPS_AXIS
from .tree import leaf_function, opening_function
from .types import QUAD, bodies_struct, types_of

# node pairs the walk keeps pending: each step goes two levels down one tree and leaves at most three
# more, so two balanced trees of depth 40 need at most 1 + 3 * 40
QUAD_STACK = 124


@cached
def lane_types(scalar=wp.float32):
    """(V4, L2): four lanes of one number; of two (a key and a gap per box)."""
    return wp.types.vector(QUAD, scalar), wp.types.matrix((2, QUAD), scalar)


@cached
def lane_functions(scalar=wp.float32):
    """(along, spread, edge_axis): the box test's steps, four lanes at a time."""
    S, V3, M33, M34, M44 = types_of(scalar)
    V4, _ = lane_types(scalar)

    @wp.func
    def along(x: V4, y: V4, z: V4, u: V3) -> V4:
        """x u0 + y u1 + z u2: a vector's component along each box's axis (x, y, z its lanes)."""
        return x * u[0] + y * u[1] + z * u[2]

    @wp.func
    def spread(x: V4) -> V4:
        """|x| + eps, as ``box_gap`` takes it: parallel edges never part boxes that touch."""
        return wp.abs(x) + V4(S(EPS_AXIS))

    @wp.func
    def edge_axis(da: V4, ra: V4, db: V4, rb: V4, ea: V4, aa: V4, eb: V4, ab: V4, h1: S, a1: V4, h2: S, a2: V4,
                  rij: V4) -> V4:
        """Positive where the axis A_i x B_j parts the boxes (``cross_gap``'s test, its terms passed
        in) and is not degenerate (|A_i x B_j|^2 > 1e-6)."""
        g = wp.abs(wp.cw_mul(da, ra) - wp.cw_mul(db, rb)) - wp.cw_mul(ea, aa) - wp.cw_mul(eb, ab) - a1 * h1 - a2 * h2
        return wp.min(g, V4(S(1.0 - 1.0e-6)) - wp.cw_mul(rij, rij))

    return along, spread, edge_axis


@cached
def quad_gap_function(scalar=wp.float32):
    """quad_gaps(m, k, rq, cq, hq): record k's four boxes against one box."""
    S, V3, M33, M34, M44 = types_of(scalar)
    V4, L2 = lane_types(scalar)
    along, spread, edge_axis = lane_functions(scalar)
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def quad_gaps(m: BodyArrays, k: int, rq: M33, cq: V3, hq: V3) -> L2:
        """Record k's four boxes against one box (axes ``rq`` as columns, centre ``cq``, half-sizes
        ``hq``, in the four's body frame). Row 0: the squared distance of the centres (the order of
        the walk); row 1: positive where one of the fifteen axes parts them (``box_gap``'s test).
        Written out lane vector by lane vector (r01: the other box's axis 1 along each box's axis 0)."""
        x0, y0, z0 = m.quad_axes[k, 0], m.quad_axes[k, 3], m.quad_axes[k, 6]
        x1, y1, z1 = m.quad_axes[k, 1], m.quad_axes[k, 4], m.quad_axes[k, 7]
        x2, y2, z2 = m.quad_axes[k, 2], m.quad_axes[k, 5], m.quad_axes[k, 8]
        c0 = V4(cq[0]) - m.quad_center[k, 0]
        c1 = V4(cq[1]) - m.quad_center[k, 1]
        c2 = V4(cq[2]) - m.quad_center[k, 2]
        d0 = wp.cw_mul(x0, c0) + wp.cw_mul(y0, c1) + wp.cw_mul(z0, c2)
        d1 = wp.cw_mul(x1, c0) + wp.cw_mul(y1, c1) + wp.cw_mul(z1, c2)
        d2 = wp.cw_mul(x2, c0) + wp.cw_mul(y2, c1) + wp.cw_mul(z2, c2)
        u0 = V3(rq[0, 0], rq[1, 0], rq[2, 0])
        u1 = V3(rq[0, 1], rq[1, 1], rq[2, 1])
        u2 = V3(rq[0, 2], rq[1, 2], rq[2, 2])
        r00, r01, r02 = along(x0, y0, z0, u0), along(x0, y0, z0, u1), along(x0, y0, z0, u2)
        r10, r11, r12 = along(x1, y1, z1, u0), along(x1, y1, z1, u1), along(x1, y1, z1, u2)
        r20, r21, r22 = along(x2, y2, z2, u0), along(x2, y2, z2, u1), along(x2, y2, z2, u2)
        a00, a01, a02 = spread(r00), spread(r01), spread(r02)
        a10, a11, a12 = spread(r10), spread(r11), spread(r12)
        a20, a21, a22 = spread(r20), spread(r21), spread(r22)
        e0, e1, e2 = m.quad_half[k, 0], m.quad_half[k, 1], m.quad_half[k, 2]
        # the six face axes: each box's, then the other box's
        worst = wp.max(wp.max(wp.abs(d0) - e0 - along(a00, a01, a02, hq), wp.abs(d1) - e1 - along(a10, a11, a12, hq)),
                       wp.abs(d2) - e2 - along(a20, a21, a22, hq))
        fb0 = wp.abs(wp.cw_mul(r00, d0) + wp.cw_mul(r10, d1) + wp.cw_mul(r20, d2)) - V4(hq[0]) - (
            wp.cw_mul(a00, e0) + wp.cw_mul(a10, e1) + wp.cw_mul(a20, e2))
        fb1 = wp.abs(wp.cw_mul(r01, d0) + wp.cw_mul(r11, d1) + wp.cw_mul(r21, d2)) - V4(hq[1]) - (
            wp.cw_mul(a01, e0) + wp.cw_mul(a11, e1) + wp.cw_mul(a21, e2))
        fb2 = wp.abs(wp.cw_mul(r02, d0) + wp.cw_mul(r12, d1) + wp.cw_mul(r22, d2)) - V4(hq[2]) - (
            wp.cw_mul(a02, e0) + wp.cw_mul(a12, e1) + wp.cw_mul(a22, e2))
        worst = wp.max(worst, wp.max(fb0, wp.max(fb1, fb2)))
        # the nine edge axes A_i x B_j
        apart = wp.max(worst, edge_axis(d2, r10, d1, r20, e1, a20, e2, a10, hq[1], a02, hq[2], a01, r00))
        apart = wp.max(apart, edge_axis(d2, r11, d1, r21, e1, a21, e2, a11, hq[2], a00, hq[0], a02, r01))
        apart = wp.max(apart, edge_axis(d2, r12, d1, r22, e1, a22, e2, a12, hq[0], a01, hq[1], a00, r02))
        apart = wp.max(apart, edge_axis(d0, r20, d2, r00, e2, a00, e0, a20, hq[1], a12, hq[2], a11, r10))
        apart = wp.max(apart, edge_axis(d0, r21, d2, r01, e2, a01, e0, a21, hq[2], a10, hq[0], a12, r11))
        apart = wp.max(apart, edge_axis(d0, r22, d2, r02, e2, a02, e0, a22, hq[0], a11, hq[1], a10, r12))
        apart = wp.max(apart, edge_axis(d1, r00, d0, r10, e0, a10, e1, a00, hq[1], a22, hq[2], a21, r20))
        apart = wp.max(apart, edge_axis(d1, r01, d0, r11, e0, a11, e1, a01, hq[2], a20, hq[0], a22, r21))
        apart = wp.max(apart, edge_axis(d1, r02, d0, r12, e0, a12, e1, a02, hq[0], a21, hq[1], a20, r22))
        return wp.matrix_from_rows(wp.cw_mul(d0, d0) + wp.cw_mul(d1, d1) + wp.cw_mul(d2, d2), apart)

    return quad_gaps


@cached
def push_function(scalar=wp.float32):
    """pushed(stack, top, g, slots, na, nb, on_a): the pairs a step of the walk leaves pending."""
    S = scalar
    _, L2 = lane_types(scalar)
    SL = wp.types.vector(QUAD, wp.int32)

    @wp.func
    def pushed(stack: Any, top: int, g: L2, slots: SL, na: int, nb: int, on_a: bool) -> int:
        """The overlapping boxes' node pairs pushed, the nearest last (on top); returns the new top.
        (Kept as a selection: ranks computed without branches, each pair stored where its rank puts
        it, ran slower in a trial.)"""
        key = g[0]
        live = SL()
        count = int(0)
        for j in range(QUAD):
            live[j] = wp.where(g[1][j] <= S(0.0), 1, 0) * wp.where(slots[j] >= 0, 1, 0)
            count += live[j]
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

    return pushed


@cached
def quad_walk(scalar=wp.float32):
    """meshes_cross(m, a, b, r, t): whether the surfaces of bodies a and b cross (x_A = r x_B + t),
    the boxes four at a time."""
    S, V3, M33, M34, M44 = types_of(scalar)
    _, L2 = lane_types(scalar)
    quad_gaps = quad_gap_function(scalar)
    opens_a = opening_function(scalar)
    pushed = push_function(scalar)
    leaf_distance = leaf_function(scalar)
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def meshes_cross(m: BodyArrays, a: int, b: int, r: M33, t: V3) -> bool:
        """Depth first, the nearer boxes first; the boxes of the roots are known to overlap."""
        stack = wp.zeros(shape=wp.static(2 * QUAD_STACK), dtype=wp.int32)
        stack[0] = m.root[a]
        stack[1] = m.root[b]
        top = int(1)
        rt = wp.transpose(r)
        while top > 0:
            top -= 1
            na = stack[2 * top]
            nb = stack[2 * top + 1]
            if m.nodes[na].left < 0 and m.nodes[nb].left < 0:
                if leaf_distance(m, na, nb, r, t, True) <= S(0.0):
                    return True
                continue
            if top + QUAD > QUAD_STACK:  # cannot happen for trees of bvh.MAX_DEPTH; never a silent miss
                return True
            on_a = opens_a(m, na, nb)
            g = L2()
            k = int(0)
            if on_a:  # B's box carried into A's frame, against A's four
                k = m.nodes[na].quad
                g = quad_gaps(m, k, r * m.nodes[nb].axes, r * m.nodes[nb].center + t, m.nodes[nb].half)
            else:  # A's box carried into B's frame
                k = m.nodes[nb].quad
                g = quad_gaps(m, k, rt * m.nodes[na].axes, rt * (m.nodes[na].center - t), m.nodes[na].half)
            top = pushed(stack, top, g, m.quad_slot[k], na, nb, on_a)
        return False

    return meshes_cross
