"""Walking two bodies' box trees (``rswarp.geometry.bvh``) together, as device code: the node-pair
test, the split, the leaves' triangles, and the walks built on them (nearest triangles; a spread
sample of all crossing triangle pairs). The sweep's walk for crossing triangles is ``quad``'s."""

from typing import Any

import warp as wp

from .cache import cached
from .geometry import FAR, box_functions, triangle_functions
from .types import WITNESSES, bodies_struct, types_of, witness_vec
from .values import fresh

STACK = 96  # node pairs a traversal keeps pending: two balanced trees of depth 40 need at most 81
SAMPLE = 32  # crossing triangle pairs a sampling walk holds at once


@cached
def leaf_function(scalar=wp.float32):
    """leaf_distance(m, na, nb, r, t, overlap_only): what the tree walk does with two leaves."""
    S, V3, M33, M34, M44 = types_of(scalar)
    triangles_cross, triangle_distance = triangle_functions(scalar)
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def leaf_distance(m: BodyArrays, na: int, nb: int, r: M33, t: V3, overlap_only: bool) -> S:
        """The distance between the triangles of two leaves; with ``overlap_only``, 0 if two cross
        and huge otherwise."""
        best = fresh(S(FAR))
        fa = -1 - m.nodes[na].left
        fb = -1 - m.nodes[nb].left
        for kb in range(fb, fb + m.nodes[nb].right):
            b0 = r * m.triangles[3 * kb] + t
            b1 = r * m.triangles[3 * kb + 1] + t
            b2 = r * m.triangles[3 * kb + 2] + t
            for ka in range(fa, fa + m.nodes[na].right):
                a0 = m.triangles[3 * ka]
                a1 = m.triangles[3 * ka + 1]
                a2 = m.triangles[3 * ka + 2]
                if overlap_only:
                    if triangles_cross(a0, a1, a2, b0, b1, b2):
                        return S(0.0)
                else:
                    best = wp.min(best, triangle_distance(a0, a1, a2, b0, b1, b2))
        return best

    return leaf_distance


@cached
def opening_function(scalar=wp.float32):
    """opens_a(m, na, nb): whether a walk opens A's node (the larger, unless it is a leaf) rather
    than B's; every walk of two trees opens by this rule."""
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def opens_a(m: BodyArrays, na: int, nb: int) -> bool:
        ha = m.nodes[na].half
        hb = m.nodes[nb].half
        return m.nodes[nb].left < 0 or (m.nodes[na].left >= 0 and ha[0] + ha[1] + ha[2] >= hb[0] + hb[1] + hb[2])

    return opens_a


