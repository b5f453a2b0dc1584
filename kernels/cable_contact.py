"""What a cable meets and how it is measured, as device functions for ``rswarp.kernels.cable``:
contact with the link meshes (Warp ``wp.Mesh`` BVH queries in each link's zero-position frame,
with the cable's radius) and the floor, the bend radius along the chain, and the twist between
two clamped ends (a reference normal parallel-transported along the chain), and the stretch between
consecutive attachments."""

from typing import Any

import warp as wp

from .fk import pose_functions
from .types import types_of

BIG = 1.0e30
TINY = 1.0e-12


@wp.struct
class CableParams:
    """One cable on one mechanism (SI). Per particle: rest length of segment k (particles k, k + 1),
    inverse mass, carrying link (-1: free) and its zero-position point, bending compliance of the
    curvature at k; ``touch[k, j]``: particle k may touch link j (it is not beside its own
    attachment to j). Per link: its mesh in its zero-position frame (id 0: none) and a bounding
    sphere (centre, radius) that spares the query of far links. ``ends``: the links clamping the
    first and the last segment (-1: that end turns freely); ``start_normal``, ``end_normal``: their
    reference normals at the zero position, parallel-transported into each other along the rest
    shape, so the rest shape has no twist. ``pair_a``, ``pair_b``: consecutive attached particles,
``pair_length`` the cable's length between them."""

    rest: wp.array(dtype=wp.float32)
    w: wp.array(dtype=wp.float32)
    link: wp.array(dtype=wp.int32)
    local: wp.array(dtype=wp.vec3)
    compliance: wp.array(dtype=wp.float32)
    touch: wp.array2d(dtype=wp.int32)
    mesh: wp.array(dtype=wp.uint64)
    sphere: wp.array(dtype=wp.vec4)
    ends: wp.vec2i
    start_normal: wp.vec3
    end_normal: wp.vec3
    gravity: wp.vec3
    radius: wp.float32
    damping: wp.float32
    floor: wp.float32
    margin: wp.float32  # contact query distance beyond the radius, per substep
    reach: wp.float32  # clearance query distance beyond the radius, per frame
    max_speed: wp.float32  # a particle faster than this has blown up
    pair_a: wp.array(dtype=wp.int32)
    pair_b: wp.array(dtype=wp.int32)
    pair_length: wp.array(dtype=wp.float32)


_, _, _apply, _rotate = pose_functions(wp.float32)
M34 = types_of(wp.float32).mat34

# Functions taking a kernel-local array (typed Any) are made per kernel by a factory: Warp
# specializes them by the array's size, which differs between kernels.


@wp.func
def to_link(m: M34, p: wp.vec3) -> wp.vec3:
    """``p`` in the link's zero-position frame: the 3x4 pose's inverse applied."""
    d = p - wp.vec3(m[0, 3], m[1, 3], m[2, 3])
    return wp.vec3(m[0, 0] * d[0] + m[1, 0] * d[1] + m[2, 0] * d[2],
                   m[0, 1] * d[0] + m[1, 1] * d[1] + m[2, 1] * d[2],
                   m[0, 2] * d[0] + m[1, 2] * d[1] + m[2, 2] * d[2])


@wp.func
def surface(mesh: wp.uint64, pz: wp.vec3, max_dist: float):
    """Signed distance from ``pz`` to the mesh (negative inside) and the outward normal there;
    BIG when no face is within ``max_dist``."""
    q = wp.mesh_query_point_sign_normal(mesh, pz, max_dist)
    if not q.result:
        return float(BIG), wp.vec3(0.0, 0.0, 1.0)
    d = pz - wp.mesh_eval_position(mesh, q.face, q.u, q.v)
    dist = wp.length(d)
    n = wp.mesh_eval_face_normal(mesh, q.face)
    if dist > TINY:
        n = d / dist
    if q.sign < 0.0:
        return -dist, -n
    return dist, n


