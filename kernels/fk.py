"""Forward kinematics as device code that other kernels call.

A mechanism's kinematics is a ``wp.func`` made once per chain (``tree_fk``): a closure per link,
recursion over the tree unrolled at code generation with ``wp.static``, each joint's axis and
point folded into constants with zero terms left out, poses passed down in registers. Every link
the caller asks for is handed to an ``emit`` function the caller chooses: write it to an output
array, keep it in a local array for later tests, or apply a flange offset. Precision is a choice
(float32 for batches, float64 for refinement and checks).

Chains longer than ``MAX_UNROLLED_LINKS`` and arbitrary subsets of links use the generic tree walk
(``generic_kernels``), which reads the chain from arrays and keeps poses in a scratch array.
"""

from functools import lru_cache
from typing import Any

import numpy as np
import warp as wp

from ..rsxml.closed import ANGLE, FOUR_BAR, SPEC
from ..rsxml.fourbar import DEAD_TOLERANCE
from .loops import loop_solver, unknowns
from .types import PRISMATIC, REVOLUTE, Chain, types_of

# Longer chains compile slowly when unrolled (code grows with the chain): they take the generic walk.
MAX_UNROLLED_LINKS = 64


# -- joint motions with constants folded ----------------------------------------------------------


def _entries(matrix_type, const, cos_coef, sin_coef, rows: int, cols: int):
    """A wp.func(c, s) -> matrix_type whose entries are const + c * cos_coef + s * sin_coef, with
    the terms whose coefficient is zero left out (so an axis along x, y or z costs what it should)."""
    S = matrix_type._wp_scalar_type_
    k0, kc, ks = ([float(v) for v in np.ravel(a)] for a in (const, cos_coef, sin_coef))

    @wp.func
    def value(c: S, s: S) -> matrix_type:
        m = matrix_type()
        for e in range(wp.static(rows * cols)):
            v = S(0.0)
            if wp.static(k0[e] != 0.0):
                v += wp.static(S(k0[e]))
            if wp.static(kc[e] != 0.0):
                v += wp.static(S(kc[e])) * c
            if wp.static(ks[e] != 0.0):
                v += wp.static(S(ks[e])) * s
            if wp.static(cols == 1):
                m[wp.static(e)] = v
            else:
                m[wp.static(e // cols), wp.static(e % cols)] = v
        return m

    return value


def _revolute(axis: np.ndarray, point: np.ndarray, T):
    """Rotation and translation of a revolute joint as functions of (cos, sin): Rodrigues written as
    R = a a^T + c (I - a a^T) + s [a]x and t = p - R p."""
    a, p = np.asarray(axis, float), np.asarray(point, float)
    outer = np.outer(a, a)
    ortho = np.eye(3) - outer
    skew = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    rot = _entries(T.mat33, outer, ortho, skew, 3, 3)
    tra = _entries(T.vec3, p - outer @ p, -ortho @ p, -skew @ p, 3, 1)
    return rot, tra


# -- the tree visitor ------------------------------------------------------------------------------


def tree_fk(chain: Chain, needed, emit, scalar=wp.float32):
    """``fk(q, i, out)``: the poses of configuration ``q[i]`` for the links in ``needed`` (and only
    the paths to them), each handed to ``emit(out, i, k, rotation, translation)`` with ``k`` the
    link's index in the chain."""
    T = types_of(scalar)
    _, V3, M33, M34, M44 = T
    needed = frozenset(int(k) for k in needed)
    keep = chain.ancestors(needed)
    VX = wp.types.vector(unknowns(chain), scalar)
    root = _link_visitor(chain, chain.root, keep, needed, emit, T, VX)
    # loops with no closed form are solved once per configuration, before any link is posed
    solve = loop_solver(chain, scalar) if any(chain.unknown[k] >= 0 for k in keep) else None

    @wp.func
    def fk(q: wp.array2d(dtype=scalar), i: int, out: Any):
        x = VX()
        if wp.static(solve is not None):
            x = wp.static(solve)(q, i)
        wp.static(root)(q, i, wp.identity(n=3, dtype=scalar), V3(), out, x)

    return fk


def _link_visitor(chain: Chain, k: int, keep: set, needed: frozenset, emit, T, VX):
    """The wp.func that poses link ``k`` from its parent's pose, emits it if needed, and visits the
    children on the way to a needed link (``x``: the Newton-solved passive joints)."""
    S, V3, M33, _, _ = T
    kids = tuple(_link_visitor(chain, c, keep, needed, emit, T, VX) for c in chain.children(k) if c in keep)
    col, jtype = int(chain.qidx[k]), int(chain.jtype[k])
    on_root = int(chain.parent[k]) >= 0 and int(chain.parent[int(chain.parent[k])]) < 0  # parent pose is identity
    follows = bool(np.any(chain.mimic[k] != 0.0) or chain.closed[k][0] != 0.0 or chain.unknown[k] >= 0)
    moves = (col >= 0 or follows) and jtype in (REVOLUTE, PRISMATIC)
    value = _joint_value(chain, k, T)
    revolute = jtype == REVOLUTE
    rot, tra = _revolute(chain.axis[k], chain.point[k], T) if moves and revolute else (None, None)
    # a four-bar's or a Newton-solved joint is NaN where its loop cannot close: the pose then NaN whole
    can_fail = bool(chain.closed[k][0] == FOUR_BAR or chain.unknown[k] >= 0)
    axis = V3(*(float(v) for v in chain.axis[k]))
    emits = k in needed

    @wp.func
    def visit(q: wp.array2d(dtype=S), i: int, rp: M33, tp: V3, out: Any, x: VX):
        r = rp
        t = tp
        if wp.static(moves):
            th = wp.static(value)(q, i, x)
            if wp.static(revolute):
                c = wp.cos(th)
                s = wp.sin(th)
                if wp.static(on_root):
                    r = wp.static(rot)(c, s)
                    t = wp.static(tra)(c, s)
                else:
                    r = rp * wp.static(rot)(c, s)
                    t = rp * wp.static(tra)(c, s) + tp
            else:
                t = rp * (th * wp.static(axis)) + tp
            if wp.static(can_fail):
                if wp.isnan(th):
                    r = r * S(wp.nan)
                    t = t * S(wp.nan)
        if wp.static(emits):
            wp.static(emit)(out, i, wp.static(k), r, t)
        for c in range(wp.static(len(kids))):
            wp.static(kids[c])(q, i, r, t, out, x)

    return visit


@lru_cache(maxsize=None)
def slider_function(scalar=wp.float32):
    """slider_value(spec, theta): a balance cylinder's pivot angle (kind ANGLE) or piston stroke
    (kind STROKE) for the arm angle ``theta`` (``rswarp.rsxml.slider``: the pin turns about the arm
    joint O from A0; the cylinder runs from the pivot P to the pin)."""
    S = scalar
    V = wp.types.vector(SPEC, scalar)

    @wp.func
    def slider_value(spec: V, theta: S) -> S:
        c = wp.cos(theta)
        s = wp.sin(theta)
        rx = spec[4] - spec[2]
        ry = spec[5] - spec[3]
        dx = spec[2] + c * rx - s * ry - spec[6]
        dy = spec[3] + s * rx + c * ry - spec[7]
        ex = spec[4] - spec[6]
        ey = spec[5] - spec[7]
        if spec[0] == S(float(ANGLE)):
            return spec[1] * wp.atan2(ex * dy - ey * dx, ex * dx + ey * dy)
        return spec[1] * (wp.sqrt(dx * dx + dy * dy) - wp.sqrt(ex * ex + ey * ey))

    return slider_value


@lru_cache(maxsize=None)
def four_bar_function(scalar=wp.float32):
    """four_bar_value(spec, theta): a four-bar's passive joint for the driven angle ``theta``
    (``rswarp.rsxml.fourbar``, whose ``four_bar_values`` is the host twin): the corner V2 where the
    circles about V1 and V3 meet, on its side at zero; NaN past a dead point."""
    S = scalar
    V = wp.types.vector(SPEC, scalar)
    V2 = wp.types.vector(2, scalar)

    @wp.func
    def turn(a: V2, b: V2) -> S:
        return wp.atan2(a[0] * b[1] - a[1] * b[0], wp.dot(a, b))

    @wp.func
    def four_bar_value(spec: V, theta: S) -> S:
        v0 = V2(spec[1], spec[2])
        v1_0 = V2(spec[3], spec[4])
        v2_0 = V2(spec[5], spec[6])
        v3 = V2(spec[7], spec[8])
        r = v1_0 - v0
        c = wp.cos(theta)
        s = wp.sin(theta)
        v1 = v0 + V2(c * r[0] - s * r[1], s * r[0] + c * r[1])
        e1 = v2_0 - v1_0
        e2 = v3 - v2_0
        l1 = wp.dot(e1, e1)
        d = v3 - v1
        dd = wp.dot(d, d)
        a = (l1 - wp.dot(e2, e2) + dd) / (S(2.0) * dd)  # the foot of V2 on V1-V3, as a share of it
        h2 = l1 / dd - a * a  # V2's offset across V1-V3, squared, as a share of it
        if h2 < -S(DEAD_TOLERANCE) * l1 / dd:
            return S(wp.nan)
        cross0 = (v3[0] - v1_0[0]) * e1[1] - (v3[1] - v1_0[1]) * e1[0]
        h = wp.sign(cross0) * wp.sqrt(wp.max(h2, S(0.0)))
        v2 = v1 + a * d + h * V2(-d[1], d[0])
        return spec[9] * theta + spec[10] * turn(e1, v2 - v1) + spec[11] * turn(e2, v3 - v2)

    return four_bar_value


@lru_cache(maxsize=None)
def closed_function(scalar=wp.float32):
    """closed_value(spec, theta): a loop's passive joint by its closed form's kind (the generic
    walk, which reads specs from arrays; unrolled kernels choose the form at code generation)."""
    S = scalar
    V = wp.types.vector(SPEC, scalar)
    slider_value = slider_function(scalar)
    four_bar_value = four_bar_function(scalar)

    @wp.func
    def closed_value(spec: V, theta: S) -> S:
        if spec[0] == S(float(FOUR_BAR)):
            return four_bar_value(spec, theta)
        return slider_value(spec, theta)

    return closed_value


def _joint_value(chain: Chain, k: int, T):
    """value(q, i, x): link k's joint value: its column of q; for a passive joint of a solved loop,
    its sum of active columns (a parallelogram), its closed form (balance cylinder, four-bar), or
    its unknown in the loops' Newton solve ``x``."""
    S = T.scalar
    col = int(chain.qidx[k])
    follows = tuple((c, float(v)) for c, v in enumerate(chain.mimic[k]) if v != 0.0)
    arm = tuple((c, float(v)) for c, v in enumerate(chain.closed_coef[k]) if v != 0.0)
    kind = int(chain.closed[k][0])
    terms = arm if kind else follows
    cols, coefs = tuple(c for c, _ in terms), tuple(v for _, v in terms)
    spec = wp.types.vector(SPEC, S)(*(float(v) for v in chain.closed[k]))
    form = four_bar_function(S) if kind == FOUR_BAR else slider_function(S)
    u = int(chain.unknown[k])

    @wp.func
    def value(q: wp.array2d(dtype=S), i: int, x: Any) -> S:
        if wp.static(col >= 0):
            return q[i, wp.static(max(col, 0))]
        if wp.static(u >= 0):
            return x[wp.static(max(u, 0))]
        th = S(0.0)
        for n in range(wp.static(len(cols))):
            th += wp.static(S(coefs[n])) * q[i, wp.static(cols[n])]
        if wp.static(kind != 0):
            th = wp.static(form)(wp.static(spec), th)
        return th

    return value


# -- what to do with a pose ---------------------------------------------------------------------------


@lru_cache(maxsize=None)
def pose_functions(scalar=wp.float32):
    """(to_mat44, to_mat34, apply, rotate) for one precision: a pose as a 4x4 or 3x4 matrix, a
    point moved by a 3x4 pose, a direction turned by it."""
    T = types_of(scalar)
    _, V3, M33, M34, M44 = T
    S = scalar

    @wp.func
    def to_mat44(r: M33, t: V3) -> M44:
        return M44(r[0, 0], r[0, 1], r[0, 2], t[0], r[1, 0], r[1, 1], r[1, 2], t[1],
                       r[2, 0], r[2, 1], r[2, 2], t[2], S(0.0), S(0.0), S(0.0), S(1.0))

    @wp.func
    def to_mat34(r: M33, t: V3) -> M34:
        return M34(r[0, 0], r[0, 1], r[0, 2], t[0], r[1, 0], r[1, 1], r[1, 2], t[1],
                       r[2, 0], r[2, 1], r[2, 2], t[2])

    @wp.func
    def apply(m: M34, p: V3) -> V3:
        return V3(m[0, 0] * p[0] + m[0, 1] * p[1] + m[0, 2] * p[2] + m[0, 3],
                      m[1, 0] * p[0] + m[1, 1] * p[1] + m[1, 2] * p[2] + m[1, 3],
                      m[2, 0] * p[0] + m[2, 1] * p[1] + m[2, 2] * p[2] + m[2, 3])

    @wp.func
    def rotate(m: M34, d: V3) -> V3:
        return V3(m[0, 0] * d[0] + m[0, 1] * d[1] + m[0, 2] * d[2],
                      m[1, 0] * d[0] + m[1, 1] * d[1] + m[1, 2] * d[2],
                      m[2, 0] * d[0] + m[2, 1] * d[1] + m[2, 2] * d[2])

    return to_mat44, to_mat34, apply, rotate


def emit_matrix(scalar=wp.float32):
    """emit: ``out[i, k]`` = the link's pose as a 4x4 matrix (``out`` is an (N, n_links) array)."""
    to_mat44 = pose_functions(scalar)[0]
    T = types_of(scalar)
    _, V3, M33, M34, M44 = T

    @wp.func
    def emit(out: wp.array2d(dtype=M44), i: int, k: int, r: M33, t: V3):
        out[i, k] = to_mat44(r, t)

    return emit


def emit_frame(offset: np.ndarray, scalar=wp.float32):
    """emit: ``out[i]`` = the link's pose times a constant 4x4 ``offset`` (a flange on the link)."""
    to_mat44 = pose_functions(scalar)[0]
    T = types_of(scalar)
    _, V3, M33, M34, M44 = T
    rot = M33(*(float(v) for v in np.asarray(offset)[:3, :3].ravel()))
    tra = V3(*(float(v) for v in np.asarray(offset)[:3, 3]))

    @wp.func
    def emit(out: wp.array(dtype=M44), i: int, k: int, r: M33, t: V3):
        out[i] = to_mat44(r * wp.static(rot), r * wp.static(tra) + t)

    return emit


def emit_local(scalar=wp.float32):
    """emit: ``out[k]`` = the link's pose as a 3x4 matrix, into a kernel-local array
    (``wp.zeros(shape=n_links, dtype=mat34)``) for the tests that follow in the same kernel."""
    to_mat34 = pose_functions(scalar)[1]
    T = types_of(scalar)
    _, V3, M33, M34, M44 = T

    @wp.func
    def emit(out: Any, i: int, k: int, r: M33, t: V3):
        out[k] = to_mat34(r, t)

    return emit


@lru_cache(maxsize=None)
def wrist_centre(scalar=wp.float32):
    """The wrist centre as ABB defines it: the point of the J5 axis (p5, d5) nearest the J4 axis
    (p4, d4), unit directions; where the axes are parallel, J5's anchor."""
    T = types_of(scalar)
    _, V3, M33, M34, M44 = T
    S = scalar

    @wp.func
    def centre(p4: V3, d4: V3, p5: V3, d5: V3) -> V3:
        w = p5 - p4
        b = wp.dot(d4, d5)
        den = S(1.0) - b * b
        if den < S(1.0e-12):
            return p5
        return p5 + ((b * wp.dot(w, d4) - wp.dot(w, d5)) / den) * d5

    return centre


# -- generic tree walk: any subset of links, any chain length ---------------------------------------


@lru_cache(maxsize=None)
def generic_walk(scalar=wp.float32):
    """(Tree struct, walk): the chain as device arrays, and a wp.func that writes every link's pose
    into ``poses[i]``, parents first."""
    T = types_of(scalar)
    _, V3, M33, M34, M44 = T
    S = scalar
    _, to_mat34, apply, _ = pose_functions(scalar)
    closed_value = closed_function(scalar)

    @wp.struct
    class Tree:
        parent: wp.array(dtype=wp.int32)
        jtype: wp.array(dtype=wp.int32)
        qidx: wp.array(dtype=wp.int32)
        axis: wp.array(dtype=V3)
        point: wp.array(dtype=V3)
        order: wp.array(dtype=wp.int32)
        follows: wp.array(dtype=wp.int32)  # 1: a passive joint of a solved loop (mimic or closed rows)
        mimic: wp.array2d(dtype=S)
        closed: wp.array(dtype=wp.types.vector(SPEC, S))
        closed_coef: wp.array2d(dtype=S)

    @wp.func
    def walk(tree: Tree, q: wp.array2d(dtype=S), i: int, poses: wp.array2d(dtype=M34)):
        for o in range(tree.order.shape[0]):
            k = tree.order[o]
            p = tree.parent[k]
            if p < 0:
                poses[i, k] = to_mat34(wp.identity(n=3, dtype=S), V3())
                continue
            th = S(0.0)
            if tree.qidx[k] >= 0:
                th = q[i, tree.qidx[k]]
            elif tree.follows[k] != 0:  # a passive joint of a solved loop
                arm = S(0.0)
                for c in range(q.shape[1]):
                    th += tree.mimic[k, c] * q[i, c]
                    arm += tree.closed_coef[k, c] * q[i, c]
                if tree.closed[k][0] != S(0.0):
                    th = closed_value(tree.closed[k], arm)
            a = tree.axis[k]
            r = wp.identity(n=3, dtype=S)
            t = th * a
            if tree.jtype[k] == REVOLUTE:
                r = wp.quat_to_matrix(wp.quat_from_axis_angle(a, th))
                t = tree.point[k] - r * tree.point[k]
            if wp.isnan(th):  # past a dead point: no pose at all
                r = r * S(wp.nan)
                t = t * S(wp.nan)
            m = poses[i, p]
            rp = M33(m[0, 0], m[0, 1], m[0, 2], m[1, 0], m[1, 1], m[1, 2], m[2, 0], m[2, 1], m[2, 2])
            poses[i, k] = to_mat34(rp * r, apply(m, t))

    return Tree, walk


@lru_cache(maxsize=None)
def generic_kernels(scalar=wp.float32):
    """(Tree struct, frames kernel, wrist_flange kernel) reading the chain from arrays.

    ``frames``: ``out[i, j]`` = pose of link ``links[j]`` times ``offsets[j]``.
    ``wrist_flange``: flange position and wrist centre from link indices and constants."""
    T = types_of(scalar)
    _, V3, M33, M34, M44 = T
    S = scalar
    _, _, apply, rotate = pose_functions(scalar)
    centre = wrist_centre(scalar)
    Tree, walk = generic_walk(scalar)
    module = f"rswarp_fk_generic_{scalar.__name__}"

    @wp.kernel(enable_backward=False, module=module)
    def frames(tree: Tree, links: wp.array(dtype=wp.int32), offsets: wp.array(dtype=M44),
               q: wp.array2d(dtype=S), poses: wp.array2d(dtype=M34), out: wp.array2d(dtype=M44)):
        i = wp.tid()
        walk(tree, q, i, poses)
        for j in range(links.shape[0]):
            m = poses[i, links[j]]
            full = M44(m[0, 0], m[0, 1], m[0, 2], m[0, 3], m[1, 0], m[1, 1], m[1, 2], m[1, 3],
                       m[2, 0], m[2, 1], m[2, 2], m[2, 3], S(0.0), S(0.0), S(0.0), S(1.0))
            out[i, j] = full * offsets[j]

    @wp.kernel(enable_backward=False, module=module)
    def wrist_flange(tree: Tree, links: wp.array(dtype=wp.int32), consts: wp.array(dtype=V3),
                     q: wp.array2d(dtype=S), poses: wp.array2d(dtype=M34),
                     wrist: wp.array(dtype=V3), flange: wp.array(dtype=V3)):
        """links = (flange link, J4's link, J5's link); consts = (flange offset, p4, a4, p5, a5)."""
        i = wp.tid()
        walk(tree, q, i, poses)
        flange[i] = apply(poses[i, links[0]], consts[0])
        if links.shape[0] < 3:
            wrist[i] = V3()
            return
        m4 = poses[i, links[1]]
        m5 = poses[i, links[2]]
        wrist[i] = centre(apply(m4, consts[1]), rotate(m4, consts[2]), apply(m5, consts[3]), rotate(m5, consts[4]))

    return Tree, frames, wrist_flange


# -- the kernels of one chain ------------------------------------------------------------------------


_CHAIN_KERNELS: dict[str, tuple] = {}


def chain_kernels(chain: Chain, flanges, wrist, scalar=wp.float32):
    """The unrolled kernels of one chain, made once per chain and precision, in a Warp module of
    their own (named by the chain's content, so Warp's cache serves later processes):

    ``all_links(q, out)``: every link's 4x4 pose; ``flange[f](q, out)``: flange f's pose;
    ``wrist_flange[f](q, wrist, flange)``: wrist centre and flange position.
    ``flanges`` are (link, 4x4 offset); ``wrist`` is ((link, point, axis) of J4, of J5) or None."""
    import hashlib

    h = hashlib.sha256(chain.digest().encode())
    for link, m in flanges:
        h.update(np.asarray([link], np.int64).tobytes() + np.asarray(m, float).tobytes())
    for link, p, a in wrist or ():
        h.update(np.asarray([link], np.int64).tobytes() + np.asarray([*p, *a], float).tobytes())
    key = f"{h.hexdigest()[:16]}_{scalar.__name__}"
    if key not in _CHAIN_KERNELS:
        _CHAIN_KERNELS[key] = _make_chain_kernels(key, chain, flanges, wrist, scalar)
    return _CHAIN_KERNELS[key]


def _make_chain_kernels(key: str, chain: Chain, flanges, wrist, scalar):
    T = types_of(scalar)
    _, V3, M33, M34, M44 = T
    S = scalar
    module = f"rswarp_fk_{key}"
    n = len(chain.parent)
    fk_all = tree_fk(chain, range(n), emit_matrix(scalar), scalar)

    @wp.kernel(enable_backward=False, module=module)
    def all_links(q: wp.array2d(dtype=S), out: wp.array2d(dtype=M44)):
        fk_all(q, wp.tid(), out)

    flange_kernels = tuple(_flange_kernel(chain, link, m, scalar, module) for link, m in flanges)
    wrist_kernels = tuple(_wrist_kernel(chain, link, m, wrist, scalar, module) for link, m in flanges)
    return all_links, flange_kernels, wrist_kernels


def _flange_kernel(chain: Chain, link: int, offset: np.ndarray, scalar, module: str):
    T = types_of(scalar)
    _, V3, M33, M34, M44 = T
    fk = tree_fk(chain, [link], emit_frame(offset, scalar), scalar)

    @wp.kernel(enable_backward=False, module=module)
    def flange(q: wp.array2d(dtype=scalar), out: wp.array(dtype=M44)):
        fk(q, wp.tid(), out)

    return flange


def _wrist_kernel(chain: Chain, link: int, offset: np.ndarray, wrist, scalar, module: str):
    T = types_of(scalar)
    _, V3, M33, M34, M44 = T
    _, _, apply, rotate = pose_functions(scalar)
    centre = wrist_centre(scalar)
    n = len(chain.parent)
    has_wrist = wrist is not None
    (l4, p4, a4), (l5, p5, a5) = wrist if has_wrist else ((link, (0, 0, 0), (1, 0, 0)),) * 2
    fk = tree_fk(chain, {link, l4, l5} if has_wrist else {link}, emit_local(scalar), scalar)
    tf, c4, d4, c5, d5 = (V3(*(float(x) for x in v)) for v in (offset[:3, 3], p4, a4, p5, a5))

    @wp.kernel(enable_backward=False, module=module)
    def wrist_flange(q: wp.array2d(dtype=scalar), wrist: wp.array(dtype=V3), flange: wp.array(dtype=V3)):
        i = wp.tid()
        poses = wp.zeros(shape=wp.static(n), dtype=M34)
        fk(q, i, poses)
        flange[i] = apply(poses[wp.static(link)], wp.static(tf))
        if wp.static(has_wrist):
            m4 = poses[wp.static(l4)]
            m5 = poses[wp.static(l5)]
            wrist[i] = centre(apply(m4, wp.static(c4)), rotate(m4, wp.static(d4)),
                              apply(m5, wp.static(c5)), rotate(m5, wp.static(d5)))
        else:
            wrist[i] = V3()

    return wrist_flange
