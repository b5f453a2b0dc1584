"""The wrist of the arm's closed-form IK (``ik``), as device code: where the three wrist angles'
atan2 arguments come from, for each of the four arm solutions of a pose. An orthogonal wrist (every
ABB arm's) by Euler angles, its flip derived; any other spherical wrist by Paden-Kahan subproblems
2 and 1, two branches each. The kernel takes the angles later, eight at a time
(``trig.atan2_lanes``)."""

from types import SimpleNamespace
from typing import Any

import warp as wp

from .trig import V8D

D = wp.float64
V8I = wp.types.vector(8, wp.int32)  # per lane: 0, the wrist singular (1), or out of its reach (2)
# how far below zero (float64, float32) a non-orthogonal wrist's g^2 may round where the cones about
# axes 4 and 5 touch; below it they do not meet, and the arm solution's wrist is out of reach
WRIST_REACH = {8: 1e-12, 4: 1e-5}


def _euler_args(k: SimpleNamespace, h: SimpleNamespace):
    """``euler_args(v, vn) -> (y4, x4, y5, x5, y6, x6, singular)``: the atan2 arguments of q4, q5
    and q6 of an orthogonal wrist (q6 is S6 times its angle where not singular; at the singularity
    q4 is atan2(0, 1) = 0 and q5 atan2(0, +-1): 0, or pi where the wrist is folded back)."""
    S, V3, SINGULAR = k.S, k.V3, k.SINGULAR
    W4, W5, W6, N6, W45, N01, N02, S6 = k.W4, k.W5, k.W6, k.N6, k.W45, k.N01, k.N02, k.S6
    rot, turn_args = h.rot, h.turn_args

    @wp.func
    def euler_args(v: V3, vn: V3):
        """By Euler angles, for an orthogonal wrist (axis 6 in line with axis 4 at zero): in the
        frame of axes 4, 5 and 4 x 5 the wrist turns by Rx(q4) Ry(q5) Rx(+-q6), whose first column
        is axis 6's target ``v``: q4 and q5 from it. q6 turns the direction across axis 6 onto
        Ry(q5)^T Rx(q4)^T ``vn``, so that near the singularity, where q4 is rounding, q6 still
        makes up the rest of the turn. The branch whose sin q5 has the sign of -(w4 . w6), as the
        Paden-Kahan form's first; the flip is the other."""
        a0 = S6 * wp.dot(W4, v)
        a1 = S6 * wp.dot(W5, v)
        a2 = S6 * wp.dot(W45, v)
        r = wp.sqrt(a1 * a1 + a2 * a2)  # |sin q5|
        if r > SINGULAR:
            sg = -S6
            # vn in the frame of axes 4, 5, 4 x 5 turned back by q4, then q5, times r (cos and sin
            # of q4 are -sg a2 / r and sg a1 / r; of q5, a0 and sg r): the angle is the same
            n1 = wp.dot(W5, vn)
            n2 = wp.dot(W45, vn)
            w1 = sg * (a1 * n2 - a2 * n1)
            w2 = sg * (r * r * wp.dot(W4, vn) - a0 * (a1 * n1 + a2 * n2))
            return sg * a1, -sg * a2, sg * r, a0, N01 * w2 - N02 * w1, N01 * w1 + N02 * w2, int(0)
        if a0 < S(0.0):  # folded back: q5 is pi, and q6 turns N6 onto R5^T vn, vn turned half about axis 5
            y6, x6, c6, s6 = turn_args(W6, N6, rot(W5, S(-1.0), S(0.0), vn))
            return S(0.0), S(1.0), S(0.0), S(-1.0), y6, x6, int(1)
        y6, x6, c6, s6 = turn_args(W6, N6, vn)
        return S(0.0), S(1.0), S(0.0), S(1.0), y6, x6, int(1)

    return euler_args