@wp.func
def _link_gap(p: wp.vec3, m: M34, mesh: wp.uint64, sphere: wp.vec4, radius: float, query: float):
    """The clearance from a particle to one link's mesh (BIG beyond ``query``, or beyond its
    bounding sphere), and where the particle goes to touch it from outside."""
    pz = to_link(m, p)
    if wp.length(pz - wp.vec3(sphere[0], sphere[1], sphere[2])) >= sphere[3] + radius + query:
        return float(BIG), p
    signed, n = surface(mesh, pz, radius + query)
    gap = signed - radius
    return gap, _apply(m, pz - gap * n)


def near_function(n_links: int):
    """``near(p, params, poses, query, push, clear, at)`` for a tree of ``n_links`` links: each free
    particle against every link it may touch and the floor (slot ``n_links``). It lowers the least
    clearance per slot (surface to surface, where within ``query``) and notes which particle; with
    ``push``, particles inside are moved out along the normal (frictionless contact). A particle
    deeper than the radius plus ``query`` cannot have got there in one substep: the robot carried
    it (a trajectory through the floor); it is counted, not pushed."""

    @wp.func
    def note(clear: Any, at: Any, j: int, gap: float, k: int):
        if gap < clear[j]:
            clear[j] = gap
            at[j] = k

    @wp.func
    def near(p: Any, params: CableParams, poses: Any, query: float, push: int, clear: Any, at: Any):
        for k in range(params.w.shape[0]):
            if params.w[k] <= 0.0:
                continue
            for j in range(n_links):
                if params.mesh[j] != wp.uint64(0) and params.touch[k, j] != 0:
                    gap, out = _link_gap(p[k], poses[j], params.mesh[j], params.sphere[j], params.radius, query)
                    note(clear, at, j, gap, k)
                    if push != 0 and gap < 0.0:
                        p[k] = out
            gap = p[k][2] - params.radius - params.floor
            note(clear, at, n_links, gap, k)
            if push != 0 and gap < 0.0 and gap > -params.radius - query:
                p[k] = wp.vec3(p[k][0], p[k][1], params.floor + params.radius)

    return near


def sharpest_function():
    """``sharpest(p, params) -> (radius, k)``: the least bend radius along the chain and where: at
    particle k, l / (2 tan(angle / 2)) with l the mean of its two segments' rest lengths (the
    discrete curvature of elastic rods)."""

    @wp.func
    def sharpest(p: Any, params: CableParams):
        best = float(BIG)
        where = int(-1)
        for k in range(1, params.w.shape[0] - 1):
            a = p[k] - p[k - 1]
            b = p[k + 1] - p[k]
            s = wp.length(wp.cross(a, b))
            if s > TINY:
                mean = 0.5 * (params.rest[k - 1] + params.rest[k])
                r = mean * (wp.length(a) * wp.length(b) + wp.dot(a, b)) / (2.0 * s)
                if r < best:
                    best = r
                    where = k
        return best, where

    return sharpest


def twist_function():
    """``twist(p, params, poses)``: the turn (rad) of the last clamp's normal about the cable from the
    first clamp's normal carried along the chain by parallel transport; 0 unless both ends are
    clamped."""

    @wp.func
    def twist(p: Any, params: CableParams, poses: Any) -> float:
        if params.ends[0] < 0 or params.ends[1] < 0:
            return 0.0
        n = _rotate(poses[params.ends[0]], params.start_normal)
        t0 = wp.normalize(p[1] - p[0])
        for k in range(1, params.w.shape[0] - 1):
            t1 = wp.normalize(p[k + 1] - p[k])
            b = wp.cross(t0, t1)
            c = wp.dot(t0, t1)
            if c > -0.999:
                n = c * n + wp.cross(b, n) + b * (wp.dot(b, n) / (1.0 + c))
            t0 = t1
        e = _rotate(poses[params.ends[1]], params.end_normal)
        return wp.atan2(wp.dot(t0, wp.cross(n, e)), wp.dot(n, e))

    return twist


def stretch_function():
    """``stretch(p, params)``: the greatest straight distance between consecutive attachments over
    the cable's length between them (1: pulled straight); 0 with fewer than two attachments."""

    @wp.func
    def stretch(p: Any, params: CableParams) -> float:
        most = float(0.0)
        for k in range(params.pair_a.shape[0]):
            d = wp.length(p[params.pair_b[k]] - p[params.pair_a[k]]) / params.pair_length[k]
            most = wp.max(most, d)
        return most

    return stretch
