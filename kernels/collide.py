"""Exact mesh-mesh collision of posed bodies, as device code: forward kinematics inside the kernel,
then each body pair tested against the closed meshes themselves.

A pair collides when the meshes come within ``padding`` of each other (their surfaces cross when
the padding is 0) or one contains the other. Bounding spheres and box trees only skip work: every
"collides" is a pair of triangles within the padding or a point inside a closed mesh.

Per pair and state the sweep kernel also gives a lower bound of a free pair's distance (bounding
spheres, root boxes): the host keeps the nearest samples by it, and a second kernel measures their
exact distances (the clearance of pairs that never collide).
"""

from functools import lru_cache
from typing import Any

import warp as wp

from .fk import emit_local, pose_functions, tree_fk
from .types import Chain, types_of

STACK = 96  # node pairs a traversal keeps pending: two balanced trees of depth 40 need at most 81
EPS_AXIS = 1.0e-6  # added to |R| in the box test: parallel edges never separate boxes that touch
FAR = 1.0e30


@lru_cache(maxsize=None)
def bodies_struct(scalar=wp.float32):
    """The struct of everything the collision kernels read about bodies and pairs (one precision)."""
    _, V3, M33, M34, M44 = types_of(scalar)

    @wp.struct
    class Bodies:
        link: wp.array(dtype=wp.int32)  # the chain link that moves the body, -1: fixed in the world
        pose: wp.array(dtype=M34)  # a fixed body's pose
        root: wp.array(dtype=wp.int32)  # its tree's root node
        mesh: wp.array(dtype=wp.uint64)  # its wp.Mesh, for point-inside queries
        center: wp.array(dtype=V3)  # bounding sphere, body frame
        radius: wp.array(dtype=scalar)
        point_start: wp.array(dtype=wp.int32)  # one point per connected piece (containment)
        point_count: wp.array(dtype=wp.int32)
        points: wp.array(dtype=V3)
        node_center: wp.array(dtype=V3)  # box trees (rswarp.geometry.bvh), all bodies joined
        node_half: wp.array(dtype=V3)
        node_left: wp.array(dtype=wp.int32)
        node_right: wp.array(dtype=wp.int32)
        triangles: wp.array(dtype=V3)  # three vertices per triangle, leaf order
        pair_a: wp.array(dtype=wp.int32)
        pair_b: wp.array(dtype=wp.int32)
        padding: scalar

    return Bodies