def _paden_kahan_args(k: SimpleNamespace, h: SimpleNamespace):
    """``pk_args(z, v, vn) -> (y4, x4, y5, x5, y6, x6, singular)`` of any spherical wrist."""
    S, V3, SINGULAR, ALONG = k.S, k.V3, k.SINGULAR, k.ALONG
    W4, W5, W6, N6 = k.W4, k.W5, k.W6, k.N6
    rot, turn_args = h.rot, h.turn_args

    @wp.func
    def pk_args(z: V3, v: V3, vn: V3):
        """The atan2 arguments of the wrist that turns axis 6 onto ``z`` by q5, ``z`` onto ``v`` by
        q4 and the direction across axis 6 onto ``vn`` by q6. At the singularity (``z`` along axis
        4 within SINGULAR, where q4 cannot move it) q4 is held at 0 and q6 takes the turn. Not
        |sin q5|: a wrist whose axis 5 is not square to axis 4 is not singular at q5 = pi."""
        y5, x5, c5, s5 = turn_args(W5, W6, z)
        y4 = S(0.0)
        x4 = S(1.0)
        c4 = S(1.0)
        s4 = S(0.0)
        singular = int(1)
        if wp.length(wp.cross(W4, z)) > SINGULAR:  # z off axis 4: q4 turns it onto v
            y4, x4, c4, s4 = turn_args(W4, z, v)
            singular = 0
        elif wp.static(ALONG):  # z is +-axis 6 at zero: q5 is 0 or pi, what is left rounding
            y5 = S(0.0)
            x5 = wp.where(c5 < S(0.0), S(-1.0), S(1.0))
            c5 = x5
            s5 = S(0.0)
        y6, x6, c6, s6 = turn_args(W6, N6, rot(W5, c5, -s5, rot(W4, c4, -s4, vn)))  # R6 N6 = R5^T R4^T vn
        return y4, x4, y5, x5, y6, x6, singular

    return pk_args


def wrist_args_func(k: SimpleNamespace, h: SimpleNamespace):
    """``wrist_args(v, vn) -> (yb, xb, yc, xc, yd, xd, singular)``: the atan2 arguments of the
    wrists of the four arm solutions (rows of ``v``: where R4 R5 R6 must take axis 6; of ``vn``:
    the direction across it), in three groups of eight lanes. An orthogonal wrist's flip is its
    twin's angles turned (q4 + pi, -q5, q6 + pi): lane l of group b is arm l's q4, lane 4 + l its
    q5, lane l of group c its q6; group d is unused. Any other wrist: lane 2 l + f of groups b, c,
    d is branch f's q4, q5, q6, Paden-Kahan subproblem 2 giving z. ``singular``: 1 where the wrist
    is straight, 2 where no wrist turns axis 6 onto v (a wrist that is not orthogonal reaches a
    cone of directions, not all)."""
    S, FLIP = k.S, k.FLIP
    W4, W5, N45, C45, C56, C4556, C45X2, DET, G2 = k.W4, k.W5, k.N45, k.C45, k.C56, k.C4556, k.C45X2, k.DET, k.G2
    REACH = S(WRIST_REACH[wp.types.type_size_in_bytes(k.scalar)])
    euler_args, pk_args = _euler_args(k, h), _paden_kahan_args(k, h)

    @wp.func
    def wrist_args(v: Any, vn: Any):
        yb = V8D()
        xb = V8D()
        yc = V8D()
        xc = V8D()
        yd = V8D()
        xd = V8D()
        singular = V8I()
        for ln in range(4):
            if wp.static(FLIP):
                y4, x4, y5, x5, y6, x6, sg = euler_args(v[ln], vn[ln])
                yb[ln] = D(y4)
                xb[ln] = D(x4)
                yb[4 + ln] = D(y5)
                xb[4 + ln] = D(x5)
                yc[ln] = D(y6)
                xc[ln] = D(x6)
                xc[4 + ln] = D(1.0)  # lanes 4..7: atan2(0, 1)
                singular[ln] = sg
            else:
                w = v[ln]
                alpha = (wp.dot(W4, w) - C4556) / DET
                beta = (C56 - C45 * wp.dot(W4, w)) / DET
                g = (S(1.0) - alpha * alpha - beta * beta - C45X2 * alpha * beta) / G2
                beyond = g < -REACH  # the cones about axes 4 and 5 do not meet: no wrist turns axis 6 onto v
                g = wp.sqrt(wp.max(g, S(0.0)))
                for f in range(2):
                    z = W4 * alpha + W5 * beta + N45 * (g * (S(1.0) - S(2.0) * S(float(f))))
                    y4, x4, y5, x5, y6, x6, sg = pk_args(z, w, vn[ln])
                    yb[2 * ln + f] = D(y4)
                    xb[2 * ln + f] = D(x4)
                    yc[2 * ln + f] = D(y5)
                    xc[2 * ln + f] = D(x5)
                    yd[2 * ln + f] = D(y6)
                    xd[2 * ln + f] = D(x6)
                    singular[2 * ln + f] = wp.where(beyond, 2, sg)
        return yb, xb, yc, xc, yd, xd, singular

    return wrist_args
