"""One implicit step of the rod, as device functions for the step kernel (``kernel``): the prediction
(inertia and gravity), one Gauss-Newton iteration of implicit Euler on all its bodies at once,
and the commit of the new positions and velocities.

The iteration minimizes 1/2 |y - y_pred|^2_M / h^2 + E(y) over every segment's pose y, E the
joints', clamps' and contacts' energy: the Hessian is block-tridiagonal along each cable (6x6
blocks; a joint couples two consecutive segments, a clamp or a contact only its own), so one
forward sweep assembles and factors it (block LDL^T, each pivot block's own L D L^T, carried as
D_k^-1 L_k^-1 B_k so each step costs two triangular solves) and one backward sweep solves it, in
time linear in the segments: a direct solve, so stiff hoses converge in an iteration or two
where Gauss-Seidel sweeps would not."""

import warp as wp

from .algebra import (
    axial,
    blocks,
    bottom,
    diag3,
    gram,
    ldl,
    over_pivots,
    over_pivots_v,
    pair,
    rotation_vector,
    top,
    transposed_times,
    turned,
    unit_backward,
    unit_forward,
    unit_forward_columns,
)
from .contact import contact_terms
from .joint import axis_of, joint_terms
from .slots import NOT_FINITE, RUNAWAY, RUNNING
from .types import (
    F64,
    M44,
    M66,
    MAX_CONTACTS,
    V3,
    V6,
    BodyWork,
    Contact,
    Factor,
    Q,
    RodParams,
)


@wp.func
def attachment_pose(params: RodParams, d: int, poses: wp.array3d(dtype=M44), e: int, s: int, a: int):
    """(point, frame) of attachment ``a`` in the world at pose row ``s``: carried by its link."""
    m = poses[e, s, params.attach_link[a]]
    p = params.attach_point[d, a]
    rot = wp.mat33d(m[0, 0], m[0, 1], m[0, 2], m[1, 0], m[1, 1], m[1, 2], m[2, 0], m[2, 1], m[2, 2])
    turn = wp.quat_from_matrix(rot)
    return rot * p + wp.vec3d(m[0, 3], m[1, 3], m[2, 3]), wp.normalize(turn * params.attach_frame[d, a])


@wp.func
def predict(params: RodParams, d: int, x_s: wp.array2d(dtype=V3), q_s: wp.array2d(dtype=Q), v_s: wp.array2d(dtype=V3),
            w_s: wp.array2d(dtype=V3), a_s: wp.array2d(dtype=V3), e: int, work: wp.array2d(dtype=BodyWork), row: int,
            h: F64):
    """Where each body would go unhindered (its velocity and gravity): the pose the step is drawn
    to. The first iterate goes on at the body's last acceleration instead of gravity's (as VBD's
    adaptive start does): a cable at rest or swinging freely starts at its solution, and the first
    step's length tells (``iterate``). Bodies in contact start again at ``free_start``."""
    for k in range(params.bodies[d]):
        b = BodyWork()
        b.x = x_s[e, k] + h * v_s[e, k]
        b.x_pred = b.x + (h * h) * params.gravity
        b.x = b.x + (h * h) * a_s[e, k]
        b.q_pred = turned(q_s[e, k], h * w_s[e, k])
        b.q = b.q_pred
        work[row, k] = b


@wp.func
def free_start(params: RodParams, d: int, work: wp.array2d(dtype=BodyWork), count: wp.array2d(dtype=wp.int32),
               row: int):
    """A body in contact starts its iterations in free flight: its lagged friction (``contact_terms``)
    then meets the slip from above, and converges in the iterations given, where a start at the
    last acceleration holds a sliding body stuck for several substeps."""
    for k in range(params.bodies[d]):
        if count[row, k] > 0:
            b = work[row, k]
            b.x = b.x_pred
            work[row, k] = b


@wp.func
def _inertia(params: RodParams, d: int, k: int, b: BodyWork, h: F64):
    """(Hessian, gradient) of body k's pull towards its predicted pose."""
    m = params.mass[d, k] / (h * h)
    inertia = params.inertia[d, k] / (h * h)
    iw = axial(inertia[0], inertia[1], axis_of(b.q))
    turn_left = rotation_vector(b.q * wp.quat_inverse(b.q_pred))
    return blocks(diag3(m, m, m), wp.mat33d(), wp.mat33d(), iw), pair(m * (b.x - b.x_pred), iw * turn_left)


@wp.func
def _attachments(params: RodParams, d: int, poses: wp.array3d(dtype=M44), e: int, s: int, k: int, b: BodyWork):
    """(Hessian, gradient) of the clamps and ball joints holding body k."""
    hess = M66()
    grad = V6()
    half = params.half[d, k]
    for a in range(params.attach_first[d, k], params.attach_first[d, k + 1]):
        p, f = attachment_pose(params, d, poses, e, s, a)
        if params.attach_end[a] > F64(0.0):  # held at its end: the body is the joint's first
            aa, ab, bb, ga, gb = joint_terms(b.x, b.q, half, p, f, F64(0.0), params.attach_stiff[d, a])
            hess = hess + aa
            grad = grad + ga
        else:  # held at its start: the clamp is the joint's first
            aa, ab, bb, ga, gb = joint_terms(p, f, F64(0.0), b.x, b.q, -half, params.attach_stiff[d, a])
            hess = hess + bb
            grad = grad + gb
    return hess, grad


