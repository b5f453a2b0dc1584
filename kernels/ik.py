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
``ik_common`` (and importable from here); the wrist's, in ``ik_wrist``.

Every one of a pose's twenty angles (atan2 and acos) is a leaf: the rest of the solve needs only
their cosines and sines, which come without them. So the kernel finds all their arguments first,
then takes them eight at a time in float64 SIMD lanes (``trig.atan2_lanes``), then writes the
branches."""

from types import SimpleNamespace
from typing import NamedTuple

import numpy as np
import warp as wp

from .cache import cached, finite_math, module_name
from .ik_common import NO_LIMITS, NO_REACH, NOT_RIGID, OK, SAME, angle_funcs, rigid_func, shoulder_args_func
from .ik_common import RIGID_TOL as RIGID_TOL  # the host reads every status and tolerance from here
from .ik_common import SHOULDER as SHOULDER
from .ik_wrist import V8I, D, wrist_args_func
from .trig import V8D, atan2_lanes, trig_funcs
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
        ALONG=bool(np.linalg.norm(np.cross(c["w4"], c["w6"])) < 1e-12),  # axis 6 in line with axis 4 at zero
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


def _elbows(k: SimpleNamespace, h: SimpleNamespace):
    """``elbows(yd, d2, cg, sg, behind1, u6, un) -> (v, vn, cross, dot, arm_conf)``: the
    elbow-up and elbow-down arms (rows 0 and 1) of one q1: where R4 R5 R6 must take axis 6 and the
    direction across it, q2's atan2 arguments, the configuration bits."""
    S, V3, V2 = k.S, k.V3, k.V2
    W2, A2, B2, CT0, ST0, SIDE0 = k.W2, k.A2, k.B2, k.CT0, k.ST0, k.SIDE0
    M23 = wp.types.matrix((2, 3), S)
    rot = h.rot

    @wp.func
    def elbows(yd: V2, d2: S, cg: S, sg: S, behind1: bool, u6: V3, un: V3):
        """q3 from the triangle of the J2 axis, the J3 axis and the wrist centre (``cg``, ``sg``:
        its angle's cosine and sine), then q2's turn."""
        v, vn, cross2, dot2 = M23(), M23(), V2(), V2()
        conf = wp.vec2i()
        for e in range(2):
            sign_e = S(1.0) - S(2.0) * S(float(e))
            zc = cg * CT0 - sign_e * sg * ST0  # cos(phi3), with TURN0's cos and sin
            zs = sign_e * sg * CT0 + cg * ST0
            z = A2 + V2(zc * B2[0] - zs * B2[1], zs * B2[0] + zc * B2[1])
            cross = z[0] * yd[1] - z[1] * yd[0]
            dot = wp.dot(z, yd)
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
            v[e] = rot(W2, c23, -s23, u6)
            vn[e] = rot(W2, c23, -s23, un)
            cross2[e] = cross
            dot2[e] = dot
            conf[e] = arm_conf
        return v, vn, cross2, dot2, conf

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


def _arms(arm: ArmConstants, k: SimpleNamespace, h: SimpleNamespace):
    """``arms(wc, t6, tn) -> (ya, xa, v, vn, arm_conf, status)``: the four arm solutions of the
    wrist centre ``wc`` (lane l = 2 s + e: shoulder s front or back, elbow e up or down), given
    where R1..R6 must take axis 6 (``t6``) and the direction across it (``tn``): per arm, where
    R4 R5 R6 must take them (rows of ``v``, ``vn``), its configuration bits and status; and the
    atan2 arguments of the arm's angles, in eight lanes: q1's phi and spread, each shoulder's
    elbow angle, each arm's q2."""
    S, V3, V2 = k.S, k.V3, k.V2
    M43 = wp.types.matrix((4, 3), S)
    shoulder = shoulder_args_func(k.scalar, arm.w1, arm.p1, arm.w2,
                                  float(np.dot(arm.w2, arm.c0) - np.dot(arm.w2, arm.p1)))
    rot, elbows, acos_args = h.rot, _elbows(k, h), trig_funcs(k.scalar).acos_args
    W1, P1, H0, EA, EB, P2D, LSUM, LPROD = k.W1, k.P1, k.H0, k.EA, k.EB, k.P2D, k.LSUM, k.LPROD

    @wp.func
    def arms(wc: V3, t6: V3, tn: V3):
        u = wc - P1
        ratio, a, bb, rho, shoulder_status = shoulder(wc)
        ya, xa = V8D(), V8D()
        ya[0] = D(bb)  # phi = atan2(b, a)
        xa[0] = D(a)
        sy, sx = acos_args(ratio)  # spread, and its sine: sqrt((1 + x)(1 - x)) keeps its digits near x = +-1
        ya[1] = sy
        xa[1] = sx
        cs = S(sy)
        v, vn, conf, status = M43(), M43(), wp.vec4i(), wp.vec4i()
        for s in range(2):
            sign = S(1.0) - S(2.0) * S(float(s))
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
            cg = wp.clamp(cg, S(-1.0), S(1.0))
            gy, gx = acos_args(cg)  # the elbow angle
            ya[2 + s] = gy
            xa[2 + s] = gx
            # R1^T of axis 6's target and the direction across it
            ve, vne, cross, dot, ce = elbows(yd, d2, cg, S(gy), behind1, rot(W1, c1, -s1, t6), rot(W1, c1, -s1, tn))
            for e in range(2):
                v[2 * s + e] = ve[e]
                vn[2 * s + e] = vne[e]
                ya[4 + 2 * s + e] = D(cross[e])  # q2
                xa[4 + 2 * s + e] = D(dot[e])
                conf[2 * s + e] = ce[e]
                status[2 * s + e] = st
        return ya, xa, v, vn, conf, status

    return arms


