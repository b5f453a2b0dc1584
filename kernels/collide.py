"""Exact mesh-mesh collision of posed bodies, as device code: forward kinematics inside the kernel,
then each body pair tested against the closed meshes themselves.

A pair collides when the meshes come within ``padding`` of each other (their surfaces cross when
the padding is 0) or one contains the other. Bounding spheres, box trees and convex hulls only skip
work: every "collides" is a pair of triangles within the padding or a point inside a closed mesh.

Per pair and state the sweep kernel also gives a lower bound of a free pair's distance (bounding
spheres, root boxes): the host keeps the nearest samples by it, and a second kernel measures their
exact distances (the clearance of pairs that never collide).
"""

from typing import Any

import warp as wp

from .cache import FUSED, INLINE_ALL, cached, cpu_flags, module_name
from .contain import containment_functions
from .fk import emit_local, pose_functions, tree_fk
from .geometry import FAR
from .hull import hull_function
from .quad import quad_walk
from .tree import sampling_functions, traversal_functions
from .types import Chain, bodies_struct, types_of, witness_vec
from .witness import APART, CROSSING, certified_function, first_crossing_function, pierce_function, witness_functions

SWEEP_FLAGS = f"{FUSED} {INLINE_ALL}"  # the sweep's module, compiled for the CPU


@cached
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


@cached
def pair_functions(scalar=wp.float32):
    """(pair_verdict, pair_distance) over a ``BodyArrays`` struct."""
    S, V3, M33, M34, M44 = types_of(scalar)
    node_gap, mesh_distance = traversal_functions(scalar)
    meshes_cross = quad_walk(scalar)
    rotation, relative = pose_helpers(scalar)
    enclosed = containment_functions(scalar)
    _, witness_hit = witness_functions(scalar)
    BodyArrays = bodies_struct(scalar)
    hulls_apart = hull_function(scalar)

    @wp.func
    def pair_verdict(m: BodyArrays, p: int, pa: M34, pb: M34, cell: int, cert: int, sphere_gap: S) -> S:
        """Pair p's bodies at poses pa and pb, whose bounding spheres are ``sphere_gap`` apart (at
        most the padding): at most the padding if they collide (-1 if one contains the other),
        else a lower bound of their distance above the padding (from their spheres and root
        boxes). ``cell``: the pair's witness cell, -1 for none; ``cert``: what the pose's certified
        cell says (``witness.certified_function``: APART, CROSSING or 0)."""
        a = m.pair_a[p]
        b = m.pair_b[p]
        if cert == CROSSING:  # crossing at every pose of the cell: what a witness or the walk finds
            return S(0.0)
        rel = relative(pa, pb)
        r = rotation(rel)
        t = V3(rel[0, 3], rel[1, 3], rel[2, 3])
        if cert == APART:  # apart at every pose of the cell: the gap the walk would have ended with
            gap = wp.max(sphere_gap, node_gap(m, m.root[a], m.root[b], r, t))
            if gap > m.padding:
                return gap
            return wp.max(gap, m.padding + S(1.0e-9))
        # the cell's witnesses crossed at its centre: tried first, they mostly cross here too
        if cell >= 0:
            if witness_hit(m, cell, r, t):
                return S(0.0)
        gap = wp.max(sphere_gap, node_gap(m, m.root[a], m.root[b], r, t))
        if gap > m.padding:
            return gap
        # hulls proved apart beyond the padding: the walk would find nothing (a surface lies within
        # its hull) and end with this gap, and neither body holds a point of the other
        if hulls_apart(m, a, b, r, t, m.padding):
            return wp.max(gap, m.padding + S(1.0e-9))
        # a vertex of one inside the other: they collide, surfaces crossing or not; asked before the
        # walk, it spares the walks that would end in a containment (a full walk finding nothing),
        # and after a walk that finds nothing it would be asked all the same
        if enclosed(m, a, b, r, t):
            return S(-1.0)
        if m.padding <= S(0.0):
            # the triangle pairs this pair's walks mostly find first: a crossing is a crossing
            if m.usual[p] >= 0:
                if witness_hit(m, m.usual[p], r, t):
                    return S(0.0)
            if meshes_cross(m, a, b, r, t):
                return S(0.0)
        else:
            d = mesh_distance(m, a, b, r, t, m.padding, m.padding)
            if d <= m.padding:
                return d
        return wp.max(gap, m.padding + S(1.0e-9))

    return pair_verdict, distance_functions(scalar)[0]


