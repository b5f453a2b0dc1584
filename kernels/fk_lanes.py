"""Forward kinematics eight configurations a thread, in float32: SIMD across configurations.

Warp runs a CPU kernel one item after another, and its loop over items does not vectorize (the
item's index is a 32-bit int the compiler cannot bound). Here each item is a block of ``LANES``
configurations whose every number is a ``LANES``-vector: a pose is a (12, LANES) matrix, rotation
rows then translation, and each step of the chain is a vector product the compiler lays out in AVX
registers. Only the stores go lane by lane, into the caller's (N, links, 4, 4) or (N, links, 3, 4)
layout. The block of the last few configurations reads its last row again and stores only its own.

For serial and tree chains of revolute and prismatic joints driven by their own columns (the
arms); a chain with loops, mimics or closed forms takes ``fk.chain_kernels``. Each lane's arithmetic
is the same instruction sequence, so a configuration's pose does not depend on its lane.
"""

import functools
from typing import Any

import numpy as np
import warp as wp

from .cache import cached, cpu_flags, module_name
from .motion import revolute_parts
from .trig import BIG32, sincos32_funcs
from .types import PRISMATIC, REVOLUTE, Chain

DEEP_SLP = "-mllvm=-slp-recursion-max-depth=12"
LANES = 8  # configurations a thread: one AVX register of float32 (16 were slower in a trial)
S = wp.float32
VL = wp.types.vector(LANES, S)
PL = wp.types.matrix((12, LANES), S)  # a pose, lane by lane: R row by row (rows 0-8), t (rows 9-11)
SCH = wp.types.matrix((4, LANES), S)  # sines, cosines, and the half angles' (rows 2, 3), lane by lane
PQ = wp.types.matrix((16, LANES), S)  # a pose and its quaternion (rows 12-15: x, y, z, w), lane by lane
M34 = wp.types.matrix((3, 4), S)
M44 = wp.types.matrix((4, 4), S)


def lanes_fit(chain: Chain) -> bool:
    """True where every moving joint reads its own column of q: no loop, mimic or closed form."""
    return not (np.any(chain.mimic != 0.0) or np.any(chain.closed_form[:, 0] != 0.0)
                or np.any(chain.unknown >= 0))


@wp.func
def identity() -> PL:
    """The identity pose, over lanes."""
    one = VL(S(1.0))
    zero = VL()
    return wp.matrix_from_rows(one, zero, zero, zero, one, zero, zero, zero, one, zero, zero, zero)


def codes_of(const: np.ndarray, cos_coef: np.ndarray, sin_coef: np.ndarray) -> tuple:
    """Each entry of a joint's motion as 0 (zero at every angle), 1 (one at every angle) or 2."""
    return tuple(0 if not (k or c or s) else 1 if (k == 1.0 and not c and not s) else 2
                 for k, c, s in zip(const, cos_coef, sin_coef))


@cached
def _term(k: int, code: int):
    """Term k of ``a x + b y + c z``: the factor of m alone where j's is one."""

    @wp.func
    def term(a: VL, b: VL, c: VL, x: VL, y: VL, z: VL) -> VL:
        u = a
        v = x
        if wp.static(k == 1):
            u = b
            v = y
        if wp.static(k == 2):
            u = c
            v = z
        if wp.static(code == 1):
            return u
        return wp.cw_mul(u, v)

    return term


@cached
def _dot(codes: tuple, base: bool):
    """``t + a x + b y + c z`` over lanes (``t`` only with ``base``), each term's code (``codes_of``)
    of j's factor: zero left out, one without its product. Joint axes along x, y or z make most of
    a motion's entries zero or one."""
    if not any(codes):
        return _start(base)
    k = max(i for i, code in enumerate(codes) if code)
    term = _term(k, codes[k])
    if not (base or any(codes[:k])):

        @wp.func
        def alone(t: VL, a: VL, b: VL, c: VL, x: VL, y: VL, z: VL) -> VL:
            return term(a, b, c, x, y, z)

        return alone
    head = _dot(codes[:k] + (0,) * (3 - k), base)

    @wp.func
    def dot(t: VL, a: VL, b: VL, c: VL, x: VL, y: VL, z: VL) -> VL:
        return head(t, a, b, c, x, y, z) + term(a, b, c, x, y, z)

    return dot


@cached
def _start(base: bool):
    @wp.func
    def start(t: VL, a: VL, b: VL, c: VL, x: VL, y: VL, z: VL) -> VL:
        if wp.static(base):
            return t
        return VL()

    return start


