"""Cable dynamics as device code: one environment per thread, its cable a chain of particles.

Each substep: forward kinematics poses the links the cable is attached to (``tree_fk``, inside
the kernel); attached particles (and, where a control point clamps the tangent, their neighbour)
move rigidly with their links; free particles fall under gravity. Then the chain is made
inextensible exactly: a few Newton steps on all its distance constraints at once, a tridiagonal
system solved in linear time (a direct solve, not Gauss-Seidel sweeps, so long cables do not
stretch under their weight). Bending follows by XPBD on the discrete curvature x[i-1] - 2 x[i] +
x[i+1] with compliance l^3 / EI, then the lengths are restored. Velocities are the positions'
change, damped.
"""

from typing import Any

import warp as wp

from .fk import emit_local, tree_fk
from .types import Chain, types_of

NEWTON_STEPS = 3  # exact-length projections per substep (quadratic convergence)


def cable_kernel(chain: Chain, links: set, particles: int, substeps: int, bending_iterations: int,
                 scalar=wp.float32):
    """``step(rest, w, link, local, compliance, gravity, dt, damping, qs, x, v)``: one frame of
    ``substeps`` substeps for each environment. ``qs`` (envs, substeps, dof): the joints at the end
    of each substep; ``x``, ``v`` (envs, particles) positions and velocities, updated in place;
    ``link[k] >= 0``: particle k is carried by that link from its zero-position point ``local[k]``."""
    S, V3, M33, M34, M44 = types_of(scalar)
    n_links = max(len(chain.parent), 1)
    fk = tree_fk(chain, links or {chain.root}, emit_local(scalar), scalar)
    P = int(particles)
    project = _length_projection(P, scalar)
    bend = _bending_solve(P, scalar)
    module = f"rswarp_cable_{chain.digest()}_{P}_{substeps}_{bending_iterations}_{scalar.__name__}"

    @wp.kernel(enable_backward=False, module=module)
    def step(rest: wp.array(dtype=S), w: wp.array(dtype=S), link: wp.array(dtype=wp.int32),
             local: wp.array(dtype=V3), compliance: wp.array(dtype=S), gravity: V3, dt: S, damping: S,
             qs: wp.array3d(dtype=S), x: wp.array2d(dtype=V3), v: wp.array2d(dtype=V3)):
        e = wp.tid()
        poses = wp.zeros(shape=n_links, dtype=M34)
        p = wp.zeros(shape=P, dtype=V3)
        keep = wp.exp(-damping * dt)
        for s in range(substeps):
            fk(qs[e], s, poses)
            for k in range(P):
                if link[k] >= 0:
                    m = poses[link[k]]
                    c = local[k]
                    p[k] = V3(m[0, 0] * c[0] + m[0, 1] * c[1] + m[0, 2] * c[2] + m[0, 3],
                              m[1, 0] * c[0] + m[1, 1] * c[1] + m[1, 2] * c[2] + m[1, 3],
                              m[2, 0] * c[0] + m[2, 1] * c[1] + m[2, 2] * c[2] + m[2, 3])
                else:
                    v[e, k] = v[e, k] + gravity * dt
                    p[k] = x[e, k] + v[e, k] * dt
            project(p, rest, w)
            lam = wp.zeros(shape=P, dtype=V3)  # XPBD multipliers of the curvature constraints
            for it in range(bending_iterations):
                bend(p, lam, w, compliance, dt)
                project(p, rest, w)
            for k in range(P):
                v[e, k] = (p[k] - x[e, k]) / dt * keep
                x[e, k] = p[k]

    return step


