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


def revolute_motion(axis: np.ndarray, point: np.ndarray, T):
    """Rotation and translation of a revolute joint as functions of (cos, sin): Rodrigues written as
    R = a a^T + c (I - a a^T) + s [a]x and t = p - R p. ``T``: the types of one precision."""
    a, p = np.asarray(axis, float), np.asarray(point, float)
    outer = np.outer(a, a)
    ortho = np.eye(3) - outer
    skew = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    rot = entries(T.mat33, outer, ortho, skew, 3, 3)
    tra = entries(T.vec3, p - outer @ p, -ortho @ p, -skew @ p, 3, 1)
    return rot, tra
