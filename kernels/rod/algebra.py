"""Small float64 algebra for the rod: rotations as quaternions and rotation vectors, 3x3 blocks of
6x6 matrices, and the 6x6 L D L^T factorization and triangular solves the block-tridiagonal
solve is made of."""

import warp as wp

from .types import F64, M33, M66, TINY, V3, V6, Q


@wp.func
def skew(v: V3) -> M33:
    """[v]x: skew(v) @ u = v x u."""
    return M33(F64(0.0), -v[2], v[1], v[2], F64(0.0), -v[0], -v[1], v[0], F64(0.0))


SMALL_TURN = 0.0625  # rad: under it, sin(a/2)/a and cos(a/2) by their Taylor series to a^8 (within 1e-20)


@wp.func
def rotation(w: V3) -> Q:
    """The unit quaternion of the rotation vector ``w`` (axis times angle). A substep's turns are
    small: under SMALL_TURN by the series (each term's error below double rounding), past it by
    libm's sine and cosine."""
    a2 = wp.dot(w, w)
    if a2 < F64(SMALL_TURN * SMALL_TURN):
        s = F64(0.5) + a2 * (F64(-1.0 / 48.0) + a2 * (F64(1.0 / 3840.0) + a2 * (F64(-1.0 / 645120.0)
                                                                                + a2 * F64(1.0 / 185794560.0))))
        c = F64(1.0) + a2 * (F64(-1.0 / 8.0) + a2 * (F64(1.0 / 384.0) + a2 * (F64(-1.0 / 46080.0)
                                                                              + a2 * F64(1.0 / 10321920.0))))
        return Q(s * w[0], s * w[1], s * w[2], c)
    angle = wp.sqrt(a2)
    s = wp.sin(F64(0.5) * angle) / angle
    return Q(s * w[0], s * w[1], s * w[2], wp.cos(F64(0.5) * angle))


@wp.func
def rotation_vector(q: Q) -> V3:
    """The rotation vector of ``q``, of the shorter way round (angle in [0, pi])."""
    v = V3(q[0], q[1], q[2])
    w = q[3]
    if w < F64(0.0):
        v = -v
        w = -w
    s = wp.length(v)
    if s < F64(1.0e-9):
        return F64(2.0) * v
    return (F64(2.0) * wp.atan2(s, w) / s) * v


@wp.func
def turned(q: Q, w: V3) -> Q:
    """``q`` turned further by the world-frame rotation vector ``w``."""
    return wp.normalize(rotation(w) * q)


@wp.func
def relative(a: Q, b: Q) -> Q:
    """a* b with a non-negative real part: b's frame in a's, the shorter way."""
    r = wp.quat_inverse(a) * b
    if r[3] < F64(0.0):
        r = Q(-r[0], -r[1], -r[2], -r[3])
    return r


@wp.func
def diag3(a: F64, b: F64, c: F64) -> M33:
    return M33(a, F64(0.0), F64(0.0), F64(0.0), b, F64(0.0), F64(0.0), F64(0.0), c)


@wp.func
def axial(a: F64, b: F64, t: V3) -> M33:
    """a I + (b - a) t t^T: a stiffness or inertia of a across unit axis t and b along it."""
    return diag3(a, a, a) + (b - a) * wp.outer(t, t)


@wp.func
def blocks(m11: M33, m12: M33, m21: M33, m22: M33) -> M66:
    """The 6x6 matrix [[m11, m12], [m21, m22]]."""
    out = M66()
    for i in range(3):
        for j in range(3):
            out[i, j] = m11[i, j]
            out[i, j + 3] = m12[i, j]
            out[i + 3, j] = m21[i, j]
            out[i + 3, j + 3] = m22[i, j]
    return out


@wp.func
def pair(a: V3, b: V3) -> V6:
    return V6(a[0], a[1], a[2], b[0], b[1], b[2])


@wp.func
def top(v: V6) -> V3:
    return V3(v[0], v[1], v[2])


