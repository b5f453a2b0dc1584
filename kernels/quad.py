"""The crossing walk four boxes at a time, as device code: a node pair opens the larger node two
levels down (its record, ``Node.quad``), and the other node's box is tested against those four at
once, lane by lane (Gottschalk's fifteen axes each), where a binary walk takes two pops and up to
six tests one at a time. The boxes that overlap are walked nearest centres first: there crossing
triangles are likeliest, and a walk that finds one stops. The leaves decide, as in ``tree``: the
boxes only skip work."""

from typing import Any

import warp as wp

from .cache import cached
from .geometry import EPS_AXIS, triangle_functions
from .tree import leaf_function, opening_function
from .types import QUAD, bodies_struct, types_of

# node pairs the walk keeps pending: each step goes two levels down one tree and leaves at most three
# more, so two balanced trees of depth 40 need at most 1 + 3 * 40
QUAD_STACK = 124


@cached
def lane_types(scalar=wp.float32):
    """(V4, L2): four lanes of one number; of two (a key and a gap per box)."""
    return wp.types.vector(QUAD, scalar), wp.types.matrix((2, QUAD), scalar)


# One box against four, lane by lane (Gottschalk's fifteen axes each, no square roots), as a native
# snippet: Warp's vectors of four do not become SIMD (each lane was its own scalar instruction, and
# its max a pair of compares for NaN), where clang's vector types make each step one instruction.
# Under clang (Warp's CPU compiler) the four lanes are one vector; any other compiler (CUDA's), or
# RSW_LANES_LOOP, loops over them. Either way each lane takes the same operations in the same
# order, and max and min are Warp's (the other operand where one is NaN), so the two agree bit for
# bit (``tests/test_quad_lanes.py``). Row 0 of the result: the centres' squared distance (the walk's
# order); row 1: positive where an axis parts the boxes (``box_gap``'s test). ``r01``: the other
# box's axis 1 along each box's axis 0; ``a``: its absolute value and EPS_AXIS.
_QUAD_EXPR = r"""
T d0 = x0 * c0 + y0 * c1 + z0 * c2;
T d1 = x1 * c0 + y1 * c1 + z1 * c2;
T d2 = x2 * c0 + y2 * c1 + z2 * c2;
T r00 = x0 * u[0][0] + y0 * u[1][0] + z0 * u[2][0], r01 = x0 * u[0][1] + y0 * u[1][1] + z0 * u[2][1];
T r02 = x0 * u[0][2] + y0 * u[1][2] + z0 * u[2][2];
T r10 = x1 * u[0][0] + y1 * u[1][0] + z1 * u[2][0], r11 = x1 * u[0][1] + y1 * u[1][1] + z1 * u[2][1];
T r12 = x1 * u[0][2] + y1 * u[1][2] + z1 * u[2][2];
T r20 = x2 * u[0][0] + y2 * u[1][0] + z2 * u[2][0], r21 = x2 * u[0][1] + y2 * u[1][1] + z2 * u[2][1];
T r22 = x2 * u[0][2] + y2 * u[1][2] + z2 * u[2][2];
T a00 = RSW_ABS(r00) + EPS, a01 = RSW_ABS(r01) + EPS, a02 = RSW_ABS(r02) + EPS;
T a10 = RSW_ABS(r10) + EPS, a11 = RSW_ABS(r11) + EPS, a12 = RSW_ABS(r12) + EPS;
T a20 = RSW_ABS(r20) + EPS, a21 = RSW_ABS(r21) + EPS, a22 = RSW_ABS(r22) + EPS;
T worst = RSW_MAX(RSW_MAX(RSW_ABS(d0) - e0 - (a00 * h0 + a01 * h1 + a02 * h2),
                          RSW_ABS(d1) - e1 - (a10 * h0 + a11 * h1 + a12 * h2)),
                  RSW_ABS(d2) - e2 - (a20 * h0 + a21 * h1 + a22 * h2));
T fb0 = RSW_ABS(r00 * d0 + r10 * d1 + r20 * d2) - h0 - (a00 * e0 + a10 * e1 + a20 * e2);
T fb1 = RSW_ABS(r01 * d0 + r11 * d1 + r21 * d2) - h1 - (a01 * e0 + a11 * e1 + a21 * e2);
T fb2 = RSW_ABS(r02 * d0 + r12 * d1 + r22 * d2) - h2 - (a02 * e0 + a12 * e1 + a22 * e2);
worst = RSW_MAX(worst, RSW_MAX(fb0, RSW_MAX(fb1, fb2)));
#define RSW_EDGE(da, ra, db, rb, ea, aa, eb, ab, g1, b1, g2, b2, rij) \
    RSW_MIN(RSW_ABS(da * ra - db * rb) - ea * aa - eb * ab - b1 * g1 - b2 * g2, NEAR1 - rij * rij)
T apart = RSW_MAX(worst, RSW_EDGE(d2, r10, d1, r20, e1, a20, e2, a10, h1, a02, h2, a01, r00));
apart = RSW_MAX(apart, RSW_EDGE(d2, r11, d1, r21, e1, a21, e2, a11, h2, a00, h0, a02, r01));
apart = RSW_MAX(apart, RSW_EDGE(d2, r12, d1, r22, e1, a22, e2, a12, h0, a01, h1, a00, r02));
apart = RSW_MAX(apart, RSW_EDGE(d0, r20, d2, r00, e2, a00, e0, a20, h1, a12, h2, a11, r10));
apart = RSW_MAX(apart, RSW_EDGE(d0, r21, d2, r01, e2, a01, e0, a21, h2, a10, h0, a12, r11));
apart = RSW_MAX(apart, RSW_EDGE(d0, r22, d2, r02, e2, a02, e0, a22, h0, a11, h1, a10, r12));
apart = RSW_MAX(apart, RSW_EDGE(d1, r00, d0, r10, e0, a10, e1, a00, h1, a22, h2, a21, r20));
apart = RSW_MAX(apart, RSW_EDGE(d1, r01, d0, r11, e0, a11, e1, a01, h2, a20, h0, a22, r21));
apart = RSW_MAX(apart, RSW_EDGE(d1, r02, d0, r12, e0, a12, e1, a02, h0, a21, h1, a20, r22));
#undef RSW_EDGE
T key = d0 * d0 + d1 * d1 + d2 * d2;
"""
# the record's numbers: box axes (nine lane vectors, entry 3 r + c), centres (three), half sizes
_QUAD_NAMES = (("x0", "axes", 0), ("y0", "axes", 3), ("z0", "axes", 6), ("x1", "axes", 1), ("y1", "axes", 4),
               ("z1", "axes", 7), ("x2", "axes", 2), ("y2", "axes", 5), ("z2", "axes", 8), ("e0", "halfs", 0),
               ("e1", "halfs", 1), ("e2", "halfs", 2))