@cached
def distance_functions(scalar=wp.float32):
    """(pair_distance, pair_apart) over a ``BodyArrays`` struct: the exact distance kernels', and
    the free cells' test."""
    S, V3, M33, M34, M44 = types_of(scalar)
    _, mesh_distance = traversal_functions(scalar)
    rotation, _ = pose_helpers(scalar)
    enclosed = containment_functions(scalar)
    hulls_apart = hull_function(scalar)
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def pair_distance(m: BodyArrays, a: int, b: int, rel: M34) -> S:
        """The exact distance between bodies a and b, b's frame in a's being ``rel`` (0 where
        surfaces cross, -1 where one contains the other)."""
        r = rotation(rel)
        t = V3(rel[0, 3], rel[1, 3], rel[2, 3])
        d = mesh_distance(m, a, b, r, t, S(FAR), S(0.0))
        if d > S(0.0) and enclosed(m, a, b, r, t):
            return S(-1.0)
        return d

    @wp.func
    def pair_apart(m: BodyArrays, a: int, b: int, rel: M34, limit: S, contain: bool) -> bool:
        """Whether the surfaces of bodies a and b (b's frame in a's being ``rel``) are further apart
        than ``limit`` (the walk stops at the first distance within it), and with ``contain``,
        neither body contains the other."""
        r = rotation(rel)
        t = V3(rel[0, 3], rel[1, 3], rel[2, 3])
        if hulls_apart(m, a, b, r, t, limit):  # surfaces within their hulls, and neither holds the other
            return True
        if mesh_distance(m, a, b, r, t, limit, limit) <= limit:
            return False
        return not (contain and enclosed(m, a, b, r, t))

    return pair_distance, pair_apart


@cached
def collision_kernels(chain: Chain, links, bodies: int, scalar=wp.float32):
    """(collide, distance, witness, first, apart, crossing) for ``bodies`` bodies, riding on chain ``links``:

    ``collide(bodies, q, hit_out, gap_out)``: for configuration ``q[i]``, each pair's verdict
    ``hit_out[i, p]`` (1: collides) and ``gap_out[i, p]``, a lower bound of the pair's distance when
    it is free. ``distance(bodies, q, pair, distance_out)``: the exact distance of pair ``pair[i]``
    at ``q[i]``. ``witness(bodies, q, pair, witness_out)``: crossing triangle pairs of pair
    ``pair[i]`` at ``q[i]``, spread over all that cross (``witness_vec``, -1 where fewer cross).
    ``first(bodies, q, pair, triangles_out)``: the triangles (A's, B's; -1: none) at which the
    sweep's walk of pair ``pair[i]`` at ``q[i]`` first finds a crossing.
    ``apart(bodies, contain, q, pair, limit, apart_out)``: 1 where the surfaces of pair ``pair[i]``
    at ``q[i]`` are further apart than ``limit[i]`` (and with ``contain``, neither body contains
    the other). ``crossing(bodies, q, pair, pairs, move, a_moves, crossing_out)``: 1 where one of
    the triangle pairs ``pairs[i]`` (A's, B's; -1: none) crosses at ``q[i]`` so that it still does
    when the moving body's points move by up to ``move[i]`` (``witness.pierce_function``)."""
    return _make_kernels(module_name("collide", chain, links, bodies, scalar), chain, links, bodies, scalar)


