"""Forward kinematics eight configurations a thread, in float32: SIMD across configurations.

Warp runs a CPU kernel one item after another, and its loop over items does not vectorize (the
item's index is a 32-bit int the compiler cannot bound). Here each item is a block of ``LANES``
configurations whose every number is a ``LANES``-vector: a pose is a (12, LANES) matrix, rotation
rows then translation, and each step of the chain is a vector product the compiler lays out in AVX
registers (``lane_algebra``: the products with a motion's zeros and ones left out). The block's
joint values are read once, before the walk (``_block``); each pose is turned from lanes into rows
in registers and stored a row a lane (``lane_store``), into the caller's (N, links, 4, 4),
(N, links, 3, 4) or (N, links, 7) layout. The block of the last few configurations reads its last
row again and stores only its own.

Position and quaternion (``quats``) take each joint's half-angle sine and cosine alone, the
quaternion's own, and the rotation's from them by the double-angle rules: six sines and cosines a
configuration where twelve were taken. Its positions so round a little differently from the
matrices' (within 2e-6 m of float64, ``tests/test_fk_lanes.py``); the matrices are as they were.

Sines and cosines are the vectorized float32 core (``trig.sincos32_funcs``), good below BIG32 rad.
One test a block, before the walk, sends a block holding a larger angle or a NaN down a second
walk that takes libm's lane by lane: a test inside the walk merged its vectors lane by lane.

For serial and tree chains of revolute and prismatic joints driven by their own columns (the
arms); a chain with loops, mimics or closed forms takes ``fk.chain_kernels``. Each lane's arithmetic
is the same instruction sequence, so a configuration's pose does not depend on its lane.
"""

import functools
from typing import Any

import numpy as np
import warp as wp

from .cache import INLINE_ALL, cached, cpu_flags, module_name
from .lane_algebra import (
    LANES,
    PL,
    PQ,
    SCH,
    VL,
    S,
    compose_after,
    entry_of,
    identity,
    lane_dot,
    pose_of,
    turned_by,
    with_turn,
)
from .lane_store import M34, M44, M88, load_block, store_flange, store_mat34, store_mat44, store_transforms
from .motion import codes_of, revolute_parts
from .trig import BIG32, sincos32_funcs
from .types import PRISMATIC, REVOLUTE, Chain

DEEP_SLP = "-mllvm=-slp-recursion-max-depth=12"


def lanes_fit(chain: Chain) -> bool:
    """True where every moving joint reads its own column of q: no loop, mimic or closed form."""
    return not (np.any(chain.mimic != 0.0) or np.any(chain.closed_form[:, 0] != 0.0)
                or np.any(chain.unknown >= 0))


def _angles(col: int, halves: bool = False, exact: bool = False):
    """``sincos(qb)``: the sine (row 0) and cosine (row 1) of column ``col`` of the block's
    configurations; with ``halves``, those of the half angles (rows 2 and 3) and the whole angle's
    from them (``2 s c`` and ``(c - s)(c + s)``). The vectorized core (|angle| under BIG32, no
    branch), or with ``exact`` libm's lane by lane (any angle)."""
    core, libm = sincos32_funcs()
    f = libm if exact else core

    @wp.func
    def sincos(qb: Any) -> SCH:
        s = VL()
        c = VL()
        sh = VL()
        ch = VL()
        for ln in range(wp.static(LANES)):
            th = qb[wp.static(col), ln]
            if wp.static(halves):
                v = wp.static(f)(S(0.5) * th)
                sh[ln] = v[0]
                ch[ln] = v[1]
                s[ln] = S(2.0) * v[0] * v[1]
                c[ln] = (v[1] - v[0]) * (v[1] + v[0])
            else:
                v = wp.static(f)(th)
                s[ln] = v[0]
                c[ln] = v[1]
        return wp.matrix_from_rows(s, c, sh, ch)  # without halves, rows 2 and 3 zero (and unread)

    return sincos