@cached
def node_functions(scalar=wp.float32):
    """(node_gap, child_gaps, split): what the tree walk does with one pair of boxes."""
    S, V3, M33, M34, M44 = types_of(scalar)
    V2 = wp.types.vector(2, scalar)
    abs_rotation, box_gap = box_functions(scalar)
    opens_a = opening_function(scalar)
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def node_gap(m: BodyArrays, na: int, nb: int, r: M33, t: V3) -> S:
        """A lower bound of the distance between the boxes of nodes na (body A) and nb (body B),
        x_A = r x_B + t: B's box is carried into the frame of A's."""
        at = wp.transpose(m.nodes[na].axes)
        rr = at * (r * m.nodes[nb].axes)
        d = at * (r * m.nodes[nb].center + t - m.nodes[na].center)
        return box_gap(m.nodes[na].half, m.nodes[nb].half, rr, abs_rotation(rr), d, True)

    @wp.func
    def child_gaps(m: BodyArrays, c: wp.vec4i, r: M33, t: V3, bound: bool) -> V2:
        """node_gap of the two pairs ``split`` gives (a1, b1, a2, b2), the node they share carried
        across once: B's box into A's body frame, or the frame of A's box into B's body. Without
        ``bound``, a pair apart only gets some positive value."""
        g = V2()
        if c[1] == c[3]:  # A's node was split
            rb = r * m.nodes[c[1]].axes
            cb = r * m.nodes[c[1]].center + t
            for k in range(2):
                at = wp.transpose(m.nodes[c[2 * k]].axes)
                rr = at * rb
                g[k] = box_gap(m.nodes[c[2 * k]].half, m.nodes[c[1]].half, rr, abs_rotation(rr),
                               at * (cb - m.nodes[c[2 * k]].center), bound)
            return g
        at = wp.transpose(m.nodes[c[0]].axes)
        ar = at * r
        d0 = at * (t - m.nodes[c[0]].center)
        for k in range(2):
            rr = ar * m.nodes[c[2 * k + 1]].axes
            g[k] = box_gap(m.nodes[c[0]].half, m.nodes[c[2 * k + 1]].half, rr, abs_rotation(rr),
                           ar * m.nodes[c[2 * k + 1]].center + d0, bound)
        return g

    @wp.func
    def split(m: BodyArrays, na: int, nb: int) -> wp.vec4i:
        """The two node pairs (a1, b1, a2, b2) that (na, nb) opens into: the children of the node
        ``opens_a`` picks."""
        if opens_a(m, na, nb):
            return wp.vec4i(m.nodes[na].left, nb, m.nodes[na].right, nb)
        return wp.vec4i(na, m.nodes[nb].left, na, m.nodes[nb].right)

    return node_gap, child_gaps, split


@cached
def traversal_functions(scalar=wp.float32):
    """(node_gap, mesh_distance): the box gap of two tree nodes, and the dual walk of two bodies'
    box trees down to their nearest triangles."""
    S, V3, M33, M34, M44 = types_of(scalar)
    leaf_distance = leaf_function(scalar)
    node_gap, child_gaps, split = node_functions(scalar)
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def mesh_distance(m: BodyArrays, a: int, b: int, r: M33, t: V3, limit: S, stop: S) -> S:
        """The distance between bodies a and b (x_A = r x_B + t) where it is at most ``limit``, else
        a distance above ``limit`` or a huge value; returns as soon as one at or below ``stop`` is
        found. With ``limit`` 0 only crossing surfaces are looked for (0 if they cross).

        Depth first, nearer (more overlapping) children first: crossings and small distances are
        found early, and a small distance prunes the rest."""
        overlap_only = limit <= S(0.0)
        best = fresh(S(FAR))
        if node_gap(m, m.root[a], m.root[b], r, t) > limit:
            return best
        stack = wp.zeros(shape=wp.static(2 * STACK), dtype=wp.int32)
        gaps = wp.zeros(shape=wp.static(STACK), dtype=S)
        stack[0] = m.root[a]
        stack[1] = m.root[b]
        gaps[0] = S(-FAR)
        top = int(1)
        while top > 0:
            top -= 1
            na = stack[2 * top]
            nb = stack[2 * top + 1]
            if gaps[top] > wp.min(best, limit):  # a nearer pair was found since this one was pushed
                continue
            if m.nodes[na].left < 0 and m.nodes[nb].left < 0:
                best = wp.min(best, leaf_distance(m, na, nb, r, t, overlap_only))
                if best <= stop:
                    return best
                continue
            if top + 2 > STACK:  # cannot happen for trees of bvh.MAX_DEPTH; never a silent miss
                return S(-1.0)
            c = split(m, na, nb)
            gs = child_gaps(m, c, r, t, True)
            g1 = gs[0]
            g2 = gs[1]
            near = int(2)  # the nearer pair goes on top
            if g1 < g2:
                near = 0
            far = 2 - near
            cut = wp.min(best, limit)
            for k in range(2):
                j = far if k == 0 else near
                g = g1 if j == 0 else g2
                if g <= cut:
                    stack[2 * top] = c[j]
                    stack[2 * top + 1] = c[j + 1]
                    gaps[top] = g
                    top += 1
        return best

    return node_gap, mesh_distance


