"""Closed-form inverse kinematics of a 6-axis arm whose axes 2 and 3 are parallel and whose wrist
axes 4, 5 and 6 meet in a point (every ABB serial 6-axis robot), as device code: one pose per
thread, all eight branches (shoulder, elbow, wrist flip) with their ABB configuration data.

Product of exponentials on the axes at the zero position (world): the wrist centre fixes q1
(rotations about J2 and J3 keep its component along their common axis), then q3 and q2 (two
parallel axes: a triangle in the arm's plane), then q4, q5, q6 (three axes through one point: Euler
angles where the wrist is orthogonal, as ABB's are; Paden-Kahan subproblems 2 and 1 otherwise). The
arm's constants are folded into the code per robot, and the module is compiled with
``finite_math``: the host checks the poses finite, the kernel bounds them first. The status codes,
the angle helpers, the shoulder and the rigid check, shared with the palletizer's kernel, are in
``ik_common`` (and importable from here)."""

from types import SimpleNamespace
from typing import NamedTuple

import numpy as np
import warp as wp

from .cache import cached, finite_math, module_name
from .ik_common import NO_LIMITS, NO_REACH, NOT_RIGID, OK, SAME, angle_funcs, rigid_func, shoulder_func
from .ik_common import RIGID_TOL as RIGID_TOL  # the host reads every status and tolerance from here
from .ik_common import SHOULDER as SHOULDER
from .trig import trig_funcs
from .types import types_of

BRANCHES = 8  # shoulder (front, back) x elbow (up, down) x wrist (flip or not): index 4 s + 2 e + w
CONF = 4  # cf1, cf4, cf6, cfx
# |sin q5| below this (float64, float32): the wrist is singular, q4 is held at 0 and q6 takes the
# turn; above the rounding noise of q5's own computation, which a square root amplifies
SINGULAR_Q5 = {8: 1e-7, 4: 1e-3}
# m: a flange pose this far from the world's origin is out of any arm's reach, whatever rounding
# made of it (float32's squares overflow past 1e19 m, where a closed form would read noise as a solution)
FAR_M = 1000.0


class ArmConstants(NamedTuple):
    """An arm's axes at the zero position (world, metres), as the kernel folds them in."""

    w1: tuple
    p1: tuple
    w2: tuple
    p2: tuple
    s3: float  # w3 . w2: +1 or -1
    p3: tuple
    w4: tuple
    w5: tuple
    w6: tuple
    c0: tuple  # the wrist centre
    cf: tuple  # the wrist centre in the flange frame
    rm: tuple  # the flange's zero-position rotation, row-major 3x3
    h0: tuple  # the arm's horizontal direction at zero: the wrist centre's, across J1
    side0: float  # the side of the J2-J3 line the wrist centre is on at zero (+1 or -1)
    lo: tuple  # joint limits (rad)
    hi: tuple

    def digest(self) -> str:
        import hashlib

        return hashlib.sha256(repr(tuple(self)).encode()).hexdigest()[:16]