@lru_cache(maxsize=None)
def geometry_functions(scalar=wp.float32):
    """Distances between points, segments, triangles and boxes, in one precision."""
    S, V3, M33, M34, M44 = types_of(scalar)

    @wp.func
    def point_triangle_sq(p: V3, a: V3, b: V3, c: V3) -> S:
        """Squared distance from a point to a triangle (Ericson, Real-Time Collision Detection 5.1.5)."""
        ab = b - a
        ac = c - a
        ap = p - a
        d1 = wp.dot(ab, ap)
        d2 = wp.dot(ac, ap)
        if d1 <= S(0.0) and d2 <= S(0.0):
            return wp.length_sq(ap)
        bp = p - b
        d3 = wp.dot(ab, bp)
        d4 = wp.dot(ac, bp)
        if d3 >= S(0.0) and d4 <= d3:
            return wp.length_sq(bp)
        vc = d1 * d4 - d3 * d2
        if vc <= S(0.0) and d1 >= S(0.0) and d3 <= S(0.0):
            return wp.length_sq(ap - (d1 / (d1 - d3)) * ab)
        cp = p - c
        d5 = wp.dot(ab, cp)
        d6 = wp.dot(ac, cp)
        if d6 >= S(0.0) and d5 <= d6:
            return wp.length_sq(cp)
        vb = d5 * d2 - d1 * d6
        if vb <= S(0.0) and d2 >= S(0.0) and d6 <= S(0.0):
            return wp.length_sq(ap - (d2 / (d2 - d6)) * ac)
        va = d3 * d6 - d5 * d4
        if va <= S(0.0) and d4 - d3 >= S(0.0) and d5 - d6 >= S(0.0):
            return wp.length_sq(bp - ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b))
        den = S(1.0) / (va + vb + vc)
        return wp.length_sq(ap - (vb * den) * ab - (vc * den) * ac)

    @wp.func
    def segment_segment_sq(p1: V3, q1: V3, p2: V3, q2: V3) -> S:
        """Squared distance between two segments (Ericson 5.1.9)."""
        d1 = q1 - p1
        d2 = q2 - p2
        r = p1 - p2
        a = wp.dot(d1, d1)
        e = wp.dot(d2, d2)
        f = wp.dot(d2, r)
        eps = S(1.0e-20)
        s = S(0.0)
        t = S(0.0)
        if a <= eps and e <= eps:
            return wp.dot(r, r)
        if a <= eps:
            t = wp.clamp(f / e, S(0.0), S(1.0))
        else:
            c = wp.dot(d1, r)
            if e <= eps:
                s = wp.clamp(-c / a, S(0.0), S(1.0))
            else:
                b = wp.dot(d1, d2)
                den = a * e - b * b
                if den > S(0.0):
                    s = wp.clamp((b * f - c * e) / den, S(0.0), S(1.0))
                t = (b * s + f) / e
                if t < S(0.0):
                    t = S(0.0)
                    s = wp.clamp(-c / a, S(0.0), S(1.0))
                elif t > S(1.0):
                    t = S(1.0)
                    s = wp.clamp((b - c) / a, S(0.0), S(1.0))
        return wp.length_sq(r + s * d1 - t * d2)

    @wp.func
    def orient(a: V3, b: V3, c: V3, d: V3) -> S:
        """Six times the signed volume of tetrahedron abcd: which side of plane abc d is on."""
        return wp.dot(wp.cross(b - a, c - a), d - a)

    @wp.func
    def segment_hits_triangle(p: V3, q: V3, a: V3, b: V3, c: V3) -> bool:
        """Whether segment pq meets triangle abc (touching counts): its ends are not both on one side
        of the plane, and its line passes inside the three edges (signs of signed volumes only)."""
        dp = orient(a, b, c, p)
        dq = orient(a, b, c, q)
        if (dp > S(0.0) and dq > S(0.0)) or (dp < S(0.0) and dq < S(0.0)) or (dp == S(0.0) and dq == S(0.0)):
            return False
        s1 = orient(p, q, a, b)
        s2 = orient(p, q, b, c)
        s3 = orient(p, q, c, a)
        return (s1 >= S(0.0) and s2 >= S(0.0) and s3 >= S(0.0)) or (s1 <= S(0.0) and s2 <= S(0.0) and s3 <= S(0.0))

    @wp.func
    def triangles_cross(a0: V3, a1: V3, a2: V3, b0: V3, b1: V3, b2: V3) -> bool:
        """Whether two triangles meet. Two triangles not in one plane meet exactly where an edge of
        one meets the other; every test is a sign, free of the absolute tolerances that make Moller's
        test (``wp.intersect_tri_tri``) call small, distant triangles coplanar and crossing.
        Coplanar triangles are left to the distance tests."""
        n = wp.cross(a1 - a0, a2 - a0)
        d0 = wp.dot(n, b0 - a0)
        d1 = wp.dot(n, b1 - a0)
        d2 = wp.dot(n, b2 - a0)
        if (d0 > S(0.0) and d1 > S(0.0) and d2 > S(0.0)) or (d0 < S(0.0) and d1 < S(0.0) and d2 < S(0.0)):
            return False
        m = wp.cross(b1 - b0, b2 - b0)
        e0 = wp.dot(m, a0 - b0)
        e1 = wp.dot(m, a1 - b0)
        e2 = wp.dot(m, a2 - b0)
        if (e0 > S(0.0) and e1 > S(0.0) and e2 > S(0.0)) or (e0 < S(0.0) and e1 < S(0.0) and e2 < S(0.0)):
            return False
        return (segment_hits_triangle(a0, a1, b0, b1, b2) or segment_hits_triangle(a1, a2, b0, b1, b2)
                or segment_hits_triangle(a2, a0, b0, b1, b2) or segment_hits_triangle(b0, b1, a0, a1, a2)
                or segment_hits_triangle(b1, b2, a0, a1, a2) or segment_hits_triangle(b2, b0, a0, a1, a2))

    @wp.func
    def triangle_distance(a0: V3, a1: V3, a2: V3, b0: V3, b1: V3, b2: V3) -> S:
        """Distance between two triangles: 0 when they intersect, else the nearest of the vertex-face
        and edge-edge distances (where two disjoint triangles come closest)."""
        if triangles_cross(a0, a1, a2, b0, b1, b2):
            return S(0.0)
        d = point_triangle_sq(a0, b0, b1, b2)
        d = wp.min(d, point_triangle_sq(a1, b0, b1, b2))
        d = wp.min(d, point_triangle_sq(a2, b0, b1, b2))
        d = wp.min(d, point_triangle_sq(b0, a0, a1, a2))
        d = wp.min(d, point_triangle_sq(b1, a0, a1, a2))
        d = wp.min(d, point_triangle_sq(b2, a0, a1, a2))
        d = wp.min(d, segment_segment_sq(a0, a1, b0, b1))
        d = wp.min(d, segment_segment_sq(a0, a1, b1, b2))
        d = wp.min(d, segment_segment_sq(a0, a1, b2, b0))
        d = wp.min(d, segment_segment_sq(a1, a2, b0, b1))
        d = wp.min(d, segment_segment_sq(a1, a2, b1, b2))
        d = wp.min(d, segment_segment_sq(a1, a2, b2, b0))
        d = wp.min(d, segment_segment_sq(a2, a0, b0, b1))
        d = wp.min(d, segment_segment_sq(a2, a0, b1, b2))
        d = wp.min(d, segment_segment_sq(a2, a0, b2, b0))
        return wp.sqrt(d)

    @wp.func
    def box_gap(ca: V3, ea: V3, cb: V3, eb: V3, r: M33, ar: M33, t: V3) -> S:
        """A lower bound of the distance between box A (centre ``ca``, half-sizes ``ea``, A's frame)
        and box B (in B's frame, x_A = r x_B + t; ``ar`` = |r| + eps); negative when no separating
        axis of the two boxes (Gottschalk's 15) parts them. Where A's or B's face axes part them, the
        bound is the distance between A and B's bounding box in A's frame (or the other way round):
        diagonal gaps count in full, not only along one axis."""
        d = r * cb + t - ca
        sa = S(0.0)
        sb = S(0.0)
        worst = S(-FAR)
        for i in range(3):
            g = wp.abs(d[i]) - ea[i] - (ar[i, 0] * eb[0] + ar[i, 1] * eb[1] + ar[i, 2] * eb[2])
            worst = wp.max(worst, g)
            if g > S(0.0):
                sa += g * g
        for j in range(3):
            ra = ar[0, j] * ea[0] + ar[1, j] * ea[1] + ar[2, j] * ea[2]
            g = wp.abs(d[0] * r[0, j] + d[1] * r[1, j] + d[2] * r[2, j]) - ra - eb[j]
            worst = wp.max(worst, g)
            if g > S(0.0):
                sb += g * g
        if worst > S(0.0):
            return wp.sqrt(wp.max(sa, sb))
        for i in range(3):
            i1 = (i + 1) % 3
            i2 = (i + 2) % 3
            for j in range(3):
                j1 = (j + 1) % 3
                j2 = (j + 2) % 3
                n2 = S(1.0) - r[i, j] * r[i, j]
                if n2 > S(1.0e-6):
                    ra = ea[i1] * ar[i2, j] + ea[i2] * ar[i1, j]
                    rb = eb[j1] * ar[i, j2] + eb[j2] * ar[i, j1]
                    s = wp.abs(d[i2] * r[i1, j] - d[i1] * r[i2, j])
                    worst = wp.max(worst, (s - ra - rb) / wp.sqrt(n2))
        return worst

    return triangles_cross, segment_segment_sq, triangle_distance, box_gap


