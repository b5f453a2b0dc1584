"""The elastic joint between two rigid segments of a rod (or a segment and a clamp): its strain, its
energy's gradient, and its Gauss-Newton Hessian in 6x6 blocks, the terms the rod's implicit step
assembles (Deul, Kugelstadt, Weiler, Bender, "Direct position-based solver for stiff rods", 2018).

Body a's point at ``ca`` along its axis (its end: +half; a clamp's own point: 0) meets body b's at
``cb``. Strain, in a's frame: the gap between the two points (shear, shear, stretch) and the
relative rotation 2 Im(a* b) (bend, bend, twist), each against its stiffness over the joint's
length, so the energy is 1/2 (kappa G A |shear|^2 + E A stretch^2) / l + 1/2 (E I |bend|^2 + G J
twist^2) / l. Perturbations are world-frame: (dx, dtheta) per body."""

import warp as wp

from .algebra import axial, blocks, diag3, pair, relative, skew
from .types import F64, M66, V3, V6, Q


@wp.func
def axis_of(q: Q) -> V3:
    """The body's own axis (its third column) in the world."""
    return wp.quat_rotate(q, V3(F64(0.0), F64(0.0), F64(1.0)))


@wp.func
def joint_strain(xa: V3, qa: Q, ca: F64, xb: V3, qb: Q, cb: F64):
    """(gap in a's frame, 2 Im(a* b), a* b): the joint's strain before stiffness."""
    pa = xa + ca * axis_of(qa)
    pb = xb + cb * axis_of(qb)
    gap = wp.quat_rotate_inv(qa, pb - pa)
    rel = relative(qa, qb)
    return gap, F64(2.0) * V3(rel[0], rel[1], rel[2]), rel


@wp.func
def twist_angle(rel: Q) -> F64:
    """The twist of a relative rotation: its turn about the body's own axis (swing-twist)."""
    return F64(2.0) * wp.atan2(rel[2], rel[3])


@wp.func
def _pull(xa: V3, qa: Q, ca: F64, xb: V3, qb: Q, cb: F64, k: V6):
    """(f, tau, rel, t, rb): dE/d(b's point) and the rotational dE/d(theta_b), world; a* b; a's
    axis; b's point from b's centre. A round section: shear and bending stiffness alike across."""
    t = axis_of(qa)
    rb = cb * axis_of(qb)
    g = xb + rb - xa - ca * t
    f = k[0] * g + (k[2] - k[0]) * wp.dot(t, g) * t
    rel = relative(qa, qb)
    v = V3(rel[0], rel[1], rel[2])
    c = F64(2.0) * V3(k[3] * v[0], k[4] * v[1], k[5] * v[2])
    tau = wp.quat_rotate(qa, rel[3] * c + wp.cross(v, c))
    return f, tau, rel, t, rb


@wp.func
def joint_forces(xa: V3, qa: Q, ca: F64, xb: V3, qb: Q, cb: F64, k: V6):
    """(force on b's point, torque on b, lever from a's centre to b's point), world: the joint's
    pull. The force on a's point is its opposite, the torque on a its opposite plus the lever's."""
    f, tau, rel, t, rb = _pull(xa, qa, ca, xb, qb, cb, k)
    return -f, -tau, xb + rb - xa


@wp.func
def joint_terms(xa: V3, qa: Q, ca: F64, xb: V3, qb: Q, cb: F64, k: V6):
    """(aa, ab, bb, ga, gb): the Gauss-Newton Hessian blocks (6x6; ba is ab^T) and the gradients of
    the joint's energy with respect to each body's (dx, dtheta)."""
    f, tau, rel, t, rb = _pull(xa, qa, ca, xb, qb, cb, k)
    kpw = axial(k[0], k[2], t)
    # the rotational stiffness T^T Kr T, T = (w I - [v]x) Ra^T: with a unit rel, T^T T = I - u u^T
    v = V3(rel[0], rel[1], rel[2])
    u = wp.quat_rotate(qa, v)
    s = wp.quat_rotate(qa, rel[3] * V3(F64(0.0), F64(0.0), F64(1.0)) + V3(v[1], -v[0], F64(0.0)))
    krw = k[3] * (diag3(F64(1.0), F64(1.0), F64(1.0)) - wp.outer(u, u)) + (k[5] - k[3]) * wp.outer(s, s)
    d = xb + rb - xa  # the lever from a's centre to where the joint acts
    sd = skew(d)
    sr = skew(rb)
    m1 = kpw * sd
    m2 = kpw * sr
    # the loads' own stiffness (a torque turning with its body, a force on its lever) is left out of
    # Gauss-Newton; a twisted or loaded rod's iterations then overshoot unless each body's turning is
    # stiffened by at least that much, which leaves the answer (the gradient) as it is
    ta = diag3(F64(1.0), F64(1.0), F64(1.0)) * (wp.length(tau) + wp.length(f) * wp.length(d))
    tb = diag3(F64(1.0), F64(1.0), F64(1.0)) * (wp.length(tau) + wp.length(f) * wp.length(rb))
    aa = blocks(kpw, -m1, -wp.transpose(m1), -(sd * m1) + krw + ta)
    ab = blocks(-kpw, m2, wp.transpose(m1), sd * m2 - krw)
    bb = blocks(kpw, -m2, -wp.transpose(m2), -(sr * m2) + krw + tb)
    ga = pair(-f, -wp.cross(d, f) - tau)
    gb = pair(f, wp.cross(rb, f) + tau)
    return aa, ab, bb, ga, gb


@wp.func
def zero66() -> M66:
    return M66()


@wp.func
def zero6() -> V6:
    return V6()