@cached
def _compose(codes: tuple):
    """``m J``: a pose after a motion J whose entries' codes (``codes_of``) are known, both
    (12, LANES); the products with J's zeros and ones left out."""
    d0, d1, d2 = (_dot((codes[c], codes[3 + c], codes[6 + c]), False) for c in range(3))
    dt = _dot(tuple(codes[9:12]), True)

    @wp.func
    def compose(m: PL, j: PL) -> PL:
        zero = VL()
        a0 = m[0]
        a1 = m[1]
        a2 = m[2]
        a3 = m[3]
        a4 = m[4]
        a5 = m[5]
        a6 = m[6]
        a7 = m[7]
        a8 = m[8]
        j0 = j[0]
        j1 = j[1]
        j2 = j[2]
        j3 = j[3]
        j4 = j[4]
        j5 = j[5]
        j6 = j[6]
        j7 = j[7]
        j8 = j[8]
        return wp.matrix_from_rows(
            d0(zero, a0, a1, a2, j0, j3, j6), d1(zero, a0, a1, a2, j1, j4, j7), d2(zero, a0, a1, a2, j2, j5, j8),
            d0(zero, a3, a4, a5, j0, j3, j6), d1(zero, a3, a4, a5, j1, j4, j7), d2(zero, a3, a4, a5, j2, j5, j8),
            d0(zero, a6, a7, a8, j0, j3, j6), d1(zero, a6, a7, a8, j1, j4, j7), d2(zero, a6, a7, a8, j2, j5, j8),
            dt(m[9], a0, a1, a2, j[9], j[10], j[11]), dt(m[10], a3, a4, a5, j[9], j[10], j[11]),
            dt(m[11], a6, a7, a8, j[9], j[10], j[11]))

    return compose


def _entry(k0: float, kc: float, ks: float):
    """``k0 + kc c + ks s`` over lanes, the zero terms left out."""

    @wp.func
    def entry(c: VL, s: VL) -> VL:
        v = VL()
        if wp.static(k0 != 0.0):
            v = VL(S(k0))
        if wp.static(kc != 0.0):
            v = v + S(kc) * c
        if wp.static(ks != 0.0):
            v = v + S(ks) * s
        return v

    return entry


def _angles(col: int, halves: bool = False, exact: bool = False):
    """``sincos(q, i0, n)``: the sine (row 0) and cosine (row 1) of column ``col`` of the lanes'
    configurations, and with ``halves`` those of the half angles (rows 2 and 3). The vectorized
    core (|angle| under BIG32, no branch), or with ``exact`` libm's lane by lane (any angle)."""
    core, libm = sincos32_funcs()
    f = libm if exact else core

    @wp.func
    def sincos(q: wp.array2d(dtype=S), i0: int, n: int) -> SCH:
        s = VL()
        c = VL()
        sh = VL()
        ch = VL()
        for ln in range(wp.static(LANES)):
            th = q[wp.min(i0 + ln, n - 1), wp.static(col)]
            v = wp.static(f)(th)
            s[ln] = v[0]
            c[ln] = v[1]
            if wp.static(halves):
                v = wp.static(f)(S(0.5) * th)
                sh[ln] = v[0]
                ch[ln] = v[1]
        return wp.matrix_from_rows(s, c, sh, ch)  # without halves, rows 2 and 3 zero (and unread)

    return sincos


@wp.func
def lanes_fine(q: wp.array2d(dtype=S), i0: int, n: int) -> bool:
    """True where the block's joint values sum in magnitude under BIG32: none past it and none NaN,
    so the vectorized sine and cosine hold for every lane (one test a block, taken before the walk:
    a test inside it would merge its vectors lane by lane)."""
    acc = VL()
    for c in range(q.shape[1]):
        t = VL()
        for ln in range(wp.static(LANES)):
            t[ln] = q[wp.min(i0 + ln, n - 1), c]
        acc = acc + wp.abs(t)
    return wp.dot(acc, VL(S(1.0))) < S(BIG32)


def _motion(chain: Chain, k: int):
    """``motion(c, s) -> (12, LANES)``: revolute link k's joint motion at the lanes' cosines and
    sines, its axis and point folded into constants."""
    const, cos_coef, sin_coef = revolute_parts(chain.axis[k], chain.point[k])
    e = [_entry(*(float(x) for x in terms)) for terms in zip(const, cos_coef, sin_coef)]

    @wp.func
    def motion(c: VL, s: VL) -> PL:
        return wp.matrix_from_rows(
            wp.static(e[0])(c, s), wp.static(e[1])(c, s), wp.static(e[2])(c, s), wp.static(e[3])(c, s),
            wp.static(e[4])(c, s), wp.static(e[5])(c, s), wp.static(e[6])(c, s), wp.static(e[7])(c, s),
            wp.static(e[8])(c, s), wp.static(e[9])(c, s), wp.static(e[10])(c, s), wp.static(e[11])(c, s))

    return motion