@wp.func
def bottom(v: V6) -> V3:
    return V3(v[3], v[4], v[5])


@wp.func
def add_outer(m: M66, a: V6, k: F64) -> M66:
    """m + k a a^T."""
    out = m
    for i in range(6):
        for j in range(6):
            out[i, j] = out[i, j] + k * a[i] * a[j]
    return out


@wp.func
def ldl(a: M66) -> M66:
    """a = L D L^T with L unit lower, in one matrix: L below the diagonal, 1/D on it. No square
    root: the pivots are a chain (each body's factor waits on the one before), and a square root
    is its longest link. A pivot that is not positive, from a body that nothing holds, is floored
    at TINY so the solve stays finite."""
    lo = M66()
    dd = V6()
    # every loop over all six, the triangle's bounds as tests: Warp unrolls loops of constant
    # bounds, and each test then folds away (a loop bound by j stays a loop, its indices checked)
    for j in range(6):
        v = V6()  # L_jk D_k
        s = a[j, j]
        for k in range(6):
            if k < j:
                v[k] = lo[j, k] * dd[k]
                s = s - lo[j, k] * v[k]
        dj = wp.max(s, F64(TINY))
        dd[j] = dj
        inv = F64(1.0) / dj
        lo[j, j] = inv
        for i in range(6):
            if i > j:
                t = a[i, j]
                for k in range(6):
                    if k < j:
                        t = t - lo[i, k] * v[k]
                lo[i, j] = t * inv
    return lo


@wp.func
def unit_forward(lo: M66, b: V6) -> V6:
    """L^-1 b (L unit lower, from ``ldl``)."""
    y = V6()
    for i in range(6):
        t = b[i]
        for k in range(6):
            if k < i:  # constant bounds, unrolled (``ldl``)
                t = t - lo[i, k] * y[k]
        y[i] = t
    return y


@wp.func
def unit_backward(lo: M66, y: V6) -> V6:
    """L^-T y (L unit lower, from ``ldl``)."""
    x = V6()
    for ii in range(6):
        i = 5 - ii
        t = y[i]
        for k in range(6):
            if k > i:  # constant bounds, unrolled (``ldl``)
                t = t - lo[k, i] * x[k]
        x[i] = t
    return x


@wp.func
def unit_forward_columns(lo: M66, b: M66) -> M66:
    """L^-1 B, column by column (L unit lower, from ``ldl``)."""
    out = M66()
    for c in range(6):
        for i in range(6):
            t = b[i, c]
            for k in range(6):
                if k < i:  # constant bounds, unrolled (``ldl``)
                    t = t - lo[i, k] * out[k, c]
            out[i, c] = t
    return out


@wp.func
def over_pivots(lo: M66, b: M66) -> M66:
    """D^-1 B (1/D on ``lo``'s diagonal, from ``ldl``)."""
    out = M66()
    for i in range(6):
        for j in range(6):
            out[i, j] = b[i, j] * lo[i, i]
    return out


@wp.func
def over_pivots_v(lo: M66, y: V6) -> V6:
    """D^-1 y (1/D on ``lo``'s diagonal, from ``ldl``)."""
    out = V6()
    for i in range(6):
        out[i] = y[i] * lo[i, i]
    return out


@wp.func
def gram(w: M66, v: M66) -> M66:
    """W^T V for a product known symmetric (W^T D^-1 W, V = D^-1 W): each entry computed once."""
    out = M66()
    for i in range(6):
        for j in range(6):
            if j >= i:  # constant bounds, unrolled (``ldl``)
                t = F64(0.0)
                for k in range(6):
                    t = t + w[k, i] * v[k, j]
                out[i, j] = t
                out[j, i] = t
    return out


@wp.func
def transposed_times(w: M66, y: V6) -> V6:
    """W^T y."""
    out = V6()
    for i in range(6):
        t = F64(0.0)
        for k in range(6):
            t = t + w[k, i] * y[k]
        out[i] = t
    return out
