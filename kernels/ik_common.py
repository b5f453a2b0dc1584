"""What the closed-form inverse kinematics kernels share (the arm's, ``ik``, and the palletizer's,
``ik_planar``), as device code: a branch's status codes, the angle helpers of one precision
(Rodrigues, Paden-Kahan subproblem 1, angles wrapped into [-pi, pi)), the shoulder's two q1 of a
point (Paden-Kahan subproblem 4) and the check that a pose is a rigid transform."""

from types import SimpleNamespace

import numpy as np
import warp as wp

from .cache import cached
from .trig import trig_funcs
from .types import types_of

OK, NO_REACH, NO_LIMITS, SHOULDER, SAME = 0, 1, 2, 3, 4  # a branch's status (SAME: the singular wrist's flip)
NOT_RIGID = 5  # the pose is not a rigid transform (a rotation scaled, sheared, mirrored; a bad bottom row)
RIGID_TOL = 1e-5  # the error of RᵀR - I and of the bottom row a pose may have: float32 rounding


@cached
def angle_funcs(scalar):
    """The angle helpers of one precision, shared by the arm's and the palletizer's kernels:
    Rodrigues (``rot``), Paden-Kahan subproblem 1 (``turn_about``), ``wrapped`` into [-pi, pi),
    ``half_turn``."""
    S, V3, _, _, _ = types_of(scalar)
    TAU, PI, PER_TURN = S(2.0 * np.pi), S(np.pi), S(0.5 / np.pi)  # a product, where a division costs 4 or 5 of them
    atan2 = trig_funcs(scalar).atan2

    @wp.func
    def rot(w: V3, ca: S, sa: S, v: V3) -> V3:
        """v turned about the unit axis w by the angle of cosine ca and sine sa (Rodrigues)."""
        return v * ca + wp.cross(w, v) * sa + w * (wp.dot(w, v) * (S(1.0) - ca))

    @wp.func
    def turn_args(w: V3, p: V3, q: V3):
        """(y, x, cos, sin) of the turn of p onto q about the unit axis w (Paden-Kahan subproblem
        1): its angle is atan2(y, x), taken later by a kernel that takes its angles together."""
        pp = p - w * wp.dot(w, p)
        qq = q - w * wp.dot(w, q)
        y = wp.dot(w, wp.cross(pp, qq))
        x = wp.dot(pp, qq)
        r = wp.sqrt(x * x + y * y)
        if r == S(0.0):
            return S(0.0), S(1.0), S(1.0), S(0.0)  # atan2(0, 1) = 0
        return y, x, x / r, y / r

    @wp.func
    def turn_about(w: V3, p: V3, q: V3):
        """(angle, cos, sin) of the turn of p onto q about the unit axis w (Paden-Kahan subproblem 1)."""
        y, x, c, s = turn_args(w, p, q)
        return atan2(y, x), c, s

    @wp.func
    def wrapped(x: S) -> S:
        """x into [-pi, pi)."""
        return x - TAU * wp.floor((x + PI) * PER_TURN)

    @wp.func
    def half_turn(x: S) -> S:
        """x + pi, into [-pi, pi)."""
        return wrapped(x + PI)

    return SimpleNamespace(rot=rot, turn_args=turn_args, turn_about=turn_about, wrapped=wrapped, half_turn=half_turn)


def shoulder_func(scalar, w1, p1, w2, d0: float):
    """``shoulder(point) -> (phi, spread, cos spread, a, b, rho, status)``: the two q1 = phi +-
    spread that keep ``point``'s component along the turned axis 2 at ``d0`` from p1 (rotations
    about axis 2 and its parallels keep it: Paden-Kahan subproblem 4), phi = atan2(b, a), rho =
    |(a, b)|. SHOULDER where the point is on axis 1 (q1 free), NO_REACH where no q1 does."""
    S, V3, _, _, _ = types_of(scalar)
    atan2, acos = trig_funcs(scalar).atan2, trig_funcs(scalar).acos
    args = shoulder_args_func(scalar, w1, p1, w2, d0)

    @wp.func
    def shoulder(point: V3):
        ratio, a, b, rho, status = args(point)
        return atan2(b, a), acos(ratio), ratio, a, b, rho, status

    return shoulder


@cached
def shoulder_args_func(scalar, w1, p1, w2, d0: float):
    """``shoulder_args(point) -> (cos spread, a, b, rho, status)``: ``shoulder``'s without its two
    angles, for a kernel that takes its angles together (phi = atan2(b, a), spread = acos(ratio))."""
    S, V3, _, _, _ = types_of(scalar)
    W1, P1, W2 = (V3(*(S(float(x)) for x in v)) for v in (w1, p1, w2))
    D0 = S(float(d0))

    @wp.func
    def shoulder_args(point: V3):
        u = point - P1
        u_par = W1 * wp.dot(W1, u)
        a = wp.dot(W2, u - u_par)
        b = -wp.dot(W2, wp.cross(W1, u))
        rho = wp.sqrt(a * a + b * b)
        status = OK
        ratio = S(0.0)
        if rho < S(1e-9):
            status = SHOULDER
            rho = S(1.0)
        else:
            ratio = (D0 - wp.dot(W2, u_par)) / rho
            if wp.abs(ratio) > S(1.0):
                status = NO_REACH
                ratio = wp.clamp(ratio, S(-1.0), S(1.0))
        return ratio, a, b, rho, status

    return shoulder_args


@cached
def rigid_func(scalar):
    """``rigid(pose, its rotation) -> bool``: the pose is a rotation and a translation. Its numbers
    are the host's to check finite (``finite_math`` compiles NaN tests away); each is bounded here
    before any product, so nothing after overflows."""
    S, _, M33, _, M44 = types_of(scalar)
    TOL = S(RIGID_TOL)

    @wp.func
    def rigid(m: M44, r: M33) -> bool:
        big = S(0.0)
        for a in range(4):
            for b in range(3):
                big = wp.max(big, wp.abs(m[a, b]))
        if big > S(2.0):
            return False
        e = wp.transpose(r) * r - wp.identity(n=3, dtype=S)
        worst = S(0.0)
        for a in range(3):
            for b in range(3):
                worst = wp.max(worst, wp.abs(e[a, b]))
        worst = wp.max(worst, wp.max(wp.abs(m[3, 0]), wp.max(wp.abs(m[3, 1]), wp.abs(m[3, 2]))))
        worst = wp.max(worst, wp.abs(m[3, 3] - S(1.0)))
        return worst < TOL and wp.determinant(r) > S(0.0)

    return rigid