@wp.func
def _contacts(params: RodParams, d: int, k: int, b: BodyWork, contacts: wp.array2d(dtype=Contact),
              count: wp.array2d(dtype=wp.int32), row: int, h: F64):
    hess = M66()
    grad = V6()
    for i in range(count[row, k]):
        hc, gc = contact_terms(contacts[row, k * MAX_CONTACTS + i], b.x, b.q, params.contact_stiff[d, k],
                               params.friction, params.slip * h)
        hess = hess + hc
        grad = grad + gc
    return hess, grad


@wp.func
def iterate(params: RodParams, d: int, poses: wp.array3d(dtype=M44), e: int, s: int, h: F64,
            work: wp.array2d(dtype=BodyWork), factor: wp.array2d(dtype=Factor), contacts: wp.array2d(dtype=Contact),
            count: wp.array2d(dtype=wp.int32), row: int) -> F64:
    """One Gauss-Newton iteration on every body at once (pose row ``s`` holds the clamps); returns
    how far it moved a segment's surface at most (m), for the caller's convergence test."""
    bodies = params.bodies[d]
    carry_d = M66()  # B_{k-1}^T D_{k-1}^-1 B_{k-1}
    carry_r = V6()  # B_{k-1}^T z_{k-1}
    carry_h = M66()  # the previous joint's block on this body
    carry_g = V6()
    for k in range(bodies):
        b = work[row, k]
        hess, grad = _inertia(params, d, k, b, h)
        hess = hess + carry_h
        grad = grad + carry_g
        couple = M66()
        carry_h = M66()
        carry_g = V6()
        if k + 1 < bodies:
            if params.stiff[d, k][2] > F64(0.0):  # a joint to the next body (not the next cable's)
                nb = work[row, k + 1]
                aa, ab, bb, ga, gb = joint_terms(b.x, b.q, params.half[d, k], nb.x, nb.q, -params.half[d, k + 1],
                                                 params.stiff[d, k])
                hess = hess + aa
                grad = grad + ga
                couple = ab
                carry_h = bb
                carry_g = gb
        if params.attach_first[d, k + 1] > params.attach_first[d, k]:
            ha, ga2 = _attachments(params, d, poses, e, s, k, b)
            hess = hess + ha
            grad = grad + ga2
        if count[row, k] > 0:
            hc, gc = _contacts(params, d, k, b, contacts, count, row, h)
            hess = hess + hc
            grad = grad + gc
        f = Factor()
        f.lo = ldl(hess - carry_d)
        w = unit_forward_columns(f.lo, couple)
        f.w = over_pivots(f.lo, w)
        f.y = over_pivots_v(f.lo, unit_forward(f.lo, -grad - carry_r))
        factor[row, k] = f
        carry_d = gram(w, f.w)
        carry_r = transposed_times(w, f.y)
    delta = V6()
    moved = F64(0.0)
    for kk in range(bodies):
        k = bodies - 1 - kk
        f = factor[row, k]
        delta = unit_backward(f.lo, f.y - f.w * delta)
        reach = params.half[d, k] + params.radius[d, k]
        moved = wp.max(moved, wp.length(top(delta)) + wp.length(bottom(delta)) * reach)
        b = work[row, k]
        b.x = b.x + top(delta)
        b.q = turned(b.q, bottom(delta))
        work[row, k] = b
    return moved


@wp.func
def commit(params: RodParams, d: int, work: wp.array2d(dtype=BodyWork), row: int, h: F64, x_s: wp.array2d(dtype=V3),
           q_s: wp.array2d(dtype=Q), v_s: wp.array2d(dtype=V3), w_s: wp.array2d(dtype=V3), a_s: wp.array2d(dtype=V3),
           e: int) -> int:
    """The step's poses, damped velocities and accelerations into the state, unless one is not finite or a
    segment's surface moves faster than ``max_speed``: then the state stays and the failure is
    returned."""
    keep = wp.exp(-params.damping * h)
    for k in range(params.bodies[d]):
        b = work[row, k]
        v = (b.x - x_s[e, k]) / h
        w = rotation_vector(b.q * wp.quat_inverse(q_s[e, k])) / h
        speed = wp.length(v) + wp.length(w) * (params.half[d, k] + params.radius[d, k])
        if not wp.isfinite(speed) or not wp.isfinite(b.q[3]):
            return NOT_FINITE
        if speed > params.max_speed:
            return RUNAWAY
        b.spin = w  # kept for the commit below: an atan2 a body
        work[row, k] = b
    for k in range(params.bodies[d]):
        b = work[row, k]
        v = (b.x - x_s[e, k]) / h * keep
        a_s[e, k] = (v - v_s[e, k]) / h
        v_s[e, k] = v
        w_s[e, k] = b.spin * keep
        x_s[e, k] = b.x
        q_s[e, k] = b.q
    return RUNNING