def _step(chain: Chain, k: int, on_root: bool, exact: bool):
    """``step(q, i0, n, m) -> (12, LANES)``: the pose ``m`` after link k's joint motion at the
    lanes' joint values (``m`` unread where the parent's pose is the identity)."""
    if int(chain.jtype[k]) == PRISMATIC:
        return _slide(chain, k)
    compose = _compose(codes_of(*revolute_parts(chain.axis[k], chain.point[k])))
    angles, motion = _angles(int(chain.qidx[k]), exact=exact), _motion(chain, k)

    @wp.func
    def step(q: wp.array2d(dtype=S), i0: int, n: int, m: PL) -> PL:
        sc = angles(q, i0, n)
        j = motion(sc[1], sc[0])
        if wp.static(on_root):
            return j
        return compose(m, j)

    return step


def _slide(chain: Chain, k: int):
    """A prismatic joint's step: the translation moved along the axis, turned by the parent."""
    col = int(chain.qidx[k])
    ax, ay, az = (VL(S(float(v))) for v in chain.axis[k])
    dt = _dot(tuple(2 if v else 0 for v in chain.axis[k]), True)

    @wp.func
    def slide(q: wp.array2d(dtype=S), i0: int, n: int, m: PL) -> PL:
        th = VL()
        for ln in range(wp.static(LANES)):
            th[ln] = q[wp.min(i0 + ln, n - 1), wp.static(col)]
        x = wp.cw_mul(wp.static(ax), th)
        y = wp.cw_mul(wp.static(ay), th)
        z = wp.cw_mul(wp.static(az), th)
        return wp.matrix_from_rows(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8],
                                   dt(m[9], m[0], m[1], m[2], x, y, z), dt(m[10], m[3], m[4], m[5], x, y, z),
                                   dt(m[11], m[6], m[7], m[8], x, y, z))

    return slide


@wp.func
def pose_of(m: PQ) -> PL:
    """A ``PQ``'s pose rows."""
    return wp.matrix_from_rows(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11])


@wp.func
def with_turn(r: PL, x: VL, y: VL, z: VL, w: VL) -> PQ:
    """Pose rows ``r`` and the quaternion (x, y, z, w) as one ``PQ``."""
    return wp.matrix_from_rows(r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11], x, y, z, w)


@cached
def _turned_by(axis: tuple):
    """``turned(m, r, sh, ch) -> PQ``: pose rows ``r`` with ``m``'s quaternion times the joint's
    (``axis`` sh, ch) (Hamilton, x y z w), the terms of the axis's zero components left out."""
    ax, ay, az = (float(v) for v in axis)

    @wp.func
    def turned(m: PQ, r: PL, sh: VL, ch: VL) -> PQ:
        px = m[12]
        py = m[13]
        pz = m[14]
        pw = m[15]
        x = wp.cw_mul(px, ch)
        y = wp.cw_mul(py, ch)
        z = wp.cw_mul(pz, ch)
        w = wp.cw_mul(pw, ch)
        if wp.static(ax != 0.0):
            jx = S(ax) * sh
            x = x + wp.cw_mul(pw, jx)
            y = y + wp.cw_mul(pz, jx)
            z = z - wp.cw_mul(py, jx)
            w = w - wp.cw_mul(px, jx)
        if wp.static(ay != 0.0):
            jy = S(ay) * sh
            x = x - wp.cw_mul(pz, jy)
            y = y + wp.cw_mul(pw, jy)
            z = z + wp.cw_mul(px, jy)
            w = w - wp.cw_mul(py, jy)
        if wp.static(az != 0.0):
            jz = S(az) * sh
            x = x + wp.cw_mul(py, jz)
            y = y - wp.cw_mul(px, jz)
            z = z + wp.cw_mul(pw, jz)
            w = w - wp.cw_mul(pz, jz)
        return with_turn(r, x, y, z, w)

    return turned


