"""Two bodies proved apart by their convex hulls, as device code: Gilbert, Johnson and Keerthi's
distance iteration (GJK) over the hulls' Minkowski difference, each support point found by
climbing the hull's edge graph from a start that a cube map of directions gives.

Any direction v gives a lower bound of the hulls' distance, v . w / |v|, w being the difference's
support point against v, and a body's surface lies within its hull. So a pair is called apart only
where that bound, from supports evaluated exactly as written, exceeds the limit by a hair that
covers the rounding: the iteration's own simplex steps only choose v, and a poor v never proves
anything. Where the hulls touch or nest the test says nothing, and the walk decides."""

import warp as wp

from .cache import cached
from .types import bodies_struct, types_of

CUBE = 32  # cube-map cells along each side of a face: 6 x CUBE x CUBE start vertices a body
HULL_ITERATIONS = 16  # GJK steps before the test gives up (the walk then decides)
HULL_HAIR = 1.0e-5  # of the pair's size (both hulls' reach and their offset, plus a metre): rounding


@cached
def cube_cell_function(scalar=wp.float32):
    """cube_cell(d): the cube-map cell of direction ``d`` (face 2 axis + (negative), then row, column)."""
    S, V3 = types_of(scalar)[:2]

    @wp.func
    def cube_cell(d: V3) -> int:
        x = wp.abs(d[0])
        y = wp.abs(d[1])
        z = wp.abs(d[2])
        axis = int(0)
        big = x
        u = d[1]
        v = d[2]
        if y > big:
            axis = 1
            big = y
            u = d[2]
            v = d[0]
        if z > big:
            axis = 2
            big = z
            u = d[0]
            v = d[1]
        face = 2 * axis
        if d[axis] < S(0.0):
            face += 1
        if not (big > S(0.0)):  # a zero (or NaN) direction: any start will do
            return 0
        iu = wp.clamp(int((u / big + S(1.0)) * S(0.5 * float(CUBE))), 0, CUBE - 1)
        iv = wp.clamp(int((v / big + S(1.0)) * S(0.5 * float(CUBE))), 0, CUBE - 1)
        return (face * CUBE + iu) * CUBE + iv

    return cube_cell


@cached
def support_functions(scalar=wp.float32):
    """(nearby, climb): ``nearby(m, body, d)``, the cube map's hull vertex of ``body`` for ``d``
    (the farthest along its cell's centre: along ``d`` itself, near the farthest); ``climb(m, k, d)``,
    the farthest along ``d``, climbing from vertex ``k`` along edges that go further. On a convex
    hull a vertex that no neighbour improves on is the farthest."""
    V3 = types_of(scalar)[1]
    BodyArrays = bodies_struct(scalar)
    cube_cell = cube_cell_function(scalar)

    @wp.func
    def nearby(m: BodyArrays, body: int, d: V3) -> int:
        return m.hull_cube[m.hull_cube_start[body] + cube_cell(d)]

    @wp.func
    def along(p: V3, d: wp.vec3d) -> wp.float64:
        return wp.float64(p[0]) * d[0] + wp.float64(p[1]) * d[1] + wp.float64(p[2]) * d[2]

    @wp.func
    def climb(m: BodyArrays, start: int, d: V3) -> int:
        # in float64 whatever the precision: a float32 float's products are exact there, so no
        # rounding stops the climb short on a nearly flat stretch of the hull (in float32 it did,
        # by micrometres, on the IRB 2600's Link 6)
        dd = wp.vec3d(wp.float64(d[0]), wp.float64(d[1]), wp.float64(d[2]))
        k = start
        best = along(m.hull_vertex[k], dd)
        here = int(-1)
        while here != k:  # each step strictly further: it ends
            here = k
            for e in range(m.hull_adj_start[here], m.hull_adj_start[here + 1]):
                n = m.hull_adj[e]
                s = along(m.hull_vertex[n], dd)
                if s > best:
                    best = s
                    k = n
        return k

    return nearby, climb


@cached
def simplex_functions(scalar=wp.float32):
    """(segment, triangle): the point of a simplex nearest the origin and the least simplex of its
    points that holds it, with its count (Ericson, Real-Time Collision Detection, 5.1.5)."""
    S, V3 = types_of(scalar)[:2]

    @wp.func
    def segment(a: V3, b: V3):
        ab = b - a
        den = wp.dot(ab, ab)
        t = -wp.dot(a, ab)
        if t <= S(0.0) or not (den > S(0.0)):
            return a, a, a, a, 1
        if t >= den:
            return b, b, b, b, 1
        return a + (t / den) * ab, a, b, b, 2

    @wp.func
    def triangle(a: V3, b: V3, c: V3):
        ab = b - a
        ac = c - a
        d1 = -wp.dot(ab, a)
        d2 = -wp.dot(ac, a)
        if d1 <= S(0.0) and d2 <= S(0.0):
            return a, a, a, a, 1
        d3 = -wp.dot(ab, b)
        d4 = -wp.dot(ac, b)
        if d3 >= S(0.0) and d4 <= d3:
            return b, b, b, b, 1
        vc = d1 * d4 - d3 * d2
        if vc <= S(0.0) and d1 >= S(0.0) and d3 <= S(0.0):
            return a + (d1 / (d1 - d3)) * ab, a, b, b, 2
        d5 = -wp.dot(ab, c)
        d6 = -wp.dot(ac, c)
        if d6 >= S(0.0) and d5 <= d6:
            return c, c, c, c, 1
        vb = d5 * d2 - d1 * d6
        if vb <= S(0.0) and d2 >= S(0.0) and d6 <= S(0.0):
            return a + (d2 / (d2 - d6)) * ac, a, c, c, 2
        va = d3 * d6 - d5 * d4
        if va <= S(0.0) and d4 - d3 >= S(0.0) and d5 - d6 >= S(0.0):
            return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b), b, c, c, 2
        den = va + vb + vc
        if not (den > S(0.0)):  # a flat triangle: its nearest edge point is near enough
            return segment(a, c)
        return a + (vb / den) * ab + (vc / den) * ac, a, b, c, 3

    return segment, triangle