@lru_cache(maxsize=None)
def pair_functions(scalar=wp.float32):
    """(mesh_distance, contains, pair_distance) over a ``Bodies`` struct."""
    S, V3, M33, M34, M44 = types_of(scalar)
    _, _, apply, _ = pose_functions(scalar)
    triangles_cross, _, triangle_distance, box_gap = geometry_functions(scalar)
    Bodies = bodies_struct(scalar)

    @wp.func
    def rotation(m: M34) -> M33:
        return M33(m[0, 0], m[0, 1], m[0, 2], m[1, 0], m[1, 1], m[1, 2], m[2, 0], m[2, 1], m[2, 2])

    @wp.func
    def leaf_distance(m: Bodies, na: int, nb: int, r: M33, t: V3, overlap_only: bool) -> S:
        """The distance between the triangles of two leaves; with ``overlap_only``, 0 if two cross
        and huge otherwise."""
        best = S(FAR)
        fa = -1 - m.node_left[na]
        fb = -1 - m.node_left[nb]
        for kb in range(fb, fb + m.node_right[nb]):
            b0 = r * m.triangles[3 * kb] + t
            b1 = r * m.triangles[3 * kb + 1] + t
            b2 = r * m.triangles[3 * kb + 2] + t
            for ka in range(fa, fa + m.node_right[na]):
                a0 = m.triangles[3 * ka]
                a1 = m.triangles[3 * ka + 1]
                a2 = m.triangles[3 * ka + 2]
                if overlap_only:
                    if triangles_cross(a0, a1, a2, b0, b1, b2):
                        return S(0.0)
                else:
                    best = wp.min(best, triangle_distance(a0, a1, a2, b0, b1, b2))
        return best

    @wp.func
    def node_gap(m: Bodies, na: int, nb: int, r: M33, ar: M33, t: V3) -> S:
        return box_gap(m.node_center[na], m.node_half[na], m.node_center[nb], m.node_half[nb], r, ar, t)

    @wp.func
    def mesh_distance(m: Bodies, a: int, b: int, r: M33, t: V3, limit: S, stop: S) -> S:
        """The distance between bodies a and b (x_A = r x_B + t) where it is at most ``limit``, else
        a distance above ``limit`` or a huge value; returns as soon as one at or below ``stop`` is
        found. With ``limit`` 0 only crossing surfaces are looked for (0 if they cross).

        Depth first, nearer (more overlapping) children first: crossings and small distances are
        found early, and a small distance prunes the rest."""
        ar = M33()
        for i in range(3):
            for j in range(3):
                ar[i, j] = wp.abs(r[i, j]) + S(EPS_AXIS)
        overlap_only = limit <= S(0.0)
        best = S(FAR)
        if node_gap(m, m.root[a], m.root[b], r, ar, t) > limit:
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
            leaf_a = m.node_left[na] < 0
            leaf_b = m.node_left[nb] < 0
            if leaf_a and leaf_b:
                best = wp.min(best, leaf_distance(m, na, nb, r, t, overlap_only))
                if best <= stop:
                    return best
                continue
            if top + 2 > STACK:  # cannot happen for trees of bvh.MAX_DEPTH; never a silent miss
                return S(-1.0)
            ha = m.node_half[na]
            hb = m.node_half[nb]
            a1 = na
            a2 = na
            b1 = nb
            b2 = nb
            if leaf_b or (not leaf_a and ha[0] + ha[1] + ha[2] >= hb[0] + hb[1] + hb[2]):
                a1 = m.node_left[na]
                a2 = m.node_right[na]
            else:
                b1 = m.node_left[nb]
                b2 = m.node_right[nb]
            g1 = node_gap(m, a1, b1, r, ar, t)
            g2 = node_gap(m, a2, b2, r, ar, t)
            cut = wp.min(best, limit)
            if g1 < g2:  # the nearer pair goes on top
                g1, g2 = g2, g1
                a1, a2 = a2, a1
                b1, b2 = b2, b1
            if g1 <= cut:
                stack[2 * top] = a1
                stack[2 * top + 1] = b1
                gaps[top] = g1
                top += 1
            if g2 <= cut:
                stack[2 * top] = a2
                stack[2 * top + 1] = b2
                gaps[top] = g2
                top += 1
        return best

    @wp.func
    def contains(m: Bodies, outer: int, inner: int, r: M33, t: V3) -> bool:
        """Whether a piece of body ``inner`` lies inside closed body ``outer`` (x_outer = r x_inner + t),
        given that their surfaces do not cross: one point per piece decides."""
        root = m.root[outer]
        c = m.node_center[root]
        h = m.node_half[root]
        for k in range(m.point_start[inner], m.point_start[inner] + m.point_count[inner]):
            p = r * m.points[k] + t
            o = p - c
            if wp.abs(o[0]) <= h[0] and wp.abs(o[1]) <= h[1] and wp.abs(o[2]) <= h[2]:
                pf = wp.vec3(wp.float32(p[0]), wp.float32(p[1]), wp.float32(p[2]))
                q = wp.mesh_query_point_sign_winding_number(m.mesh[outer], pf, wp.float32(FAR))
                if q.result and q.sign < wp.float32(0.0):
                    return True
        return False

    @wp.func
    def relative(pa: M34, pb: M34) -> M34:
        """B's frame in A's: x_A = r x_B + t, as one 3x4."""
        rt = wp.transpose(rotation(pa))
        r = rt * rotation(pb)
        t = rt * (V3(pb[0, 3], pb[1, 3], pb[2, 3]) - V3(pa[0, 3], pa[1, 3], pa[2, 3]))
        return M34(r[0, 0], r[0, 1], r[0, 2], t[0], r[1, 0], r[1, 1], r[1, 2], t[1], r[2, 0], r[2, 1], r[2, 2], t[2])

    @wp.func
    def enclosed(m: Bodies, a: int, b: int, r: M33, t: V3) -> bool:
        """Whether either body contains a piece of the other (their surfaces being apart)."""
        rt = wp.transpose(r)
        return contains(m, b, a, rt, -(rt * t)) or contains(m, a, b, r, t)

    @wp.func
    def pair_verdict(m: Bodies, a: int, b: int, pa: M34, pb: M34) -> S:
        """Bodies a and b at poses pa and pb: at most the padding if they collide (-1 if one
        contains the other), else a lower bound of their distance above the padding (from their
        bounding spheres and root boxes)."""
        ca = apply(pa, m.center[a])
        cb = apply(pb, m.center[b])
        gap = wp.length(ca - cb) - m.radius[a] - m.radius[b]
        if gap > m.padding:
            return gap
        rel = relative(pa, pb)
        r = rotation(rel)
        t = V3(rel[0, 3], rel[1, 3], rel[2, 3])
        ar = M33()
        for i in range(3):
            for j in range(3):
                ar[i, j] = wp.abs(r[i, j]) + S(EPS_AXIS)
        gap = wp.max(gap, node_gap(m, m.root[a], m.root[b], r, ar, t))
        if gap > m.padding:
            return gap
        d = mesh_distance(m, a, b, r, t, m.padding, m.padding)
        if d <= m.padding:
            return d
        if enclosed(m, a, b, r, t):
            return S(-1.0)
        return wp.max(gap, m.padding + S(1.0e-9))

    @wp.func
    def pair_distance(m: Bodies, a: int, b: int, pa: M34, pb: M34) -> S:
        """The exact distance between bodies a and b at poses pa and pb (0 where surfaces cross,
        -1 where one contains the other)."""
        rel = relative(pa, pb)
        r = rotation(rel)
        t = V3(rel[0, 3], rel[1, 3], rel[2, 3])
        d = mesh_distance(m, a, b, r, t, S(FAR), S(0.0))
        if d > S(0.0) and enclosed(m, a, b, r, t):
            return S(-1.0)
        return d

    return pair_verdict, pair_distance