def _plane(w2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors spanning the plane across ``w2``, right-handed about it."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(w2[0]) < 0.9 else np.array([0.0, 0.0, 1.0])
    ea = np.cross(w2, helper)
    ea /= np.linalg.norm(ea)
    return ea, np.cross(w2, ea)


def _folded(arm: ArmConstants, scalar) -> SimpleNamespace:
    """The arm's constants as the device code folds them in, in one precision: the axes, the arm's
    triangle in the plane across J2, the wrist's Paden-Kahan terms, the limits."""
    S, V3, _, _, _ = types_of(scalar)
    V2 = wp.types.vector(2, scalar)
    Q6 = wp.types.vector(6, scalar)
    c = {k: np.asarray(v, float) for k, v in arm._asdict().items()}
    ea, eb = _plane(c["w2"])
    to2 = lambda v: (float(ea @ v), float(eb @ v))  # noqa: E731
    a2 = np.subtract(to2(c["p3"]), to2(c["p2"]))  # J2 axis to J3 axis, in the arm's plane
    b2 = np.subtract(to2(c["c0"]), to2(c["p3"]))  # J3 axis to the wrist centre
    la, lb = float(np.hypot(*a2)), float(np.hypot(*b2))
    turn0 = float(np.arctan2(a2[1], a2[0]) - np.arctan2(b2[1], b2[0]))
    n6 = np.cross(c["w6"], c["w5"])
    n6 /= np.linalg.norm(n6)  # a direction across J6 at zero
    n45 = np.cross(c["w4"], c["w5"])
    c45, c56 = float(c["w4"] @ c["w5"]), float(c["w5"] @ c["w6"])
    rmt = c["rm"].reshape(3, 3).T
    w45 = np.cross(c["w4"], c["w5"])
    n0 = np.stack([c["w4"], c["w5"], w45]) @ n6  # the direction across axis 6, in the frame of axes 4, 5, 4 x 5
    vec = lambda v: V3(*(S(float(x)) for x in v))  # noqa: E731
    sca = lambda x: S(float(x))  # noqa: E731
    return SimpleNamespace(
        S=S, V3=V3, V2=V2, Q6=Q6, scalar=scalar,
        W1=vec(c["w1"]), P1=vec(c["p1"]), W2=vec(c["w2"]), W4=vec(c["w4"]), W5=vec(c["w5"]), W6=vec(c["w6"]),
        CF=vec(c["cf"]), H0=vec(c["h0"]), N6=vec(n6), N45=vec(n45), EA=vec(ea), EB=vec(eb),
        K6=vec(rmt @ c["w6"]), KN=vec(rmt @ n6),  # axis 6 and the direction across it, in the flange frame
        S3=sca(arm.s3), SIDE0=sca(arm.side0), TURN0=sca(turn0),
        C45=sca(c45), C56=sca(c56), C4556=sca(c45 * c56), C45X2=sca(2.0 * c45), DET=sca(1.0 - c45 * c45),
        G2=sca(n45 @ n45), LSUM=sca(la * la + lb * lb), LPROD=sca(2.0 * la * lb),
        SINGULAR=sca(SINGULAR_Q5[wp.types.type_size_in_bytes(scalar)]),
        A2=V2(sca(a2[0]), sca(a2[1])), B2=V2(sca(b2[0]), sca(b2[1])), CT0=sca(np.cos(turn0)),
        ST0=sca(np.sin(turn0)), P2D=V2(*(sca(x) for x in to2(c["p2"]))),
        LO=Q6(*(sca(x) for x in c["lo"])), HI=Q6(*(sca(x) for x in c["hi"])),
        W45=vec(w45), N01=sca(n0[1]), N02=sca(n0[2]), S6=sca(np.sign(c["w4"] @ c["w6"])),
        FLIP=bool(abs(c45) < 1e-12 and abs(c56) < 1e-12 and np.linalg.norm(np.cross(c["w4"], c["w6"])) < 1e-12),
        # a joint whose limits span more than (-pi, pi] may need a whole turn to fit them
        TURNS=[bool(c["lo"][j] < -np.pi or c["hi"][j] > np.pi) for j in range(6)])


def _limits(k: SimpleNamespace) -> SimpleNamespace:
    """``fit`` (each joint turned into its limits where a whole turn fits) and ABB's ``quadrant``."""
    S, Q6, LO, HI, TURNS = k.S, k.Q6, k.LO, k.HI, k.TURNS
    TAU, PER_QUARTER = S(2.0 * np.pi), S(2.0 / np.pi)

    @wp.func
    def into(x: S, lo: S, hi: S) -> S:
        """x (in [-pi, pi)) turned by whole turns into [lo, hi], the turn nearest zero; x itself when
        none fits."""
        best = x
        if x < lo or x > hi:
            if x + TAU >= lo and x + TAU <= hi:
                best = x + TAU
            elif x - TAU >= lo and x - TAU <= hi:
                best = x - TAU
        return best

    @wp.func
    def fit(q: Q6) -> Q6:
        out = q
        for j in range(6):
            if wp.static(TURNS[j]):
                out[j] = into(q[j], LO[j], HI[j])
        return out

    @wp.func
    def quadrant(x: S) -> int:
        return int(wp.floor(x * PER_QUARTER))

    return SimpleNamespace(fit=fit, quadrant=quadrant)


def _branch_out(k: SimpleNamespace, lim: SimpleNamespace):
    """``branch_out``: one branch's joints, configuration data and status (outside the limits
    where a joint is) into the outputs."""
    S, Q6, scalar, LO, HI, quadrant = k.S, k.Q6, k.scalar, k.LO, k.HI, lim.quadrant

    @wp.func
    def branch_out(i: int, b: int, q: Q6, arm_conf: int, status: int,
                   q_out: wp.array3d(dtype=scalar), conf_out: wp.array3d(dtype=wp.int8),
                   status_out: wp.array2d(dtype=wp.int8)):
        st = status
        for j in range(6):
            q_out[i, b, j] = q[j]
            if st == OK and (q[j] < LO[j] or q[j] > HI[j]):
                st = NO_LIMITS
        conf_out[i, b, 0] = wp.int8(quadrant(q[0]))
        conf_out[i, b, 1] = wp.int8(quadrant(q[3]))
        conf_out[i, b, 2] = wp.int8(quadrant(q[5]))
        cfx = arm_conf
        if q[4] < S(0.0):
            cfx += 1
        conf_out[i, b, 3] = wp.int8(cfx)
        status_out[i, b] = wp.int8(st)

    return branch_out


def _euler_angles(k: SimpleNamespace, h: SimpleNamespace):
    """``euler_angles(v, vn) -> (q4, q5, q6, singular)`` of an orthogonal wrist."""
    S, V3, SINGULAR = k.S, k.V3, k.SINGULAR
    W4, W5, W6, N6, W45, N01, N02, S6 = k.W4, k.W5, k.W6, k.N6, k.W45, k.N01, k.N02, k.S6
    turn_about, atan2 = h.turn_about, trig_funcs(k.scalar).atan2

    @wp.func
    def euler_angles(v: V3, vn: V3):
        """As ``wrist_angles`` for an orthogonal wrist (axis 6 in line with axis 4 at zero), by
        Euler angles: in the frame of axes 4, 5 and 4 x 5 the wrist turns by Rx(q4) Ry(q5)
        Rx(+-q6), whose first column is axis 6's target ``v``: q4 and q5 from it. q6 turns the
        direction across axis 6 onto Ry(q5)^T Rx(q4)^T ``vn``, so that near the singularity, where
        q4 is rounding, q6 still makes up the rest of the turn. The branch whose sin q5 has the
        sign of -(w4 . w6), as the Paden-Kahan form's first; the flip is the other."""
        a0 = S6 * wp.dot(W4, v)
        a1 = S6 * wp.dot(W5, v)
        a2 = S6 * wp.dot(W45, v)
        r = wp.sqrt(a1 * a1 + a2 * a2)  # |sin q5|
        if r > SINGULAR:
            sg = -S6
            q4 = atan2(sg * a1, -sg * a2)
            q5 = atan2(sg * r, a0)
            # vn in the frame of axes 4, 5, 4 x 5 turned back by q4, then q5, times r (cos and sin
            # of q4 are -sg a2 / r and sg a1 / r; of q5, a0 and sg r): the angle is the same
            n1 = wp.dot(W5, vn)
            n2 = wp.dot(W45, vn)
            w1 = sg * (a1 * n2 - a2 * n1)
            w2 = sg * (r * r * wp.dot(W4, vn) - a0 * (a1 * n1 + a2 * n2))
            q6 = S6 * atan2(N01 * w2 - N02 * w1, N01 * w1 + N02 * w2)
            return q4, q5, q6, int(0)
        q6, c6, s6 = turn_about(W6, N6, vn)
        return S(0.0), S(0.0), q6, int(1)

    return euler_angles


def _paden_kahan_angles(k: SimpleNamespace, h: SimpleNamespace):
    """``wrist_angles(z, v, vn) -> (q4, q5, q6, singular)`` of any spherical wrist."""
    S, V3, SINGULAR = k.S, k.V3, k.SINGULAR
    W4, W5, W6, N6 = k.W4, k.W5, k.W6, k.N6
    rot, turn_about = h.rot, h.turn_about

    @wp.func
    def wrist_angles(z: V3, v: V3, vn: V3):
        """(q4, q5, q6, singular) of the wrist that turns axis 6 onto ``z`` by q5, ``z`` onto ``v``
        by q4 and the direction across axis 6 onto ``vn`` by q6. At the singularity (|sin q5| under
        SINGULAR) the wrist is straight: q5 is 0 (what is left is rounding) and q4 is held at 0."""
        q5, c5, s5 = turn_about(W5, W6, z)
        q4 = S(0.0)
        c4 = S(1.0)
        s4 = S(0.0)
        singular = int(1)
        if wp.abs(s5) > SINGULAR:
            q4, c4, s4 = turn_about(W4, z, v)
            singular = 0
        else:
            q5 = S(0.0)
            c5 = S(1.0)
            s5 = S(0.0)
        q6, c6, s6 = turn_about(W6, N6, rot(W5, c5, -s5, rot(W4, c4, -s4, vn)))  # R6 N6 = R5^T R4^T vn
        return q4, q5, q6, singular

    return wrist_angles


def _wrist(k: SimpleNamespace, h: SimpleNamespace, lim: SimpleNamespace):
    """``wrist``: the two wrist branches of one arm solution, written out with their configuration
    data and status."""
    S, V3, Q6, scalar = k.S, k.V3, k.Q6, k.scalar
    W4, W5, N45, FLIP = k.W4, k.W5, k.N45, k.FLIP
    C45, C56, C4556, C45X2, DET, G2 = k.C45, k.C56, k.C4556, k.C45X2, k.DET, k.G2
    half_turn, fit = h.half_turn, lim.fit
    branch_out = _branch_out(k, lim)
    euler_angles, wrist_angles = _euler_angles(k, h), _paden_kahan_angles(k, h)

    @wp.func
    def wrist(i: int, b: int, q1: S, q2: S, q3: S, v: V3, vn: V3, arm_conf: int, status: int,
              q_out: wp.array3d(dtype=scalar), conf_out: wp.array3d(dtype=wp.int8),
              status_out: wp.array2d(dtype=wp.int8)):
        """The two wrist branches (b, b + 1) of one arm solution, given where R4 R5 R6 must take
        axis 6 (``v``) and the direction across it (``vn``): by Euler angles for an orthogonal
        wrist, else q4, q5 by Paden-Kahan subproblem 2 and q6 by subproblem 1."""
        if wp.static(FLIP):
            # an orthogonal wrist with axes 4 and 6 in line at zero: the flip is (q4 + pi, -q5, q6 + pi)
            q4, q5, q6, singular = euler_angles(v, vn)
            twin = status
            if singular == 1 and twin == OK:
                twin = SAME  # the flip is the same pose: one solution
            branch_out(i, b, fit(Q6(q1, q2, q3, q4, q5, q6)), arm_conf, status, q_out, conf_out, status_out)
            branch_out(i, b + 1, fit(Q6(q1, q2, q3, half_turn(q4), -q5, half_turn(q6))), arm_conf, twin, q_out,
                       conf_out, status_out)
        else:
            alpha = (wp.dot(W4, v) - C4556) / DET
            beta = (C56 - C45 * wp.dot(W4, v)) / DET
            g = (S(1.0) - alpha * alpha - beta * beta - C45X2 * alpha * beta) / G2
            g = wp.sqrt(wp.max(g, S(0.0)))
            for f in range(2):
                z = W4 * alpha + W5 * beta + N45 * (g * (S(1.0) - S(2.0) * S(float(f))))
                q4, q5, q6, singular = wrist_angles(z, v, vn)
                st = status
                if singular == 1 and f == 1 and st == OK:
                    st = SAME
                branch_out(i, b + f, fit(Q6(q1, q2, q3, q4, q5, q6)), arm_conf, st, q_out, conf_out, status_out)

    return wrist


def _elbows(k: SimpleNamespace, h: SimpleNamespace, wrist):
    """``elbows``: the elbow-up and elbow-down arms of one q1, each with its two wrists."""
    S, V3, V2, scalar = k.S, k.V3, k.V2, k.scalar
    W2, A2, B2, CT0, ST0, TURN0, SIDE0, S3 = k.W2, k.A2, k.B2, k.CT0, k.ST0, k.TURN0, k.SIDE0, k.S3
    rot, wrapped = h.rot, h.wrapped
    atan2, acos = trig_funcs(scalar).atan2, trig_funcs(scalar).acos

    @wp.func
    def elbows(i: int, b: int, q1: S, yd: V2, d2: S, cg: S, behind1: bool, u6: V3, un: V3, status: int,
               q_out: wp.array3d(dtype=scalar), conf_out: wp.array3d(dtype=wp.int8),
               status_out: wp.array2d(dtype=wp.int8)):
        """The elbow-up and elbow-down arms (branches b..b + 3) of one q1: q3 from the triangle of
        the J2 axis, the J3 axis and the wrist centre (``cg``: its angle's cosine), then q2."""
        sg = wp.sqrt(S(1.0) - cg * cg)
        gamma = acos(cg)
        for e in range(2):
            sign_e = S(1.0) - S(2.0) * S(float(e))
            phi3 = gamma * sign_e + TURN0
            zc = cg * CT0 - sign_e * sg * ST0  # cos(phi3), with TURN0's cos and sin
            zs = sign_e * sg * CT0 + cg * ST0
            z = A2 + V2(zc * B2[0] - zs * B2[1], zs * B2[0] + zc * B2[1])
            cross = z[0] * yd[1] - z[1] * yd[0]
            dot = wp.dot(z, yd)
            q2 = atan2(cross, dot)
            n = wp.max(d2, S(1e-30))
            c2 = dot / n  # |z| = |yd|: the turn's cos and sin without another transcendental
            s2 = cross / n
            # behind the lower arm: the wrist centre on the other side of the J2-J3 line than at zero
            ra = V2(c2 * A2[0] - s2 * A2[1], s2 * A2[0] + c2 * A2[1])
            arm_conf = int(0)
            if behind1:
                arm_conf += 4
            if (ra[0] * yd[1] - ra[1] * yd[0]) * SIDE0 < S(0.0):
                arm_conf += 2
            c23 = c2 * zc - s2 * zs  # R2 R3 = R(w2, q2 + phi3)
            s23 = s2 * zc + c2 * zs
            wrist(i, b + 2 * e, q1, q2, wrapped(S3 * phi3), rot(W2, c23, -s23, u6), rot(W2, c23, -s23, un),
                  arm_conf, status, q_out, conf_out, status_out)

    return elbows


def _refuse(k: SimpleNamespace):
    """``refuse(i, status, outputs)``: every branch of pose i refused with ``status``."""
    S, scalar = k.S, k.scalar

    @wp.func
    def refuse(i: int, status: int, q_out: wp.array3d(dtype=scalar), conf_out: wp.array3d(dtype=wp.int8),
               status_out: wp.array2d(dtype=wp.int8)):
        for b in range(BRANCHES):
            status_out[i, b] = wp.int8(status)
            for c in range(6):
                q_out[i, b, c] = S(0.0)
            for c in range(CONF):
                conf_out[i, b, c] = wp.int8(0)

    return refuse


def _shoulders(arm: ArmConstants, k: SimpleNamespace, h: SimpleNamespace, elbows):
    """``shoulders(i, wc, t6, tn, outputs)``: the front and back q1 of the wrist centre ``wc``,
    each with its elbows and wrists, given where R1..R6 must take axis 6 (``t6``) and the direction
    across it (``tn``)."""
    S, V3, V2, scalar = k.S, k.V3, k.V2, k.scalar
    shoulder = shoulder_func(scalar, arm.w1, arm.p1, arm.w2, float(np.dot(arm.w2, arm.c0) - np.dot(arm.w2, arm.p1)))
    rot, wrapped = h.rot, h.wrapped
    W1, P1, H0, EA, EB, P2D, LSUM, LPROD = k.W1, k.P1, k.H0, k.EA, k.EB, k.P2D, k.LSUM, k.LPROD

    @wp.func
    def shoulders(i: int, wc: V3, t6: V3, tn: V3, q_out: wp.array3d(dtype=scalar),
                  conf_out: wp.array3d(dtype=wp.int8), status_out: wp.array2d(dtype=wp.int8)):
        u = wc - P1
        phi, spread, ratio, a, bb, rho, shoulder_status = shoulder(wc)
        cs = wp.sqrt(S(1.0) - ratio * ratio)
        for s in range(2):
            sign = S(1.0) - S(2.0) * S(float(s))
            q1 = wrapped(phi + sign * spread)
            c1 = (a * ratio - bb * sign * cs) / rho  # cos(phi + sign spread)
            s1 = (bb * ratio + a * sign * cs) / rho
            y = P1 + rot(W1, c1, -s1, u)
            yd = V2(wp.dot(EA, y), wp.dot(EB, y)) - P2D
            d2 = wp.dot(yd, yd)
            cg = (d2 - LSUM) / LPROD
            st = shoulder_status
            if st == OK and wp.abs(cg) > S(1.0):
                st = NO_REACH
            behind1 = wp.dot(u, rot(W1, c1, s1, H0)) < S(0.0)
            # R1^T of axis 6's target and the direction across it
            elbows(i, 4 * s, q1, yd, d2, wp.clamp(cg, S(-1.0), S(1.0)), behind1, rot(W1, c1, -s1, t6),
                   rot(W1, c1, -s1, tn), st, q_out, conf_out, status_out)

    return shoulders


@cached
def arm_ik_kernel(arm: ArmConstants, scalar=wp.float64):
    """``ik(poses (N, 4, 4) flange poses) -> q_out (N, 8, 6), conf_out (N, 8, 4), status_out (N,
    8)``: each branch's joints (each turned by whole turns into its limits where it can be, the
    turn nearest zero), configuration data and status (OK or why not)."""
    S, V3, M33, _, M44 = types_of(scalar)
    k = _folded(arm, scalar)
    h = angle_funcs(scalar)
    shoulders = _shoulders(arm, k, h, _elbows(k, h, _wrist(k, h, _limits(k))))
    refuse, rigid = _refuse(k), rigid_func(scalar)
    CF, K6, KN, FAR = k.CF, k.K6, k.KN, S(FAR_M)

    @wp.kernel(enable_backward=False, module=module_name("ik", arm, str(scalar)))
    def ik(
        # In: flange poses (world, metres)
        poses: wp.array(dtype=M44),
        # Out: per branch, joints, configuration data and status
        q_out: wp.array3d(dtype=scalar),
        conf_out: wp.array3d(dtype=wp.int8),
        status_out: wp.array2d(dtype=wp.int8),
    ):
        i = wp.tid()
        m = poses[i]
        rt = M33(m[0, 0], m[0, 1], m[0, 2], m[1, 0], m[1, 1], m[1, 2], m[2, 0], m[2, 1], m[2, 2])
        if not rigid(m, rt):
            refuse(i, NOT_RIGID, q_out, conf_out, status_out)
            return
        if wp.max(wp.abs(m[0, 3]), wp.max(wp.abs(m[1, 3]), wp.abs(m[2, 3]))) > FAR:
            refuse(i, NO_REACH, q_out, conf_out, status_out)
            return
        # the wrist centre, and where R1..R6 must take axis 6 and the direction across it
        shoulders(i, rt * CF + V3(m[0, 3], m[1, 3], m[2, 3]), rt * K6, rt * KN, q_out, conf_out, status_out)

    return finite_math(ik)