def _quad_snippet(c: str) -> str:
    """The snippet for the C type ``c``: float, vector or looped; double, looped always (its
    four-double vector form rounded differently from the scalar code in a trial, within 3e-17,
    where float's agreed; the sweeps walk in float32)."""
    size = 4 * (4 if c == "float" else 8)
    load = "".join(f"__builtin_memcpy(&{n}, &wp::index({a}, k, {j}), {size});\n" for n, a, j in _QUAD_NAMES)
    centre = "".join(f"__builtin_memcpy(&c{i}, &wp::index(center, k, {i}), {size});\nc{i} = cq[{i}] - c{i};\n"
                     for i in range(3))
    names = ", ".join(n for n, _, _ in _QUAD_NAMES)
    return (
        f"const {c} EPS = ({c})({EPS_AXIS!r}), NEAR1 = ({c})({1.0 - 1.0e-6!r});\n"
        f"const {c} h0 = hq[0], h1 = hq[1], h2 = hq[2];\n"
        f"{c} u[3][3] = {{{{rq.data[0][0], rq.data[0][1], rq.data[0][2]}}, "
        "{rq.data[1][0], rq.data[1][1], rq.data[1][2]}, {rq.data[2][0], rq.data[2][1], rq.data[2][2]}};\n"
        f"wp::mat_t<2, {QUAD}, {c}> out;\n"
        f"#if defined(__clang__) && !defined(__CUDA_ARCH__) && !defined(RSW_LANES_LOOP) && {int(c == 'float')}\n"
        f"typedef {c} T __attribute__((ext_vector_type({QUAD})));\n"
        "#define RSW_ABS(v) __builtin_elementwise_abs(v)\n"
        "#define RSW_MAX(a, b) ((a) >= (b) ? (a) : ((b) == (b) ? (b) : (a)))\n"
        "#define RSW_MIN(a, b) ((a) <= (b) ? (a) : ((b) == (b) ? (b) : (a)))\n"
        f"T {names}, c0, c1, c2;\n" + load + centre + _QUAD_EXPR
        + f"__builtin_memcpy(&out.data[0][0], &key, {size});\n__builtin_memcpy(&out.data[1][0], &apart, {size});\n"
        "#else\n"
        f"typedef {c} T;\n#define RSW_ABS(v) wp::abs(v)\n#define RSW_MAX(a, b) wp::max(a, b)\n"
        "#define RSW_MIN(a, b) wp::min(a, b)\n"
        f"for (int ln = 0; ln < {QUAD}; ++ln) {{\n"
        + "".join(f"T {n} = wp::index({a}, k, {j}).c[ln];\n" for n, a, j in _QUAD_NAMES)
        + "".join(f"T c{i} = cq[{i}] - wp::index(center, k, {i}).c[ln];\n" for i in range(3))
        + _QUAD_EXPR + "out.data[0][ln] = key;\nout.data[1][ln] = apart;\n}\n"
        "#endif\n#undef RSW_ABS\n#undef RSW_MAX\n#undef RSW_MIN\nreturn out;\n")