def _body_pose(scalar):
    """(body_pose, body_centre): body b's pose, from the chain's poses or its fixed one; and its
    bounding sphere's centre in the world (a link may carry more than one body). Made
    anew for each kernel module: a generic (``Any``) function shared by modules whose local arrays
    differ in length is specialized for one of them only (a C++ build error in the others)."""
    S, V3, M33, M34, M44 = types_of(scalar)
    _, _, apply, _ = pose_functions(scalar)
    BodyArrays = bodies_struct(scalar)

    @wp.func
    def body_pose(m: BodyArrays, poses: Any, b: int) -> M34:
        k = m.link[b]
        if k >= 0:
            return poses[k]
        return m.pose[b]

    @wp.func
    def body_centre(m: BodyArrays, poses: Any, b: int) -> V3:
        return apply(body_pose(m, poses, b), m.center[b])

    return body_pose, body_centre


def _make_kernels(module: str, chain: Chain, links, bodies: int, scalar):
    fk = tree_fk(chain, set(int(k) for k in links) or {chain.root}, emit_local(scalar), scalar)
    body = _body_pose(scalar)  # one per module: collide and the pair kernels share it
    sweep = _sweep_kernel(module, chain, fk, body, bodies, scalar)
    if scalar == wp.float32:  # the sweep's: a pair's verdict inlined (no copy of the bodies' struct a call)
        cpu_flags(sweep.module, SWEEP_FLAGS)
    posed_pair = _posed_pair(chain, fk, body, scalar)
    return (sweep, *_pair_kernels(module, posed_pair, scalar), _apart_kernel(module, posed_pair, scalar),
            _crossing_kernel(module, posed_pair, scalar))


@cached
def finite_function(scalar=wp.float32):
    """finite_row(q, i): whether configuration q[i] is all finite numbers."""

    @wp.func
    def finite_row(q: wp.array2d(dtype=scalar), i: int) -> bool:
        ok = bool(True)
        for c in range(q.shape[1]):
            ok = ok and wp.isfinite(q[i, c])
        return ok

    return finite_row


def _sweep_kernel(module: str, chain: Chain, fk, body, bodies: int, scalar):
    """The sweep's kernel: every pair's verdict and gap at each configuration."""
    S, V3, M33, M34, M44 = types_of(scalar)
    BodyArrays = bodies_struct(scalar)
    pair_verdict, _ = pair_functions(scalar)
    witness_cell, _ = witness_functions(scalar)
    certified = certified_function(scalar)
    finite_row = finite_function(scalar)
    body_pose, body_centre = body
    n = max(len(chain.parent), 1)
    nb = max(bodies, 1)

    @wp.kernel(enable_backward=False, module=module)
    def collide(
        # Model:
        m: BodyArrays,
        # In:
        q: wp.array2d(dtype=S),
        # Out:
        hit_out: wp.array2d(dtype=wp.uint8),
        gap_out: wp.array2d(dtype=S),
    ):
        i = wp.tid()
        if not finite_row(q, i):  # no pose: every pair colliding (never cleared unchecked), no gap
            for p in range(m.pair_a.shape[0]):
                hit_out[i, p] = wp.uint8(1)
                gap_out[i, p] = S(wp.nan)
            return
        poses = wp.zeros(shape=n, dtype=M34)
        fk(q, i, poses)
        centres = wp.zeros(shape=nb, dtype=V3)  # each body's sphere once, not once per pair
        for k in range(wp.static(bodies)):
            centres[k] = body_centre(m, poses, k)
        for p in range(m.pair_a.shape[0]):
            a = m.pair_a[p]
            b = m.pair_b[p]
            g = wp.length(centres[a] - centres[b]) - m.radius[a] - m.radius[b]
            if g <= m.padding:
                g = pair_verdict(m, p, body_pose(m, poses, a), body_pose(m, poses, b), witness_cell(m, p, q, i),
                                 certified(m, p, q, i), g)
            if g <= m.padding:
                hit_out[i, p] = wp.uint8(1)
                gap_out[i, p] = S(0.0)
            else:
                hit_out[i, p] = wp.uint8(0)
                gap_out[i, p] = g

    return collide