@cached
def step_function(scalar=wp.float32):
    """step(y0, y1, y2, n, w): GJK's simplex of ``n`` points with ``w`` added, reduced to the least
    that holds its point nearest the origin: (that point, its points, their count; 4: the origin
    inside, a tetrahedron holding it)."""
    S, V3 = types_of(scalar)[:2]
    segment, triangle = simplex_functions(scalar)

    @wp.func
    def outside(a: V3, b: V3, c: V3, d: V3) -> bool:
        """Whether the origin lies beyond face abc, on the side away from d (or d is on its plane)."""
        n = wp.cross(b - a, c - a)
        return -wp.dot(n, a) * wp.dot(n, d - a) <= S(0.0)

    @wp.func
    def face(a: V3, b: V3, c: V3, d: V3):
        """``triangle`` of face abc where the origin lies beyond it (away from d), else count 0."""
        if outside(a, b, c, d):
            return triangle(a, b, c)
        return a, a, a, a, 0

    @wp.func
    def nearer(v: V3, p0: V3, p1: V3, p2: V3, n: int, u: V3, q0: V3, q1: V3, q2: V3, k: int):
        if k > 0 and (n == 0 or wp.dot(u, u) < wp.dot(v, v)):
            return u, q0, q1, q2, k
        return v, p0, p1, p2, n

    @wp.func
    def tetrahedron(a: V3, b: V3, c: V3, d: V3):
        """As ``triangle``, of the nearest face the origin lies beyond; count 4 where none (inside)."""
        v, p0, p1, p2, n = face(a, b, c, d)
        u, q0, q1, q2, k = face(a, c, d, b)
        v, p0, p1, p2, n = nearer(v, p0, p1, p2, n, u, q0, q1, q2, k)
        u, q0, q1, q2, k = face(a, d, b, c)
        v, p0, p1, p2, n = nearer(v, p0, p1, p2, n, u, q0, q1, q2, k)
        u, q0, q1, q2, k = face(b, d, c, a)
        v, p0, p1, p2, n = nearer(v, p0, p1, p2, n, u, q0, q1, q2, k)
        if n == 0:
            return v, p0, p1, p2, 4
        return v, p0, p1, p2, n

    @wp.func
    def step(y0: V3, y1: V3, y2: V3, n: int, w: V3):
        if n == 0:
            return w, w, w, w, 1
        if n == 1:
            return segment(y0, w)
        if n == 2:
            return triangle(y0, y1, w)
        return tetrahedron(y0, y1, y2, w)

    return step


@cached
def hull_function(scalar=wp.float32):
    """hulls_apart(m, a, b, r, t, limit): whether the hulls of bodies a and b (x_A = r x_B + t) are
    provably further apart than ``limit``; False where either has no hull (``m.hull_cube_start``
    -1), where they come within it, or where the iteration ends first."""
    S, V3, M33 = types_of(scalar)[:3]
    BodyArrays = bodies_struct(scalar)
    nearby, climb = support_functions(scalar)
    step = step_function(scalar)

    @wp.func
    def hulls_apart(m: BodyArrays, a: int, b: int, r: M33, t: V3, limit: S) -> bool:
        if m.hull_cube_start[a] < 0 or m.hull_cube_start[b] < 0:
            return False
        rt = wp.transpose(r)
        reach = m.hull_reach[a] + m.hull_reach[b] + wp.length(t) + S(1.0)
        edge = limit + S(HULL_HAIR) * reach
        edge2 = edge * edge
        v = m.center[a] - (r * m.center[b] + t)  # the first direction: between the spheres' centres
        if not (wp.dot(v, v) > S(0.0)):
            v = V3(S(1.0), S(0.0), S(0.0))
        y0 = V3(S(0.0))
        y1 = y0
        y2 = y0
        n = int(0)
        it = int(0)
        while it < HULL_ITERATIONS:  # a dynamic loop: a constant range would be unrolled
            it += 1
            # the difference's point least along v (A's least, B's most), first as the cube maps
            # have it: any hull vertex is a point of the hulls, so the simplex steps stay exact
            ka = nearby(m, a, -v)
            kb = nearby(m, b, rt * v)
            w = m.hull_vertex[ka] - (r * m.hull_vertex[kb] + t)
            vw = wp.dot(v, w)
            vv = wp.dot(v, v)
            proved = vw > S(0.0) and vw * vw > edge2 * vv  # v . w / |v| bounds the distance from below
            stalled = n > 0 and vv - vw <= S(1.0e-6) * vv  # no nearer point of the difference
            if proved or stalled:  # only the farthest points prove it, or say nothing nearer is left
                ka = climb(m, ka, -v)
                kb = climb(m, kb, rt * v)
                w = m.hull_vertex[ka] - (r * m.hull_vertex[kb] + t)
                vw = wp.dot(v, w)
                if vw > S(0.0) and vw * vw > edge2 * vv:
                    return True
                if n > 0 and vv - vw <= S(1.0e-6) * vv:
                    return False
            v, y0, y1, y2, n = step(y0, y1, y2, n, w)
            if n == 4:  # the origin inside: the hulls overlap
                return False
            if not (wp.dot(v, v) > edge2):  # a point of the difference within the limit
                return False
        return False

    return hulls_apart