def _emit(k: SimpleNamespace, h: SimpleNamespace, lim: SimpleNamespace):
    """``emit(i, ga, gb, gc, gd, singular, arm_conf, status, outputs)``: the eight branches of pose
    i from the angles (``ga`` as ``arms`` lays them out, the wrists' as ``wrist_args`` does),
    each joint turned into its limits where a whole turn fits, with configuration data and status."""
    S, Q6, scalar, FLIP, S3, S6, TURN0 = k.S, k.Q6, k.scalar, k.FLIP, k.S3, k.S6, k.TURN0
    wrapped, half_turn, fit = h.wrapped, h.half_turn, lim.fit
    branch_out = _branch_out(k, lim)

    @wp.func
    def emit(i: int, ga: V8D, gb: V8D, gc: V8D, gd: V8D, singular: V8I, arm_conf: wp.vec4i, status: wp.vec4i,
             q_out: wp.array3d(dtype=scalar), conf_out: wp.array3d(dtype=wp.int8),
             status_out: wp.array2d(dtype=wp.int8)):
        phi = S(ga[0])
        spread = S(ga[1])
        for s in range(2):
            q1 = wrapped(phi + (S(1.0) - S(2.0) * S(float(s))) * spread)
            gamma = S(ga[2 + s])
            for e in range(2):
                ln = 2 * s + e
                phi3 = gamma * (S(1.0) - S(2.0) * S(float(e))) + TURN0
                q2 = S(ga[4 + ln])
                q3 = wrapped(S3 * phi3)
                b = 2 * ln
                if wp.static(FLIP):
                    q4 = S(gb[ln])
                    q5 = S(gb[4 + ln])
                    q6 = S6 * S(gc[ln])
                    twin = status[ln]
                    if singular[ln] == 1:  # q5 is 0 or pi (atan2(0, +-1)), q4 held at 0
                        q4 = S(0.0)
                        q6 = S(gc[ln])
                        if twin == OK:
                            twin = SAME  # the flip is the same pose: one solution
                    branch_out(i, b, fit(Q6(q1, q2, q3, q4, q5, q6)), arm_conf[ln], status[ln], q_out, conf_out,
                               status_out)
                    branch_out(i, b + 1, fit(Q6(q1, q2, q3, half_turn(q4), -q5, half_turn(q6))), arm_conf[ln], twin,
                               q_out, conf_out, status_out)
                else:
                    for f in range(2):
                        st = status[ln]
                        if singular[b + f] == 1 and f == 1 and st == OK:
                            st = SAME
                        if singular[b + f] == 2 and st == OK:
                            st = NO_REACH
                        branch_out(i, b + f, fit(Q6(q1, q2, q3, S(gb[b + f]), S(gc[b + f]), S(gd[b + f]))),
                                   arm_conf[ln], st, q_out, conf_out, status_out)

    return emit


@cached
def arm_ik_kernel(arm: ArmConstants, scalar=wp.float64):
    """``ik(poses (N, 4, 4) flange poses) -> q_out (N, 8, 6), conf_out (N, 8, 4), status_out (N,
    8)``: each branch's joints (each turned by whole turns into its limits where it can be, the
    turn nearest zero), configuration data and status (OK or why not). Every angle is a leaf, so
    the kernel first finds the arguments of all twenty (an orthogonal wrist's; 32 otherwise), then
    takes them eight at a time (``trig.atan2_lanes``), then writes the branches."""
    S, V3, M33, _, M44 = types_of(scalar)
    k = _folded(arm, scalar)
    h = angle_funcs(scalar)
    lim = _limits(k)
    arms, wrist_args, emit = _arms(arm, k, h), wrist_args_func(k, h), _emit(k, h, lim)
    refuse, rigid = _refuse(k), rigid_func(scalar)
    CF, K6, KN, FAR, FLIP = k.CF, k.K6, k.KN, S(FAR_M), k.FLIP

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
        ya, xa, v, vn, arm_conf, status = arms(rt * CF + V3(m[0, 3], m[1, 3], m[2, 3]), rt * K6, rt * KN)
        yb, xb, yc, xc, yd, xd, singular = wrist_args(v, vn)
        gd = V8D()
        if wp.static(not FLIP):
            gd = atan2_lanes(yd, xd)
        emit(i, atan2_lanes(ya, xa), atan2_lanes(yb, xb), atan2_lanes(yc, xc), gd, singular, arm_conf, status,
             q_out, conf_out, status_out)

    return finite_math(ik)