@cached
def _block(dof: int):
    """``block(q, i0, n) -> (dof, LANES)``: the block's configurations, column by column (rows past
    ``n`` repeat the last), read once before any pose is stored: a store through the output could
    alias ``q``, so reads left after it would wait on it and keep the joints' sines and cosines
    from being computed ahead. Up to eight joints, each row read whole and turned in registers
    (``lane_store.load_block``)."""
    if dof <= LANES:

        @wp.func
        def rows(q: wp.array2d(dtype=S), i0: int, n: int) -> M88:
            return load_block(q, i0, n, wp.static(dof))

        return rows
    QB = wp.types.matrix((dof, LANES), S)

    @wp.func
    def block(q: wp.array2d(dtype=S), i0: int, n: int) -> QB:
        qb = QB()
        for ln in range(wp.static(LANES)):
            i = wp.min(i0 + ln, n - 1)
            for c in range(wp.static(dof)):
                qb[c, ln] = q[i, c]
        return qb

    return block


@cached
def _fine(dof: int):
    """``fine(qb)``: True where the block's joint values sum in magnitude under BIG32: none past it
    and none NaN, so the vectorized sine and cosine hold for every lane (one test a block, taken
    before the walk: a test inside it would merge its vectors lane by lane)."""

    @wp.func
    def fine(qb: Any) -> bool:
        acc = VL()
        for c in range(wp.static(dof)):
            acc = acc + wp.abs(qb[c])
        return wp.dot(acc, VL(S(1.0))) < S(BIG32)

    return fine


def _motion(chain: Chain, k: int):
    """``motion(c, s) -> (12, LANES)``: revolute link k's joint motion at the lanes' cosines and
    sines, its axis and point folded into constants."""
    const, cos_coef, sin_coef = revolute_parts(chain.axis[k], chain.point[k])
    e = [entry_of(*(float(x) for x in terms)) for terms in zip(const, cos_coef, sin_coef)]

    @wp.func
    def motion(c: VL, s: VL) -> PL:
        return wp.matrix_from_rows(
            wp.static(e[0])(c, s), wp.static(e[1])(c, s), wp.static(e[2])(c, s), wp.static(e[3])(c, s),
            wp.static(e[4])(c, s), wp.static(e[5])(c, s), wp.static(e[6])(c, s), wp.static(e[7])(c, s),
            wp.static(e[8])(c, s), wp.static(e[9])(c, s), wp.static(e[10])(c, s), wp.static(e[11])(c, s))

    return motion


def _step(chain: Chain, k: int, on_root: bool, exact: bool):
    """``step(qb, m) -> (12, LANES)``: the pose ``m`` after link k's joint motion at the block's
    joint values (``m`` unread where the parent's pose is the identity)."""
    if int(chain.jtype[k]) == PRISMATIC:
        return _slide(chain, k)
    compose = compose_after(codes_of(*revolute_parts(chain.axis[k], chain.point[k])))
    angles, motion = _angles(int(chain.qidx[k]), exact=exact), _motion(chain, k)

    @wp.func
    def step(qb: Any, m: PL) -> PL:
        sc = angles(qb)
        j = motion(sc[1], sc[0])
        if wp.static(on_root):
            return j
        return compose(m, j)

    return step


def _slide(chain: Chain, k: int):
    """A prismatic joint's step: the translation moved along the axis, turned by the parent."""
    col = int(chain.qidx[k])
    ax, ay, az = (VL(S(float(v))) for v in chain.axis[k])
    dt = lane_dot(tuple(2 if v else 0 for v in chain.axis[k]), True)

    @wp.func
    def slide(qb: Any, m: PL) -> PL:
        th = qb[wp.static(col)]
        x = wp.cw_mul(wp.static(ax), th)
        y = wp.cw_mul(wp.static(ay), th)
        z = wp.cw_mul(wp.static(az), th)
        return wp.matrix_from_rows(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8],
                                   dt(m[9], m[0], m[1], m[2], x, y, z), dt(m[10], m[3], m[4], m[5], x, y, z),
                                   dt(m[11], m[6], m[7], m[8], x, y, z))

    return slide


