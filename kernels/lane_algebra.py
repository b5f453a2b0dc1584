"""The algebra of poses eight configurations wide, for ``fk_lanes``: the lane types, the identity,
a joint motion's entries, a pose composed after a motion whose zero and one entries are known (a
joint axis along x, y or z makes most of them so, and their products are left out), and the
quaternion carried beside a pose."""

import warp as wp

from .cache import cached

LANES = 8  # configurations a thread: one AVX register of float32 (16 were slower in a trial)
S = wp.float32
VL = wp.types.vector(LANES, S)
PL = wp.types.matrix((12, LANES), S)  # a pose, lane by lane: R row by row (rows 0-8), t (rows 9-11)
SCH = wp.types.matrix((4, LANES), S)  # sines, cosines, and the half angles' (rows 2, 3), lane by lane
PQ = wp.types.matrix((16, LANES), S)  # a pose and its quaternion (rows 12-15: x, y, z, w), lane by lane


@wp.func
def identity() -> PL:
    """The identity pose, over lanes."""
    one = VL(S(1.0))
    zero = VL()
    return wp.matrix_from_rows(one, zero, zero, zero, one, zero, zero, zero, one, zero, zero, zero)


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
def lane_dot(codes: tuple, base: bool):
    """``t + a x + b y + c z`` over lanes (``t`` only with ``base``), each term's code (``motion.codes_of``)
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
    head = lane_dot(codes[:k] + (0,) * (3 - k), base)

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
def compose_after(codes: tuple):
    """``m J``: a pose after a motion J whose entries' codes (``motion.codes_of``) are known, both
    (12, LANES); the products with J's zeros and ones left out."""
    d0, d1, d2 = (lane_dot((codes[c], codes[3 + c], codes[6 + c]), False) for c in range(3))
    dt = lane_dot(tuple(codes[9:12]), True)

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


def entry_of(k0: float, kc: float, ks: float):
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


@wp.func
def pose_of(m: PQ) -> PL:
    """A ``PQ``'s pose rows."""
    return wp.matrix_from_rows(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11])


@wp.func
def with_turn(r: PL, x: VL, y: VL, z: VL, w: VL) -> PQ:
    """Pose rows ``r`` and the quaternion (x, y, z, w) as one ``PQ``."""
    return wp.matrix_from_rows(r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11], x, y, z, w)


@cached
def turned_by(axis: tuple):
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