def _posed_pair(chain: Chain, fk, body, scalar):
    """posed_pair(m, q, i, p): pair p's second body in the frame of its first, at configuration q[i]."""
    S, V3, M33, M34, M44 = types_of(scalar)
    BodyArrays = bodies_struct(scalar)
    _, relative = pose_helpers(scalar)
    body_pose, _ = body
    n = max(len(chain.parent), 1)

    @wp.func
    def posed_pair(m: BodyArrays, q: wp.array2d(dtype=S), i: int, p: int) -> M34:
        poses = wp.zeros(shape=n, dtype=M34)
        fk(q, i, poses)
        return relative(body_pose(m, poses, m.pair_a[p]), body_pose(m, poses, m.pair_b[p]))

    return posed_pair


def _pair_kernels(module: str, posed_pair, scalar):
    """(distance, witness, first): one pair at each configuration, its exact distance, its crossings
    spread over all, or the triangles at which the sweep's walk first finds one."""
    S, V3, M33, M34, M44 = types_of(scalar)
    BodyArrays = bodies_struct(scalar)
    _, pair_distance = pair_functions(scalar)
    rotation, _ = pose_helpers(scalar)
    crossing_sample = sampling_functions(scalar)
    first_triangles = first_crossing_function(scalar)

    @wp.kernel(enable_backward=False, module=module)
    def distance(
        # Model:
        m: BodyArrays,
        # In:
        q: wp.array2d(dtype=S),
        pair: wp.array(dtype=wp.int32),
        # Out:
        distance_out: wp.array(dtype=S),
    ):
        i = wp.tid()
        distance_out[i] = pair_distance(m, m.pair_a[pair[i]], m.pair_b[pair[i]], posed_pair(m, q, i, pair[i]))

    @wp.kernel(enable_backward=False, module=module)
    def witness(
        # Model:
        m: BodyArrays,
        # In:
        q: wp.array2d(dtype=S),
        pair: wp.array(dtype=wp.int32),
        # Out:
        witness_out: wp.array(dtype=witness_vec),
    ):
        i = wp.tid()
        rel = posed_pair(m, q, i, pair[i])
        t = V3(rel[0, 3], rel[1, 3], rel[2, 3])
        witness_out[i] = crossing_sample(m, m.pair_a[pair[i]], m.pair_b[pair[i]], rotation(rel), t)

    @wp.kernel(enable_backward=False, module=module)
    def first(
        # Model:
        m: BodyArrays,
        # In:
        q: wp.array2d(dtype=S),
        pair: wp.array(dtype=wp.int32),
        # Out:
        triangles_out: wp.array(dtype=wp.vec2i),
    ):
        i = wp.tid()
        triangles_out[i] = first_triangles(m, pair[i], posed_pair(m, q, i, pair[i]))

    return distance, witness, first


def _apart_kernel(module: str, posed_pair, scalar):
    """apart: whether one pair at each configuration is further apart than a limit (free cells)."""
    S = types_of(scalar)[0]
    BodyArrays = bodies_struct(scalar)
    _, pair_apart = distance_functions(scalar)

    @wp.kernel(enable_backward=False, module=module)
    def apart(
        # Model:
        m: BodyArrays,
        contain: int,  # 1: containment asked too
        # In:
        q: wp.array2d(dtype=S),
        pair: wp.array(dtype=wp.int32),
        limit: wp.array(dtype=S),
        # Out:
        apart_out: wp.array(dtype=wp.uint8),
    ):
        i = wp.tid()
        apart_out[i] = wp.uint8(0)
        if pair_apart(m, m.pair_a[pair[i]], m.pair_b[pair[i]], posed_pair(m, q, i, pair[i]), limit[i], contain != 0):
            apart_out[i] = wp.uint8(1)

    return apart