def _step_pose(chain: Chain, k: int, on_root: bool, exact: bool):
    """As ``_step`` with the link's quaternion carried along (``PQ``): the joint's half-angle
    sine and cosine give its quaternion, and its rotation by the double-angle rules (a few float32
    roundings more than the whole angle's own, for half the sines and cosines)."""
    if int(chain.jtype[k]) == PRISMATIC:
        slide = _slide(chain, k)

        @wp.func
        def slid(qb: Any, m: PQ) -> PQ:
            return with_turn(slide(qb, pose_of(m)), m[12], m[13], m[14], m[15])

        return slid
    compose = compose_after(codes_of(*revolute_parts(chain.axis[k], chain.point[k])))
    turned = turned_by(tuple(float(v) for v in chain.axis[k]))
    angles, motion = _angles(int(chain.qidx[k]), True, exact), _motion(chain, k)
    ax, ay, az = (float(v) for v in chain.axis[k])

    @wp.func
    def step(qb: Any, m: PQ) -> PQ:
        sc = angles(qb)
        j = motion(sc[1], sc[0])
        sh = sc[2]
        if wp.static(on_root):
            return with_turn(j, S(ax) * sh, S(ay) * sh, S(az) * sh, sc[3])
        return turned(m, compose(pose_of(m), j), sh, sc[3])

    return step


def lane_fk(chain: Chain, needed, emit, quats: bool = False):
    """``fk(q, i0, n, out)``: the poses of configurations ``q[i0 : i0 + LANES]`` (rows past ``n``
    repeat the last) for the links in ``needed``, each handed to ``emit(k)(out, i0, n, pose)``;
    ``quats``: the pose a ``PQ``, with its quaternion."""
    needed = frozenset(int(k) for k in needed)
    keep = chain.ancestors(needed)
    fast, slow = (_visitor(chain, chain.root, keep, needed, emit, quats, exact) for exact in (False, True))
    dof = int(chain.mimic.shape[1])
    block, lanes_fine = _block(dof), _fine(dof)

    @wp.func
    def fk(q: wp.array2d(dtype=S), i0: int, n: int, out: Any):
        qb = block(q, i0, n)
        fine = lanes_fine(qb)
        if wp.static(quats):
            zero = VL()
            m = with_turn(identity(), zero, zero, zero, VL(S(1.0)))
            if fine:
                wp.static(fast)(qb, i0, n, m, out)
            else:
                wp.static(slow)(qb, i0, n, m, out)
        else:
            if fine:
                wp.static(fast)(qb, i0, n, identity(), out)
            else:
                wp.static(slow)(qb, i0, n, identity(), out)

    return fk


def _visitor(chain: Chain, k: int, keep: set, needed: frozenset, emit, quats: bool, exact: bool):
    kids = tuple(_visitor(chain, c, keep, needed, emit, quats, exact) for c in chain.children(k) if c in keep)
    col = int(chain.qidx[k])
    moves = col >= 0 and int(chain.jtype[k]) in (REVOLUTE, PRISMATIC)
    on_root = int(chain.parent[k]) >= 0 and int(chain.parent[int(chain.parent[k])]) < 0
    step = (_step_pose if quats else _step)(chain, k, on_root, exact) if moves else None
    emits = k in needed
    store = emit(k) if emits else None

    @wp.func
    def visit(qb: Any, i0: int, n: int, m: Any, out: Any):
        r = m
        if wp.static(moves):
            r = wp.static(step)(qb, m)
        if wp.static(emits):
            wp.static(store)(out, i0, n, r)
        for c in range(wp.static(len(kids))):
            wp.static(kids[c])(qb, i0, n, r, out)

    return visit


# -- what to store ------------------------------------------------------------------------------------


def _emit_links(rows: int):
    """emit(k): ``out[i, k]`` = link k's pose as a 4x4 (rows 4) or 3x4 (rows 3) matrix."""
    return functools.partial(_emit_link, rows)


@cached
def _emit_link(rows: int, k: int):
    store = store_mat44 if rows == 4 else store_mat34

    @wp.func
    def emit(out: Any, i0: int, n: int, r: PL):
        # each lane's rows R|t as whole rows; a 4x4's last row 0 0 0 1 (a 3x4 stores 16 bytes fewer)
        zero = VL()
        wp.static(store)(out, i0, n, wp.static(k), 0, 32, r[0], r[1], r[2], r[9], r[3], r[4], r[5], r[10])
        wp.static(store)(out, i0, n, wp.static(k), 32, wp.static(16 * (rows - 2)), r[6], r[7], r[8], r[11], zero,
                         zero, zero, VL(S(1.0)))

    return emit


