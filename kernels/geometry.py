"""Distances and overlap tests between points, segments, triangles and boxes, as device code in
one precision: the narrow and middle phases of the collision kernels (``collide``)."""


import warp as wp

from .cache import cached
from .types import types_of

FAR = 1.0e30
EPS_AXIS = 1.0e-6  # added to |R| in the box test: parallel edges never separate boxes that touch


@cached
def point_triangle_function(scalar=wp.float32):
    """point_triangle_sq(p, a, b, c): the squared distance from a point to a triangle."""
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

    return point_triangle_sq


@cached
def segment_function(scalar=wp.float32):
    """segment_segment_sq(p1, q1, p2, q2): the squared distance between two segments."""
    S, V3, M33, M34, M44 = types_of(scalar)

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

    return segment_segment_sq


@cached
def crossing_function(scalar=wp.float32):
    """triangles_cross(a0, a1, a2, b0, b1, b2): whether two triangles in one frame meet."""
    S, V3, M33, M34, M44 = types_of(scalar)

    @wp.func
    def orient(a: V3, b: V3, c: V3, d: V3) -> S:
        """Six times the signed volume of tetrahedron abcd: which side of plane abc d is on."""
        return wp.dot(wp.cross(b - a, c - a), d - a)

    @wp.func
    def edge_meets(dp: S, dq: S, p: V3, q: V3, a: V3, b: V3, c: V3) -> bool:
        """Whether segment pq meets triangle abc (touching counts), given ``dp`` and ``dq``, the
        signed volumes ``orient(a, b, c, p)`` and ``orient(a, b, c, q)``: its ends are not both on
        one side of the plane, and its line passes inside the three edges (signs of signed volumes
        only)."""
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
        Coplanar triangles are left to the distance tests. Each vertex's side of the other plane is
        computed once, for the plane test and the edge tests alike."""
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
        return (edge_meets(e0, e1, a0, a1, b0, b1, b2) or edge_meets(e1, e2, a1, a2, b0, b1, b2)
                or edge_meets(e2, e0, a2, a0, b0, b1, b2) or edge_meets(d0, d1, b0, b1, a0, a1, a2)
                or edge_meets(d1, d2, b1, b2, a0, a1, a2) or edge_meets(d2, d0, b2, b0, a0, a1, a2))

    return triangles_cross


@cached
def triangle_functions(scalar=wp.float32):
    """(triangles_cross, triangle_distance) for two triangles in one frame."""
    S, V3, M33, M34, M44 = types_of(scalar)
    point_triangle_sq = point_triangle_function(scalar)
    segment_segment_sq = segment_function(scalar)
    triangles_cross = crossing_function(scalar)

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

    return triangles_cross, triangle_distance


@cached
def box_functions(scalar=wp.float32):
    """(abs_rotation, box_gap): |r| + eps, and a lower bound of the distance between two boxes."""
    S, V3, M33, M34, M44 = types_of(scalar)

    @wp.func
    def abs_rotation(r: M33) -> M33:
        """|r| + eps, which the box test takes: parallel edges never separate boxes that touch."""
        ar = M33()
        for i in range(3):
            for j in range(3):
                ar[i, j] = wp.abs(r[i, j]) + S(EPS_AXIS)
        return ar

    @wp.func
    def cross_gap(ea: V3, eb: V3, r: M33, ar: M33, d: V3, i: int, j: int) -> S:
        """The gap along A's axis i x B's axis j, times that axis' length."""
        i1 = (i + 1) % 3
        i2 = (i + 2) % 3
        j1 = (j + 1) % 3
        j2 = (j + 2) % 3
        ra = ea[i1] * ar[i2, j] + ea[i2] * ar[i1, j]
        rb = eb[j1] * ar[i, j2] + eb[j2] * ar[i, j1]
        return wp.abs(d[i2] * r[i1, j] - d[i1] * r[i2, j]) - ra - rb

    @wp.func
    def box_gap(ea: V3, eb: V3, r: M33, ar: M33, d: V3, bound: bool) -> S:
        """A lower bound of the distance between box A (half-sizes ``ea``, centred on its frame's
        origin, along its axes) and box B (half-sizes ``eb``, centre ``d`` and axes ``r`` in A's
        frame; ``ar`` = |r| + eps). Negative when no separating axis of the two boxes (Gottschalk's
        15) parts them: the face axes' value then, which orders overlapping pairs. Where A's or B's
        face axes part them, the bound is the distance between A and B's bounding box in A's frame
        (or the other way round): diagonal gaps count in full. Without ``bound`` a pair apart only
        gets some positive value (no square root)."""
        ga = V3(wp.abs(d[0]) - ea[0] - wp.dot(V3(ar[0, 0], ar[0, 1], ar[0, 2]), eb),
                wp.abs(d[1]) - ea[1] - wp.dot(V3(ar[1, 0], ar[1, 1], ar[1, 2]), eb),
                wp.abs(d[2]) - ea[2] - wp.dot(V3(ar[2, 0], ar[2, 1], ar[2, 2]), eb))
        db = wp.transpose(r) * d
        fa = wp.transpose(ar) * ea
        gb = V3(wp.abs(db[0]) - fa[0] - eb[0], wp.abs(db[1]) - fa[1] - eb[1], wp.abs(db[2]) - fa[2] - eb[2])
        worst = wp.max(wp.max(ga[0], wp.max(ga[1], ga[2])), wp.max(gb[0], wp.max(gb[1], gb[2])))
        if worst > S(0.0) and not bound:  # apart: how far is not asked
            return worst
        if worst > S(0.0):
            pa = V3(wp.max(ga[0], S(0.0)), wp.max(ga[1], S(0.0)), wp.max(ga[2], S(0.0)))
            pb = V3(wp.max(gb[0], S(0.0)), wp.max(gb[1], S(0.0)), wp.max(gb[2], S(0.0)))
            return wp.sqrt(wp.max(wp.dot(pa, pa), wp.dot(pb, pb)))
        for i in range(3):
            for j in range(3):
                g = cross_gap(ea, eb, r, ar, d, i, j)
                n2 = S(1.0) - r[i, j] * r[i, j]
                if g > S(0.0) and n2 > S(1.0e-6):  # the axis A_i x B_j parts them; its length is sqrt(n2)
                    worst = wp.max(worst, g / wp.sqrt(n2))
        return worst

    return abs_rotation, box_gap