def _crossing_kernel(module: str, posed_pair, scalar):
    """crossing: whether one of given triangle pairs crosses robustly at each configuration."""
    S, V3, M33, M34, M44 = types_of(scalar)
    BodyArrays = bodies_struct(scalar)
    rotation, _ = pose_helpers(scalar)
    pierced = pierce_function(scalar)

    @wp.func
    def robust(m: BodyArrays, fixed: int, moving: int, r: M33, t: V3, move: S) -> bool:
        """Whether an edge of triangle ``moving`` (at x = r x' + t) pierces triangle ``fixed`` beyond ``move``."""
        f0 = m.triangles[3 * fixed]
        f1 = m.triangles[3 * fixed + 1]
        f2 = m.triangles[3 * fixed + 2]
        v0 = r * m.triangles[3 * moving] + t
        v1 = r * m.triangles[3 * moving + 1] + t
        v2 = r * m.triangles[3 * moving + 2] + t
        return pierced(f0, f1, f2, v0, v1, move) or pierced(f0, f1, f2, v1, v2, move) or \
            pierced(f0, f1, f2, v2, v0, move)

    @wp.kernel(enable_backward=False, module=module)
    def crossing(
        # Model:
        m: BodyArrays,
        # In:
        q: wp.array2d(dtype=S),
        pair: wp.array(dtype=wp.int32),
        pairs: wp.array2d(dtype=wp.int32),  # triangle pairs (A's, B's) side by side, -1: none
        move: wp.array(dtype=S),
        a_moves: wp.array(dtype=wp.int32),  # 1: the moving body is A (B's triangles held fixed)
        # Out:
        crossing_out: wp.array(dtype=wp.uint8),
    ):
        i = wp.tid()
        rel = posed_pair(m, q, i, pair[i])
        r = rotation(rel)
        t = V3(rel[0, 3], rel[1, 3], rel[2, 3])
        rt = wp.transpose(r)
        crossing_out[i] = wp.uint8(0)
        for k in range(pairs.shape[1] // 2):
            ta = pairs[i, 2 * k]
            tb = pairs[i, 2 * k + 1]
            if ta >= 0:
                if (a_moves[i] == 0 and robust(m, ta, tb, r, t, move[i])) or \
                        (a_moves[i] != 0 and robust(m, tb, ta, rt, -(rt * t), move[i])):
                    crossing_out[i] = wp.uint8(1)
                    break

    return crossing


@cached
def posed_kernel(scalar=wp.float32):
    """``posed(bodies, pose_a, pose_b, pair, gap_out)``: pair ``pair[i]``'s bodies at poses the
    host gives (``pose_a[i]``, ``pose_b[i]``: bodies on two chains, a robot and the track or
    positioner beside it), its verdict as ``collide`` gives it: ``gap_out[i]`` at most the padding
    where they collide (-1 where one contains the other), else a lower bound of their distance."""
    S, V3, M33, M34, M44 = types_of(scalar)
    BodyArrays = bodies_struct(scalar)
    pair_verdict, _ = pair_functions(scalar)
    _, _, apply, _ = pose_functions(scalar)

    @wp.kernel(enable_backward=False, module=module_name("collide_posed", scalar))
    def posed(
        # Model:
        m: BodyArrays,
        # In:
        pose_a: wp.array(dtype=M34),
        pose_b: wp.array(dtype=M34),
        pair: wp.array(dtype=wp.int32),
        # Out:
        gap_out: wp.array(dtype=S),
    ):
        i = wp.tid()
        a = m.pair_a[pair[i]]
        b = m.pair_b[pair[i]]
        g = wp.length(apply(pose_a[i], m.center[a]) - apply(pose_b[i], m.center[b])) - m.radius[a] - m.radius[b]
        if g <= m.padding:
            g = pair_verdict(m, pair[i], pose_a[i], pose_b[i], -1, 0, g)
        gap_out[i] = g

    return posed