def _emit_flange(offset: np.ndarray):
    """emit(k): ``out[i]`` = link k's pose times a constant 4x4 ``offset``, as a 4x4 matrix."""
    return lambda k: _flange_emit(offset)


@cached
def _flange_emit(offset: np.ndarray):
    o = [[float(v) for v in row] for row in np.asarray(offset)[:3, :4]]
    values = [o[e // 3][e % 3] for e in range(9)] + [o[e][3] for e in range(3)]
    compose = compose_after(codes_of(np.array(values), np.zeros(12), np.zeros(12)))
    rows = [VL(S(v)) for v in values]

    @wp.func
    def emit(out: Any, i0: int, n: int, r: PL):
        f = compose(r, wp.matrix_from_rows(
            wp.static(rows[0]), wp.static(rows[1]), wp.static(rows[2]), wp.static(rows[3]), wp.static(rows[4]),
            wp.static(rows[5]), wp.static(rows[6]), wp.static(rows[7]), wp.static(rows[8]), wp.static(rows[9]),
            wp.static(rows[10]), wp.static(rows[11])))
        zero = VL()
        store_flange(out, i0, n, 0, 0, 32, f[0], f[1], f[2], f[9], f[3], f[4], f[5], f[10])
        store_flange(out, i0, n, 0, 32, 32, f[6], f[7], f[8], f[11], zero, zero, zero, VL(S(1.0)))

    return emit


# -- the kernels ---------------------------------------------------------------------------------------


@cached
def lane_kernels(chain: Chain, flanges):
    """The lane kernels of one chain (``lanes_fit``), one thread per ``LANES`` configurations:
    ``all_links[rows]`` (rows 4 or 3; 7: position and quaternion) and ``flange[f]``, each in a
    module of its own."""
    # a module a kernel: Warp merges look-alike closures across the kernels of one module (two
    # flanges' kernels got one's links)
    module = module_name("fk_lanes", chain, flanges)
    every = range(len(chain.parent))
    all_links = {rows: _links_kernel(lane_fk(chain, every, _emit_links(rows)), rows, f"{module}_{rows}")
                 for rows in (4, 3)}
    all_links[7] = _links_kernel(lane_fk(chain, every, _emit_pose, quats=True), 7, f"{module}_7")
    flange = tuple(_flange_kernel(lane_fk(chain, [link], _emit_flange(m)), f"{module}_f{f}")
                   for f, (link, m) in enumerate(flanges))
    for kernel in (*all_links.values(), *flange):
        # the SLP vectorizer looking deeper than Warp's default (4): the lanes' sine and cosine
        # are a deeper tree, and stayed scalar under it; the all-links walks inlined whole (the
        # flange's, one link's, is short)
        cpu_flags(kernel.module, DEEP_SLP if kernel in flange else f"{DEEP_SLP} {INLINE_ALL}")
    return all_links, flange


@cached
def _emit_pose(k: int):
    """emit: ``out[i, k]`` = link k's position and quaternion (x, y, z, w), a ``wp.transformf``."""

    @wp.func
    def emit(out: Any, i0: int, n: int, r: PQ):
        store_transforms(out, i0, n, wp.static(k), 0, 28, r[9], r[10], r[11], r[12], r[13], r[14], r[15], VL())

    return emit


def _links_kernel(fk, rows: int, module: str):
    M = M44 if rows == 4 else M34 if rows == 3 else wp.transformf
    return _lanes_kernel(fk, wp.array2d(dtype=M), module)


def _flange_kernel(fk, module: str):
    return _lanes_kernel(fk, wp.array(dtype=M44), module)


def _lanes_kernel(fk, out_type, module: str):
    """The kernel of one ``lane_fk``: a thread a block of ``LANES`` configurations."""

    @wp.kernel(enable_backward=False, module=module)
    def lanes(
        # In:
        q: wp.array2d(dtype=S),
        # Out:
        poses_out: out_type,
    ):
        i0 = wp.tid() * wp.static(LANES)
        if i0 >= 0:  # always: said so the compiler drops each store's test for a negative index
            fk(q, i0, q.shape[0], poses_out)

    return lanes