@cached
def keeping_functions():
    """(keep, spread): the bookkeeping of a sample spread evenly over a stream of crossings, in a
    kernel-local array of SAMPLE (A's, B's) triangle pairs."""

    @wp.func
    def keep(kept: Any, held: int, seen: int, stride: int, ka: int, kb: int) -> wp.vec2i:
        """Keep the ``seen``-th crossing (ka, kb) if it falls on the stride; when SAMPLE are held,
        keep every other one and double the stride first. Returns (held, stride)."""
        h = held
        st = stride
        if seen % st == 0:
            if h == SAMPLE:
                for k in range(SAMPLE // 2):
                    kept[2 * k] = kept[4 * k]
                    kept[2 * k + 1] = kept[4 * k + 1]
                h = SAMPLE // 2
                st *= 2
            if seen % st == 0:
                kept[2 * h] = ka
                kept[2 * h + 1] = kb
                h += 1
        return wp.vec2i(h, st)

    @wp.func
    def spread(kept: Any, held: int) -> witness_vec:
        """WITNESSES of the ``held`` kept pairs, evenly spaced; -1 where fewer are held."""
        out = witness_vec()
        for k in range(WITNESSES):
            out[2 * k] = -1
            out[2 * k + 1] = -1
            if k < held:
                j = k * held // wp.min(held, WITNESSES)
                out[2 * k] = kept[2 * j]
                out[2 * k + 1] = kept[2 * j + 1]
        return out

    return keep, spread


@cached
def sampling_functions(scalar=wp.float32):
    """crossing_sample(m, a, b, r, t): WITNESSES crossing triangle pairs of bodies a and b spread
    over all of them (``witness_vec``: A's, B's triangle, pair after pair; -1 where fewer cross)."""
    S, V3, M33, M34, M44 = types_of(scalar)
    triangles_cross, _ = triangle_functions(scalar)
    node_gap, child_gaps, split = node_functions(scalar)
    keep, spread = keeping_functions()
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def crossing_sample(m: BodyArrays, a: int, b: int, r: M33, t: V3) -> witness_vec:
        """Walks every overlapping node pair (depth first, so neighbours in the walk are neighbours
        on the surface) and keeps every stride-th crossing, doubling the stride when SAMPLE are
        held: what is kept is spread evenly over the walk, whatever the number of crossings."""
        kept = wp.zeros(shape=wp.static(2 * SAMPLE), dtype=wp.int32)
        stack = wp.zeros(shape=wp.static(2 * STACK), dtype=wp.int32)
        held = int(0)
        seen = int(0)
        stride = int(1)
        top = int(0)
        if node_gap(m, m.root[a], m.root[b], r, t) <= S(0.0):
            stack[0] = m.root[a]
            stack[1] = m.root[b]
            top = 1
        while top > 0 and top + 2 <= STACK:
            top -= 1
            na = stack[2 * top]
            nb = stack[2 * top + 1]
            if m.nodes[na].left >= 0 or m.nodes[nb].left >= 0:
                c = split(m, na, nb)
                gs = child_gaps(m, c, r, t, False)
                for j in range(2):
                    if gs[j] <= S(0.0):
                        stack[2 * top] = c[2 * j]
                        stack[2 * top + 1] = c[2 * j + 1]
                        top += 1
                continue
            fa = -1 - m.nodes[na].left
            fb = -1 - m.nodes[nb].left
            for ka in range(fa, fa + m.nodes[na].right):
                for kb in range(fb, fb + m.nodes[nb].right):
                    if triangles_cross(m.triangles[3 * ka], m.triangles[3 * ka + 1], m.triangles[3 * ka + 2],
                                       r * m.triangles[3 * kb] + t, r * m.triangles[3 * kb + 1] + t,
                                       r * m.triangles[3 * kb + 2] + t):
                        hs = keep(kept, held, seen, stride, ka, kb)
                        held = hs[0]
                        stride = hs[1]
                        seen += 1
        return spread(kept, held)

    return crossing_sample