@cached
def quad_gap_function(scalar=wp.float32):
    """quad_gaps(axes, center, halfs, k, rq, cq, hq): record k's four boxes (``BodyArrays``'
    ``quad_axes``, ``quad_center``, ``quad_half``) against one box (axes ``rq`` as columns, centre
    ``cq``, half sizes ``hq``, in the four's body frame), as ``_QUAD_EXPR`` says."""
    S, V3, M33, M34, M44 = types_of(scalar)
    V4, L2 = lane_types(scalar)

    @wp.func_native(_quad_snippet("float" if scalar == wp.float32 else "double"))
    def quad_gaps(axes: wp.array2d(dtype=V4), center: wp.array2d(dtype=V4), halfs: wp.array2d(dtype=V4), k: int,
                  rq: M33, cq: V3, hq: V3) -> L2: ...

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
def held_struct(scalar=wp.float32):
    """What a walk keeps from its last step: the box it carried into the other body's frame (the
    node, which way, its axes, centre and half sizes), and B's leaf triangle carried into A's."""
    S, V3, M33, M34, M44 = types_of(scalar)

    @wp.struct
    class Held:
        node: wp.int32  # -1: none yet
        into_a: wp.int32  # 1: B's node carried into A's frame, 0: A's into B's
        axes: M33
        center: V3
        half: V3
        leaf: wp.int32  # B's leaf whose triangle is t0, t1, t2 in A's frame; -1: none yet
        crossed: wp.int32  # 1: the last two leaves' triangles cross
        t0: V3
        t1: V3
        t2: V3

    return Held


