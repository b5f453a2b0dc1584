"""Forward kinematics as device code that other kernels call.

A mechanism's kinematics is a ``wp.func`` made once per chain (``tree_fk``): a closure per link,
recursion over the tree unrolled at code generation with ``wp.static``, each joint's axis and
point folded into constants with zero terms left out, poses passed down in registers. Every link
the caller asks for is handed to an ``emit`` function the caller chooses: write it to an output
array, keep it in a local array for later tests, or apply a flange offset. Precision is a choice
(float32 for batches, float64 for refinement and checks).

Chains longer than ``MAX_UNROLLED_LINKS`` and arbitrary subsets of links use the generic tree walk
(``walk.generic_kernels``), which reads the chain from arrays and keeps poses in a scratch array.
"""

from typing import Any

import numpy as np
import warp as wp

from .cache import cached, module_name
from .closed_forms import four_bar_function, slider_function
from .loops import loop_solver, unknowns
from .motion import revolute_after, revolute_motion
from .specs import FOUR_BAR, SPEC
from .trig import sincos_func
from .types import PRISMATIC, REVOLUTE, Chain, types_of

# Longer chains compile slowly when unrolled (code grows with the chain): they take the generic walk.
MAX_UNROLLED_LINKS = 64


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
    follows = bool(np.any(chain.mimic[k] != 0.0) or chain.closed_form[k][0] != 0.0 or chain.unknown[k] >= 0)
    moves = (col >= 0 or follows) and jtype in (REVOLUTE, PRISMATIC)
    value = _joint_value(chain, k, T)
    revolute = jtype == REVOLUTE
    rot, tra = revolute_after(chain.axis[k], chain.point[k], T) if moves and revolute else (None, None)
    pose, shift = revolute_motion(chain.axis[k], chain.point[k], T) if moves and revolute else (None, None)
    # float32 (the batches) takes the inline sine and cosine and the products by R's nonzero entries
    # alone; float64 (refinement, checks, shortfalls) stays libm's and the full product, bit for bit
    fast = S == wp.float32
    # a four-bar's or a Newton-solved joint is NaN where its loop cannot close: the pose then NaN whole
    can_fail = bool(chain.closed_form[k][0] == FOUR_BAR or chain.unknown[k] >= 0)
    axis = V3(*(float(v) for v in chain.axis[k]))
    emits = k in needed
    sincos = sincos_func(S)

    @wp.func
    def visit(q: wp.array2d(dtype=S), i: int, rp: M33, tp: V3, out: Any, x: VX):
        r = rp
        t = tp
        if wp.static(moves):
            th = wp.static(value)(q, i, x)
            if wp.static(revolute):
                c = S(0.0)
                s = S(0.0)
                if wp.static(fast):
                    sc = wp.static(sincos)(th)
                    s = sc[0]
                    c = sc[1]
                else:
                    c = wp.cos(th)
                    s = wp.sin(th)
                if wp.static(on_root):
                    r = wp.static(pose)(c, s)
                    t = wp.static(shift)(c, s)
                elif wp.static(fast):
                    r = wp.static(rot)(rp, c, s)  # rp R, its products by R's zeros left out
                    t = wp.static(tra)(rp, tp, c, s)
                else:
                    r = rp * wp.static(pose)(c, s)
                    t = rp * wp.static(shift)(c, s) + tp
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


def _joint_value(chain: Chain, k: int, T):
    """value(q, i, x): link k's joint value: its column of q; for a passive joint of a solved loop,
    its sum of active columns (a parallelogram), its closed form (balance cylinder, four-bar), or
    its unknown in the loops' Newton solve ``x``."""
    S = T.scalar
    col = int(chain.qidx[k])
    follows = tuple((c, float(v)) for c, v in enumerate(chain.mimic[k]) if v != 0.0)
    arm = tuple((c, float(v)) for c, v in enumerate(chain.closed_input[k]) if v != 0.0)
    kind = int(chain.closed_form[k][0])
    terms = arm if kind else follows
    cols, coefs = tuple(c for c, _ in terms), tuple(v for _, v in terms)
    spec = wp.types.vector(SPEC, S)(*(float(v) for v in chain.closed_form[k]))
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


@cached
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


@cached
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


# -- the kernels of one chain ------------------------------------------------------------------------


@cached
def chain_kernels(chain: Chain, flanges, wrist, scalar=wp.float32):
    """The unrolled kernels of one chain, made once per chain and precision, in a Warp module of
    their own (named by the chain's content, so Warp's cache serves later processes):

    ``all_links(q, poses_out)``: every link's 4x4 pose; ``flange[f](q, flange_out)``: flange f's
    pose; ``wrist_flange[f](q, wrist_out, flange_out)``: wrist centre and flange position.
    ``flanges`` are (link, 4x4 offset); ``wrist`` is ((link, point, axis) of J4, of J5) or None."""
    S = scalar
    M44 = types_of(scalar).mat44
    module = module_name("fk", chain, flanges, wrist, scalar)
    fk_all = tree_fk(chain, range(len(chain.parent)), emit_matrix(scalar), scalar)

    @wp.kernel(enable_backward=False, module=module)
    def all_links(
        # In:
        q: wp.array2d(dtype=S),
        # Out:
        poses_out: wp.array2d(dtype=M44),
    ):
        fk_all(q, wp.tid(), poses_out)

    flange_kernels = tuple(_flange_kernel(chain, link, m, scalar, module) for link, m in flanges)
    wrist_kernels = tuple(_wrist_kernel(chain, link, m, wrist, scalar, module) for link, m in flanges)
    return all_links, flange_kernels, wrist_kernels


def _flange_kernel(chain: Chain, link: int, offset: np.ndarray, scalar, module: str):
    M44 = types_of(scalar).mat44
    fk = tree_fk(chain, [link], emit_frame(offset, scalar), scalar)

    @wp.kernel(enable_backward=False, module=module)
    def flange(
        # In:
        q: wp.array2d(dtype=scalar),
        # Out:
        flange_out: wp.array(dtype=M44),
    ):
        fk(q, wp.tid(), flange_out)

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
    def wrist_flange(
        # In:
        q: wp.array2d(dtype=scalar),
        # Out:
        wrist_out: wp.array(dtype=V3),
        flange_out: wp.array(dtype=V3),
    ):
        i = wp.tid()
        poses = wp.zeros(shape=wp.static(n), dtype=M34)
        fk(q, i, poses)
        flange_out[i] = apply(poses[wp.static(link)], wp.static(tf))
        if wp.static(has_wrist):
            m4 = poses[wp.static(l4)]
            m5 = poses[wp.static(l5)]
            wrist_out[i] = centre(apply(m4, wp.static(c4)), rotate(m4, wp.static(d4)),
                                  apply(m5, wp.static(c5)), rotate(m5, wp.static(d5)))
        else:
            wrist_out[i] = V3()

    return wrist_flange