def _length_projection(P: int, scalar):
    """``project(p, rest, w)``: every segment k (particles k, k+1) back to its rest length, by
    NEWTON_STEPS Newton steps on all the distance constraints together (J W J^T is tridiagonal:
    the Thomas algorithm solves it in O(P)); particles with w = 0 do not move."""
    S, V3 = types_of(scalar).scalar, types_of(scalar).vec3
    n = max(P - 1, 1)

    @wp.func
    def project(p: Any, rest: wp.array(dtype=S), w: wp.array(dtype=S)):
        dirs = wp.zeros(shape=n, dtype=V3)
        c = wp.zeros(shape=n, dtype=S)  # superdiagonal, then the Thomas algorithm's factors
        d = wp.zeros(shape=n, dtype=S)  # right-hand side, then the solution
        for newton in range(NEWTON_STEPS):
            for k in range(P - 1):
                seg = p[k + 1] - p[k]
                length = wp.length(seg)
                dirs[k] = seg / wp.max(length, S(1.0e-12))
                d[k] = rest[k] - length
            prev_c = S(0.0)
            for k in range(P - 1):  # forward sweep: A[k,k] = w_k + w_k+1, A[k,k+1] = -w_k+1 n_k.n_k+1
                diag = w[k] + w[k + 1]
                sub = S(0.0)
                if k > 0:
                    sub = -w[k] * wp.dot(dirs[k - 1], dirs[k])
                denom = diag - sub * prev_c
                if denom <= S(1.0e-12):  # both ends held: nothing can move this segment
                    c[k] = S(0.0)
                    d[k] = S(0.0)
                    prev_c = S(0.0)
                    continue
                sup = S(0.0)
                if k < P - 2:
                    sup = -w[k + 1] * wp.dot(dirs[k], dirs[k + 1])
                c[k] = sup / denom
                if k > 0:
                    d[k] = (d[k] - sub * d[k - 1]) / denom
                else:
                    d[k] = d[k] / denom
                prev_c = c[k]
            for kk in range(P - 2):  # back substitution
                k = P - 3 - kk
                d[k] = d[k] - c[k] * d[k + 1]
            for k in range(P - 1):  # dp = W J^T dlambda: the segment's end moves along it
                p[k] = p[k] - w[k] * d[k] * dirs[k]
                p[k + 1] = p[k + 1] + w[k + 1] * d[k] * dirs[k]

    return project


def _bending_solve(P: int, scalar):
    """``bend(p, lam, w, compliance, dt)``: one XPBD step on every curvature constraint at once,
    C_k = p[k-1] - 2 p[k] + p[k+1] (linear in p), so (D W D^T + compliance / dt^2) dlam = -C -
    compliance / dt^2 lam is one symmetric pentadiagonal system (LDL^T in O(P), three right-hand
    sides): stiff hoses converge where Gauss-Seidel sweeps would not."""
    S, V3 = types_of(scalar).scalar, types_of(scalar).vec3
    n = max(P, 1)

    @wp.func
    def bend(p: Any, lam: Any, w: wp.array(dtype=S), compliance: wp.array(dtype=S), dt: S):
        d = wp.zeros(shape=n, dtype=S)
        l1 = wp.zeros(shape=n, dtype=S)
        l2 = wp.zeros(shape=n, dtype=S)
        y = wp.zeros(shape=n, dtype=V3)
        for k in range(1, P - 1):  # factor A = L D L^T and solve L y = rhs on the way
            a = compliance[k] / (dt * dt)
            akk = w[k - 1] + S(4.0) * w[k] + w[k + 1] + a
            rhs = -(p[k - 1] - S(2.0) * p[k] + p[k + 1]) - a * lam[k]
            if k >= 3:
                l2[k] = w[k - 1] / d[k - 2]  # A[k, k-2] = w[k-1]
            if k >= 2:
                l1[k] = (S(-2.0) * (w[k - 1] + w[k]) - l2[k] * l1[k - 1] * d[k - 2]) / d[k - 1]
            d[k] = akk - l1[k] * l1[k] * d[k - 1] - l2[k] * l2[k] * d[k - 2]
            y[k] = rhs - l1[k] * y[k - 1] - l2[k] * y[k - 2]
        for kk in range(P - 2):  # L^T x = y / d, from the end
            k = P - 2 - kk
            x = y[k] / d[k]
            if k + 1 <= P - 2:
                x = x - l1[k + 1] * y[k + 1]
            if k + 2 <= P - 2:
                x = x - l2[k + 2] * y[k + 2]
            y[k] = x
        for k in range(1, P - 1):  # dp = W D^T dlam
            lam[k] = lam[k] + y[k]
            p[k - 1] = p[k - 1] + w[k - 1] * y[k]
            p[k] = p[k] - S(2.0) * w[k] * y[k]
            p[k + 1] = p[k + 1] + w[k + 1] * y[k]

    return bend