@cached
def held_functions(scalar=wp.float32):
    """(carried, leaves_cross): a walk's step with what it kept from the last one. The walk pops
    the nearest of the pairs a step pushed, beside the same node of the other body, so the box (or
    the triangle) that step carried across is mostly the one the next needs: it is carried once,
    with the same arithmetic, so every number is as if carried anew."""
    S, V3, M33, M34, M44 = types_of(scalar)
    triangles_cross, _ = triangle_functions(scalar)
    leaf_distance = leaf_function(scalar)
    BodyArrays = bodies_struct(scalar)
    Held = held_struct(scalar)

    @wp.func
    def carried(m: BodyArrays, node: int, into_a: int, r: M33, t: V3, rt: M33, held: Held) -> Held:
        """``held`` with node's box carried into A's frame (``into_a`` 1, a node of B's) or B's."""
        if held.node == node and held.into_a == into_a:
            return held
        out = held
        out.node = node
        out.into_a = into_a
        out.half = m.nodes[node].half
        if into_a == 1:
            out.axes = r * m.nodes[node].axes
            out.center = r * m.nodes[node].center + t
        else:
            out.axes = rt * m.nodes[node].axes
            out.center = rt * (m.nodes[node].center - t)
        return out

    @wp.func
    def leaves_cross(m: BodyArrays, na: int, nb: int, r: M33, t: V3, held: Held) -> Held:
        """``held`` with B's leaf nb's triangle carried into A's frame, and ``crossed`` 1 if a
        triangle of leaf na crosses it (leaves of one triangle, ``bvh.LEAF_TRIANGLES``; any other
        size, ``tree``'s leaf test)."""
        out = held
        if m.nodes[na].right != 1 or m.nodes[nb].right != 1:
            if leaf_distance(m, na, nb, r, t, True) <= S(0.0):
                out.crossed = 1
            return out
        if held.leaf != nb:
            kb = -1 - m.nodes[nb].left
            out.t0 = r * m.triangles[3 * kb] + t
            out.t1 = r * m.triangles[3 * kb + 1] + t
            out.t2 = r * m.triangles[3 * kb + 2] + t
            out.leaf = nb
        ka = -1 - m.nodes[na].left
        if triangles_cross(m.triangles[3 * ka], m.triangles[3 * ka + 1], m.triangles[3 * ka + 2], out.t0, out.t1,
                           out.t2):
            out.crossed = 1
        return out

    return carried, leaves_cross


@cached
def quad_walk(scalar=wp.float32):
    """meshes_cross(m, a, b, r, t): whether the surfaces of bodies a and b cross (x_A = r x_B + t),
    the boxes four at a time."""
    V3, M33 = types_of(scalar)[1:3]
    first_crossing = crossing_walk(scalar)
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def meshes_cross(m: BodyArrays, a: int, b: int, r: M33, t: V3) -> bool:
        return first_crossing(m, a, b, r, t)[0] != -1

    return meshes_cross


@cached
def crossing_walk(scalar=wp.float32):
    """first_crossing(m, a, b, r, t): the first pair of leaves (A's, B's) whose triangles cross
    (x_A = r x_B + t), the boxes four at a time; (-1, -1) where none do, (-2, -2) where the stack
    would overflow (never reached for trees of ``bvh.MAX_DEPTH``; taken as crossing, never a miss)."""
    S, V3, M33, M34, M44 = types_of(scalar)
    quad_gaps = quad_gap_function(scalar)
    opens_a = opening_function(scalar)
    pushed = push_function(scalar)
    carried, leaves_cross = held_functions(scalar)
    BodyArrays = bodies_struct(scalar)
    Held = held_struct(scalar)

    @wp.func
    def first_crossing(m: BodyArrays, a: int, b: int, r: M33, t: V3) -> wp.vec2i:
        """Depth first, the nearer boxes first; the boxes of the roots are known to overlap."""
        stack = wp.zeros(shape=wp.static(2 * QUAD_STACK), dtype=wp.int32)
        stack[0] = m.root[a]
        stack[1] = m.root[b]
        top = int(1)
        rt = wp.transpose(r)
        held = Held()
        held.node = -1
        held.leaf = -1
        while top > 0:
            top -= 1
            na = stack[2 * top]
            nb = stack[2 * top + 1]
            if m.nodes[na].left < 0 and m.nodes[nb].left < 0:
                held = leaves_cross(m, na, nb, r, t, held)
                if held.crossed != 0:
                    return wp.vec2i(na, nb)
                continue
            if top + QUAD > QUAD_STACK:  # cannot happen for trees of bvh.MAX_DEPTH; never a silent miss
                return wp.vec2i(-2, -2)
            on_a = opens_a(m, na, nb)
            k = int(0)
            if on_a:  # B's box carried into A's frame, against A's four
                k = m.nodes[na].quad
                held = carried(m, nb, 1, r, t, rt, held)
            else:  # A's box carried into B's frame, against B's four
                k = m.nodes[nb].quad
                held = carried(m, na, 0, r, t, rt, held)
            g = quad_gaps(m.quad_axes, m.quad_center, m.quad_half, k, held.axes, held.center, held.half)
            top = pushed(stack, top, g, m.quad_slot[k], na, nb, on_a)
        return wp.vec2i(-1, -1)

    return first_crossing
