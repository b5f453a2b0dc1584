"""Joint motions with the joint's axis and point folded into constants: the building block of the
forward kinematics and of the loop solve, which unroll them per mechanism."""

import numpy as np
import warp as wp


def entries(matrix_type, const, cos_coef, sin_coef, rows: int, cols: int):
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


def revolute_parts(axis: np.ndarray, point: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A revolute joint's motion as const + c * cos_coef + s * sin_coef, each (12,): R's entries row
    by row, then t's. Rodrigues: R = a a^T + c (I - a a^T) + s [a]x and t = p - R p."""
    a, p = np.asarray(axis, float), np.asarray(point, float)
    outer = np.outer(a, a)
    ortho = np.eye(3) - outer
    skew = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return (np.concatenate([outer.ravel(), p - outer @ p]), np.concatenate([ortho.ravel(), -ortho @ p]),
            np.concatenate([skew.ravel(), -skew @ p]))


def codes_of(const: np.ndarray, cos_coef: np.ndarray, sin_coef: np.ndarray) -> tuple:
    """Each entry of a motion (``revolute_parts``' form, or constants with zero coefficients) as 0
    (zero at every angle), 1 (one at every angle) or 2: the products a composition can leave out."""
    return tuple(0 if not (k or c or s) else 1 if (k == 1.0 and not c and not s) else 2
                 for k, c, s in zip(const, cos_coef, sin_coef))


def revolute_motion(axis: np.ndarray, point: np.ndarray, T):
    """Rotation and translation of a revolute joint as functions of (cos, sin) (``revolute_parts``).
    ``T``: the types of one precision."""
    const, cos_coef, sin_coef = revolute_parts(axis, point)
    rot = entries(T.mat33, const[:9], cos_coef[:9], sin_coef[:9], 3, 3)
    tra = entries(T.vec3, const[9:], cos_coef[9:], sin_coef[9:], 3, 1)
    return rot, tra


def revolute_after(axis: np.ndarray, point: np.ndarray, T):
    """(rot_after(rp, c, s) -> rp R, tra_after(rp, tp, c, s) -> rp t + tp): a revolute joint's
    motion composed after its parent's pose, the products over entries that are zero for every
    angle left out (an axis along x, y or z makes R five numbers and one, t two or none)."""
    S, M33, V3 = T.scalar, T.mat33, T.vec3
    rot, tra = revolute_motion(axis, point, T)
    codes = codes_of(*revolute_parts(axis, point))
    nz = [c != 0 for c in codes[:9]]  # R's entries, row by row
    tz = [c != 0 for c in codes[9:]]

    @wp.func
    def rot_after(rp: M33, c: S, s: S) -> M33:
        rr = wp.static(rot)(c, s)
        m = M33()
        for e in range(wp.static(9)):
            v = S(0.0)
            for k in range(wp.static(3)):
                if wp.static(nz[k * 3 + e % 3]):
                    v += rp[wp.static(e // 3), k] * rr[k, wp.static(e % 3)]
            m[wp.static(e // 3), wp.static(e % 3)] = v
        return m

    @wp.func
    def tra_after(rp: M33, tp: V3, c: S, s: S) -> V3:
        tt = wp.static(tra)(c, s)
        out = tp
        for k in range(wp.static(3)):
            if wp.static(tz[k]):
                out += V3(rp[0, k], rp[1, k], rp[2, k]) * tt[k]
        return out

    return rot_after, tra_after
