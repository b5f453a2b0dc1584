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
from .geometry import FAR, box_functions, triangle_functions
from .types import Chain, types_of

STACK = 96  # node pairs a traversal keeps pending: two balanced trees of depth 40 need at most 81


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
def node_functions(scalar=wp.float32):
    """(leaf_distance, node_gap, split): what the tree walk does with one pair of nodes."""
    S, V3, M33, M34, M44 = types_of(scalar)
    triangles_cross, triangle_distance = triangle_functions(scalar)
    _, box_gap = box_functions(scalar)
    Bodies = bodies_struct(scalar)

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
    def split(m: Bodies, na: int, nb: int) -> wp.vec4i:
        """The two node pairs (a1, b1, a2, b2) that (na, nb) opens into: the larger node's children
        (the one that is not a leaf)."""
        ha = m.node_half[na]
        hb = m.node_half[nb]
        if m.node_left[nb] < 0 or (m.node_left[na] >= 0 and ha[0] + ha[1] + ha[2] >= hb[0] + hb[1] + hb[2]):
            return wp.vec4i(m.node_left[na], nb, m.node_right[na], nb)
        return wp.vec4i(na, m.node_left[nb], na, m.node_right[nb])

    return leaf_distance, node_gap, split


@lru_cache(maxsize=None)
def traversal_functions(scalar=wp.float32):
    """(node_gap, mesh_distance): the box gap of two tree nodes, and the dual walk of two bodies'
    box trees down to their nearest (or crossing) triangles."""
    S, V3, M33, M34, M44 = types_of(scalar)
    abs_rotation, _ = box_functions(scalar)
    leaf_distance, node_gap, split = node_functions(scalar)
    Bodies = bodies_struct(scalar)

    @wp.func
    def mesh_distance(m: Bodies, a: int, b: int, r: M33, t: V3, limit: S, stop: S) -> S:
        """The distance between bodies a and b (x_A = r x_B + t) where it is at most ``limit``, else
        a distance above ``limit`` or a huge value; returns as soon as one at or below ``stop`` is
        found. With ``limit`` 0 only crossing surfaces are looked for (0 if they cross).

        Depth first, nearer (more overlapping) children first: crossings and small distances are
        found early, and a small distance prunes the rest."""
        ar = abs_rotation(r)
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
            if m.node_left[na] < 0 and m.node_left[nb] < 0:
                best = wp.min(best, leaf_distance(m, na, nb, r, t, overlap_only))
                if best <= stop:
                    return best
                continue
            if top + 2 > STACK:  # cannot happen for trees of bvh.MAX_DEPTH; never a silent miss
                return S(-1.0)
            c = split(m, na, nb)
            g1 = node_gap(m, c[0], c[1], r, ar, t)
            g2 = node_gap(m, c[2], c[3], r, ar, t)
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


@lru_cache(maxsize=None)
def containment_functions(scalar=wp.float32):
    """enclosed(m, a, b, r, t): whether either body contains a piece of the other."""
    S, V3, M33, M34, M44 = types_of(scalar)
    Bodies = bodies_struct(scalar)

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
    def enclosed(m: Bodies, a: int, b: int, r: M33, t: V3) -> bool:
        """Whether either body contains a piece of the other (their surfaces being apart)."""
        rt = wp.transpose(r)
        return contains(m, b, a, rt, -(rt * t)) or contains(m, a, b, r, t)

    return enclosed


@lru_cache(maxsize=None)
def pose_helpers(scalar=wp.float32):
    """(rotation, relative): a pose's rotation, and B's frame in A's."""
    S, V3, M33, M34, M44 = types_of(scalar)

    @wp.func
    def rotation(m: M34) -> M33:
        return M33(m[0, 0], m[0, 1], m[0, 2], m[1, 0], m[1, 1], m[1, 2], m[2, 0], m[2, 1], m[2, 2])

    @wp.func
    def relative(pa: M34, pb: M34) -> M34:
        """B's frame in A's: x_A = r x_B + t, as one 3x4."""
        rt = wp.transpose(rotation(pa))
        r = rt * rotation(pb)
        t = rt * (V3(pb[0, 3], pb[1, 3], pb[2, 3]) - V3(pa[0, 3], pa[1, 3], pa[2, 3]))
        return M34(r[0, 0], r[0, 1], r[0, 2], t[0], r[1, 0], r[1, 1], r[1, 2], t[1], r[2, 0], r[2, 1], r[2, 2], t[2])

    return rotation, relative


@lru_cache(maxsize=None)
def pair_functions(scalar=wp.float32):
    """(pair_verdict, pair_distance) over a ``Bodies`` struct."""
    S, V3, M33, M34, M44 = types_of(scalar)
    _, _, apply, _ = pose_functions(scalar)
    abs_rotation, _ = box_functions(scalar)
    node_gap, mesh_distance = traversal_functions(scalar)
    rotation, relative = pose_helpers(scalar)
    enclosed = containment_functions(scalar)
    Bodies = bodies_struct(scalar)

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
        ar = abs_rotation(r)
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


def _body_pose(scalar):
    """body_pose(m, poses, b): body b's pose, from the chain's poses or its fixed one. Made anew for
    each kernel module: a generic (``Any``) function shared by modules whose pose arrays differ in
    length is specialized for one of them only (a C++ build error in the others)."""
    S, V3, M33, M34, M44 = types_of(scalar)
    Bodies = bodies_struct(scalar)

    @wp.func
    def body_pose(m: Bodies, poses: Any, b: int) -> M34:
        k = m.link[b]
        if k >= 0:
            return poses[k]
        return m.pose[b]

    return body_pose


def _make_kernels(key: str, chain: Chain, links, scalar):
    S, V3, M33, M34, M44 = types_of(scalar)
    Bodies = bodies_struct(scalar)
    pair_verdict, pair_distance = pair_functions(scalar)
    body_pose = _body_pose(scalar)
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