@lru_cache(maxsize=None)
def body_pose_function(scalar=wp.float32):
    S, V3, M33, M34, M44 = types_of(scalar)
    Bodies = bodies_struct(scalar)

    @wp.func
    def body_pose(m: Bodies, poses: Any, b: int) -> M34:
        k = m.link[b]
        if k >= 0:
            return poses[k]
        return m.pose[b]

    return body_pose


_KERNELS: dict[str, Any] = {}


def collision_kernels(chain: Chain, links, scalar=wp.float32):
    """(collide, distance) for bodies riding on chain ``links``:

    ``collide(bodies, q, hit, gap)``: for configuration ``q[i]``, each pair's verdict ``hit[i, p]``
    (1: collides) and ``gap[i, p]``, a lower bound of the pair's distance when it is free.
    ``distance(bodies, q, pair, out)``: the exact distance of pair ``pair[i]`` at ``q[i]``."""
    key = f"{chain.digest()}_{'_'.join(str(int(k)) for k in sorted(links))}_{scalar.__name__}"
    if key not in _KERNELS:
        _KERNELS[key] = _make_kernels(key, chain, links, scalar)
    return _KERNELS[key]


def _make_kernels(key: str, chain: Chain, links, scalar):
    S, V3, M33, M34, M44 = types_of(scalar)
    Bodies = bodies_struct(scalar)
    pair_verdict, pair_distance = pair_functions(scalar)
    body_pose = body_pose_function(scalar)
    n = max(len(chain.parent), 1)
    fk = tree_fk(chain, set(int(k) for k in links) or {chain.root}, emit_local(scalar), scalar)
    module = f"rswarp_collide_{key}"

    @wp.kernel(enable_backward=False, module=module)
    def collide(m: Bodies, q: wp.array2d(dtype=S), hit: wp.array2d(dtype=wp.uint8), gap: wp.array2d(dtype=S)):
        i = wp.tid()
        poses = wp.zeros(shape=n, dtype=M34)
        fk(q, i, poses)
        for p in range(m.pair_a.shape[0]):
            a = m.pair_a[p]
            b = m.pair_b[p]
            g = pair_verdict(m, a, b, body_pose(m, poses, a), body_pose(m, poses, b))
            if g <= m.padding:
                hit[i, p] = wp.uint8(1)
                gap[i, p] = S(0.0)
            else:
                hit[i, p] = wp.uint8(0)
                gap[i, p] = g

    @wp.kernel(enable_backward=False, module=module)
    def distance(m: Bodies, q: wp.array2d(dtype=S), pair: wp.array(dtype=wp.int32), out: wp.array(dtype=S)):
        i = wp.tid()
        poses = wp.zeros(shape=n, dtype=M34)
        fk(q, i, poses)
        a = m.pair_a[pair[i]]
        b = m.pair_b[pair[i]]
        out[i] = pair_distance(m, a, b, body_pose(m, poses, a), body_pose(m, poses, b))

    return collide, distance
