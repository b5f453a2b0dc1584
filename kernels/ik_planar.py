"""Closed-form inverse kinematics of a palletizer as device code, one pose per thread: axis 1,
then an arm whose angles are two linear forms of two active joints (its parallel rods), a level
flange and a last axis parallel to axis 1. Four branches (shoulder x elbow); the palletizer's
constants (``rswarp.kinematics.ik_planar.PlanarArm``) are folded into the code."""

import numpy as np
import warp as wp

from .cache import cached, module_name
from .ik_common import NO_REACH, OK, angle_funcs, shoulder_func
from .types import types_of

BRANCHES = 4


def _branch(c: dict, dof: int, scalar, h):
    """``branch``: one shoulder's elbow branch of a palletizer pose: the two arm angles from the
    triangle of the arm's two turning parts, the arm joints from them, q6 from the flange's turn
    (out of reach where the flange is not level)."""
    S, V3, M33, _, _ = types_of(scalar)
    vec = lambda v: V3(*(S(float(x)) for x in v))  # noqa: E731
    W1, EA, EB, W6, N6 = (vec(c[k]) for k in ("w1", "ea", "eb", "w6", "n6"))
    RMT = M33(*(S(float(x)) for x in np.asarray(c["rm"]).reshape(3, 3).T.ravel()))
    LSUM, LPROD, TURN0, TOL = (S(float(c[k])) for k in ("lsum", "lprod", "turn0", "tol"))
    BX, BY, AX, AY, BBX, BBY = (S(float(x)) for x in (*c["base"], *c["a"], *c["b"]))
    I00, I01, I10, I11 = (S(float(x)) for x in np.ravel(c["inverse"]))
    FIRST, LAST, ARM0, ARM1 = (int(c[k]) for k in ("first", "last", "arm0", "arm1"))
    rot, wrapped = h.rot, h.wrapped

    @wp.func
    def branch(i: int, k: int, q1: S, c1: S, s1: S, u: V3, rt: M33, sign_e: S, status: int,
               q_out: wp.array3d(dtype=scalar), status_out: wp.array2d(dtype=wp.int8)):
        y = rot(W1, c1, -s1, u)  # R1^T (wrist point - p1)
        ydx = wp.dot(EA, y) - BX
        ydy = wp.dot(EB, y) - BY
        cg = (ydx * ydx + ydy * ydy - LSUM) / LPROD
        st = status
        if st == OK and wp.abs(cg) > S(1.0):
            st = NO_REACH
        psi = sign_e * wp.acos(wp.clamp(cg, S(-1.0), S(1.0))) + TURN0
        zx = AX + wp.cos(psi) * BBX - wp.sin(psi) * BBY
        zy = AY + wp.sin(psi) * BBX + wp.cos(psi) * BBY
        phi_a = wp.atan2(zx * ydy - zy * ydx, zx * ydx + zy * ydy)
        phi_b = phi_a + psi
        # R1^T R_T R_M^T must be a turn about w6: q6 from it, or the flange is not level
        r1 = wp.identity(n=3, dtype=S) * c1 + wp.skew(W1) * s1 + wp.outer(W1, W1) * (S(1.0) - c1)
        r6 = wp.transpose(r1) * rt * RMT
        if st == OK and wp.length(r6 * W6 - W6) > TOL:
            st = NO_REACH
        m = r6 * N6
        q6 = wp.atan2(wp.dot(wp.cross(N6, m), W6), wp.dot(m, N6))
        for j in range(wp.static(dof)):
            q_out[i, k, j] = S(0.0)
        q_out[i, k, FIRST] = q1
        q_out[i, k, LAST] = q6
        q_out[i, k, ARM0] = wrapped(I00 * phi_a + I01 * phi_b)
        q_out[i, k, ARM1] = wrapped(I10 * phi_a + I11 * phi_b)
        status_out[i, k] = wp.int8(st)

    return branch


@cached
def planar_ik_kernel(consts: tuple, dof: int, scalar=wp.float64):
    """``ik(poses (N, 4, 4)) -> q_out (N, 4, dof), status_out (N, 4)``; ``consts`` the flat
    constants (``PlanarArm.constants``): each value turned into [-pi, pi), the limits left to the
    host."""
    S, V3, M33, _, M44 = types_of(scalar)
    c = dict(consts)
    h = angle_funcs(scalar)
    branch = _branch(c, dof, scalar, h)
    shoulder = shoulder_func(scalar, c["w1"], c["p1"], c["w2"], c["d0"])
    P1 = V3(*(S(float(x)) for x in c["p1"]))
    wrapped = h.wrapped

    @wp.kernel(enable_backward=False, module=module_name("ik_planar", consts, dof, str(scalar)))
    def ik(
        # In: flange poses (world, metres)
        poses: wp.array(dtype=M44),
        # Out: per branch, joints (turned into [-pi, pi)) and status
        q_out: wp.array3d(dtype=scalar),
        status_out: wp.array2d(dtype=wp.int8),
    ):
        i = wp.tid()
        mm = poses[i]
        rt = M33(mm[0, 0], mm[0, 1], mm[0, 2], mm[1, 0], mm[1, 1], mm[1, 2], mm[2, 0], mm[2, 1], mm[2, 2])
        point = V3(mm[0, 3], mm[1, 3], mm[2, 3])
        phi, spread, ratio, a, b, rho, status = shoulder(point)
        for s in range(2):
            q1 = wrapped(phi + spread * (S(1.0) - S(2.0) * S(float(s))))
            c1 = wp.cos(q1)
            s1 = wp.sin(q1)
            for e in range(2):
                branch(i, 2 * s + e, q1, c1, s1, point - P1, rt, S(1.0) - S(2.0) * S(float(e)), status, q_out,
                       status_out)

    return ik