def _step_pose(chain: Chain, k: int, on_root: bool, exact: bool):
    """As ``_step`` with the link's quaternion carried along (``PQ``): the joint's half-angle
    sine and cosine give its quaternion; its rotation takes the whole angle's own (the
    double-angle rules would double the rotation's rounding)."""
    if int(chain.jtype[k]) == PRISMATIC:
        slide = _slide(chain, k)

        @wp.func
        def slid(q: wp.array2d(dtype=S), i0: int, n: int, m: PQ) -> PQ:
            return with_turn(slide(q, i0, n, pose_of(m)), m[12], m[13], m[14], m[15])

        return slid
    compose = _compose(codes_of(*revolute_parts(chain.axis[k], chain.point[k])))
    turned = _turned_by(tuple(float(v) for v in chain.axis[k]))
    angles, motion = _angles(int(chain.qidx[k]), True, exact), _motion(chain, k)
    ax, ay, az = (float(v) for v in chain.axis[k])

    @wp.func
    def step(q: wp.array2d(dtype=S), i0: int, n: int, m: PQ) -> PQ:
        sc = angles(q, i0, n)
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

    @wp.func
    def fk(q: wp.array2d(dtype=S), i0: int, n: int, out: Any):
        fine = lanes_fine(q, i0, n)
        if wp.static(quats):
            zero = VL()
            m = with_turn(identity(), zero, zero, zero, VL(S(1.0)))
            if fine:
                wp.static(fast)(q, i0, n, m, out)
            else:
                wp.static(slow)(q, i0, n, m, out)
        else:
            if fine:
                wp.static(fast)(q, i0, n, identity(), out)
            else:
                wp.static(slow)(q, i0, n, identity(), out)

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
    def visit(q: wp.array2d(dtype=S), i0: int, n: int, m: Any, out: Any):
        r = m
        if wp.static(moves):
            r = wp.static(step)(q, i0, n, m)
        if wp.static(emits):
            wp.static(store)(out, i0, n, r)
        for c in range(wp.static(len(kids))):
            wp.static(kids[c])(q, i0, n, r, out)

    return visit


# -- what to store ------------------------------------------------------------------------------------


def _emit_links(rows: int):
    """emit(k): ``out[i, k]`` = link k's pose as a 4x4 (rows 4) or 3x4 (rows 3) matrix."""
    return functools.partial(_emit_link, rows)


@wp.func
def lane_pose(r: PL, ln: int) -> M34:
    """Lane ``ln`` of a pose as a 3x4 matrix."""
    return M34(r[0, ln], r[1, ln], r[2, ln], r[9, ln], r[3, ln], r[4, ln], r[5, ln], r[10, ln],
               r[6, ln], r[7, ln], r[8, ln], r[11, ln])


@wp.func
def to_mat44(m: M34) -> M44:
    return M44(m[0, 0], m[0, 1], m[0, 2], m[0, 3], m[1, 0], m[1, 1], m[1, 2], m[1, 3],
               m[2, 0], m[2, 1], m[2, 2], m[2, 3], S(0.0), S(0.0), S(0.0), S(1.0))


@cached
def _emit_link(rows: int, k: int):
    @wp.func
    def emit(out: Any, i0: int, n: int, r: PL):
        for ln in range(wp.static(LANES)):
            if i0 + ln < n:
                if wp.static(rows == 4):
                    out[i0 + ln, wp.static(k)] = to_mat44(lane_pose(r, ln))
                else:
                    out[i0 + ln, wp.static(k)] = lane_pose(r, ln)

    return emit


def _emit_flange(offset: np.ndarray):
    """emit(k): ``out[i]`` = link k's pose times a constant 4x4 ``offset``, as a 4x4 matrix."""
    return lambda k: _flange_emit(offset)


@cached
def _flange_emit(offset: np.ndarray):
    o = [[float(v) for v in row] for row in np.asarray(offset)[:3, :4]]
    values = [o[e // 3][e % 3] for e in range(9)] + [o[e][3] for e in range(3)]
    compose = _compose(codes_of(np.array(values), np.zeros(12), np.zeros(12)))
    rows = [VL(S(v)) for v in values]

    @wp.func
    def emit(out: Any, i0: int, n: int, r: PL):
        f = compose(r, wp.matrix_from_rows(
            wp.static(rows[0]), wp.static(rows[1]), wp.static(rows[2]), wp.static(rows[3]), wp.static(rows[4]),
            wp.static(rows[5]), wp.static(rows[6]), wp.static(rows[7]), wp.static(rows[8]), wp.static(rows[9]),
            wp.static(rows[10]), wp.static(rows[11])))
        for ln in range(wp.static(LANES)):
            if i0 + ln < n:
                out[i0 + ln] = to_mat44(lane_pose(f, ln))

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
        # are a deeper tree, and stayed scalar under it
        cpu_flags(kernel.module, DEEP_SLP)
    return all_links, flange


@cached
def _emit_pose(k: int):
    """emit: ``out[i, k]`` = link k's position and quaternion (x, y, z, w), a ``wp.transformf``."""

    @wp.func
    def emit(out: Any, i0: int, n: int, r: PQ):
        for ln in range(wp.static(LANES)):
            if i0 + ln < n:
                out[i0 + ln, wp.static(k)] = wp.transformf(wp.vec3f(r[9, ln], r[10, ln], r[11, ln]),
                                                           wp.quatf(r[12, ln], r[13, ln], r[14, ln], r[15, ln]))

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
