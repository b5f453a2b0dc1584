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

from .cable_contact import BIG, CableParams, contact_functions
from .fk import emit_local, pose_functions, tree_fk
from .types import Chain, types_of

NEWTON_STEPS = 3  # exact-length projections per substep (quadratic convergence)

# columns of a frame's statistics, per environment
TENSION, BEND, BEND_AT, ENERGY, TWIST = range(5)
STATS = 5
# an environment's state
RUNNING, NOT_FINITE, RUNAWAY = 0, 1, 2
MAX_PARTICLES = 4096  # per cable (its particle arrays live in each thread's local memory)


def capacity(particles: int) -> int:
    """The local-array size a kernel is built for: the next power of two from 16, so cables of
    similar sizes share one compiled kernel (the count itself is read at run time)."""
    if particles > MAX_PARTICLES:
        raise ValueError(f"a cable of {particles} particles is over the {MAX_PARTICLES} a kernel holds")
    return max(16, 1 << (int(particles) - 1).bit_length())


def cable_kernel(chain: Chain, links: set, particles: int, bending_iterations: int):
    """``step(prm, dt, qs, x, v, status, stats, clear, at)``: one frame for each environment, in as
    many substeps as ``qs`` has rows. ``qs`` (envs, substeps, dof): the joints at the end of each substep; ``x``,
    ``v`` (envs, particles) positions and velocities and ``status`` (envs,), updated in place;
    ``stats`` (envs, STATS) the frame's peak tension, least bend radius and where, kinetic energy
    and twist; ``clear``, ``at`` (envs, links + 1): the least clearance to each link (the floor
    last) over the frame and the particle where. An environment that blows up stops, frozen, with
    its status set."""
    S = wp.float32
    M34 = types_of(S).mat34
    n_links = max(len(chain.parent), 1)
    slots = n_links + 1  # each link, then the floor
    fk = tree_fk(chain, links or {chain.root}, emit_local(S), S)
    apply = pose_functions(S)[2]
    P = capacity(particles)
    project = _length_projection(P, S)
    bend = _bending_solve(P, S)
    near, sharpest, twist = contact_functions(n_links)
    carried = "-".join(str(k) for k in sorted(links))
    module = f"rswarp_cable_{chain.digest()}_{carried}_{P}_{bending_iterations}"

    @wp.func
    def advance(prm: CableParams, poses: Any, q: wp.array2d(dtype=S), s: int, h: S,
                x: Any, v: Any, e: int, p: Any):
        """Predicted positions: carried particles where their links are, free ones by their
        velocity and gravity."""
        fk(q, s, poses)
        for k in range(prm.w.shape[0]):
            if prm.link[k] >= 0:
                p[k] = apply(poses[prm.link[k]], prm.local[k])
            else:
                v[e, k] = v[e, k] + prm.gravity * h
                p[k] = x[e, k] + v[e, k] * h

    @wp.kernel(enable_backward=False, module=module)
    def step(prm: CableParams, dt: S, qs: wp.array3d(dtype=S), x: wp.array2d(dtype=wp.vec3),
             v: wp.array2d(dtype=wp.vec3), status: wp.array(dtype=wp.int32), stats: wp.array2d(dtype=S),
             clear: wp.array2d(dtype=S), at: wp.array2d(dtype=wp.int32)):
        e = wp.tid()
        if status[e] != RUNNING:
            return
        poses = wp.zeros(shape=n_links, dtype=M34)
        p = wp.zeros(shape=P, dtype=wp.vec3)
        gap = wp.zeros(shape=slots, dtype=S)
        where = wp.zeros(shape=slots, dtype=wp.int32)
        for j in range(n_links + 1):
            gap[j] = S(BIG)
            where[j] = -1
        substeps = qs.shape[1]
        h = dt / S(substeps)
        keep = wp.exp(-prm.damping * h)
        peak = S(0.0)
        tightest = S(BIG)
        tightest_at = int(-1)
        count = prm.w.shape[0]
        for s in range(substeps):
            advance(prm, poses, qs[e], s, h, x, v, e, p)
            near(p, prm, poses, prm.margin, 1, gap, where)
            impulse = wp.zeros(shape=P, dtype=S)  # each segment's constraint impulse this substep
            project(p, prm.rest, prm.w, impulse)
            lam = wp.zeros(shape=P, dtype=wp.vec3)  # XPBD multipliers of the curvature constraints
            for it in range(bending_iterations):
                bend(p, lam, prm.w, prm.compliance, h)
                project(p, prm.rest, prm.w, impulse)
            near(p, prm, poses, prm.margin, 1, gap, where)
            for k in range(count - 1):
                peak = wp.max(peak, -impulse[k] / (h * h))
            r, k_r = sharpest(p, prm)
            if r < tightest:
                tightest = r
                tightest_at = k_r
            energy = S(0.0)
            for k in range(count):
                u = (p[k] - x[e, k]) / h * keep
                speed = wp.length(u)
                if not wp.isfinite(speed):
                    status[e] = NOT_FINITE
                    return
                if speed > prm.max_speed:
                    status[e] = RUNAWAY
                    return
                if prm.w[k] > 0.0:
                    energy = energy + S(0.5) * speed * speed / prm.w[k]
                v[e, k] = u
                x[e, k] = p[k]
            stats[e, ENERGY] = energy
        near(p, prm, poses, prm.reach, 0, gap, where)
        stats[e, TENSION] = peak
        stats[e, BEND] = tightest
        stats[e, BEND_AT] = S(tightest_at)
        stats[e, TWIST] = twist(p, prm, poses)
        for j in range(n_links + 1):
            clear[e, j] = gap[j]
            at[e, j] = where[j]

    return step


def _length_projection(P: int, scalar):
    """``project(p, rest, w, impulse)``: every segment k (particles k, k+1) back to its rest length,
    by NEWTON_STEPS Newton steps on all the distance constraints together (J W J^T is tridiagonal:
    the Thomas algorithm solves it in O(P)); particles with w = 0 do not move. ``impulse[k]`` adds
    the segment's multiplier (kg m; negative when it pulls: tension is -impulse / h^2)."""
    S, V3 = types_of(scalar).scalar, types_of(scalar).vec3
    n = max(P - 1, 1)

    @wp.func
    def project(p: Any, rest: wp.array(dtype=S), w: wp.array(dtype=S), impulse: Any):
        dirs = wp.zeros(shape=n, dtype=V3)
        c = wp.zeros(shape=n, dtype=S)  # superdiagonal, then the Thomas algorithm's factors
        d = wp.zeros(shape=n, dtype=S)  # right-hand side, then the solution
        count = rest.shape[0] + 1
        for newton in range(NEWTON_STEPS):
            for k in range(count - 1):
                seg = p[k + 1] - p[k]
                length = wp.length(seg)
                dirs[k] = seg / wp.max(length, S(1.0e-12))
                d[k] = rest[k] - length
            prev_c = S(0.0)
            for k in range(count - 1):  # forward sweep: A[k,k] = w_k + w_k+1, A[k,k+1] = -w_k+1 n_k.n_k+1
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
                if k < count - 2:
                    sup = -w[k + 1] * wp.dot(dirs[k], dirs[k + 1])
                c[k] = sup / denom
                if k > 0:
                    d[k] = (d[k] - sub * d[k - 1]) / denom
                else:
                    d[k] = d[k] / denom
                prev_c = c[k]
            for kk in range(count - 2):  # back substitution
                k = count - 3 - kk
                d[k] = d[k] - c[k] * d[k + 1]
            for k in range(count - 1):  # dp = W J^T dlambda: the segment's end moves along it
                impulse[k] = impulse[k] + d[k]
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
        count = w.shape[0]
        for k in range(1, count - 1):  # factor A = L D L^T and solve L y = rhs on the way
            a = compliance[k] / (dt * dt)
            akk = w[k - 1] + S(4.0) * w[k] + w[k + 1] + a
            rhs = -(p[k - 1] - S(2.0) * p[k] + p[k + 1]) - a * lam[k]
            if k >= 3:
                l2[k] = w[k - 1] / d[k - 2]  # A[k, k-2] = w[k-1]
            if k >= 2:
                l1[k] = (S(-2.0) * (w[k - 1] + w[k]) - l2[k] * l1[k - 1] * d[k - 2]) / d[k - 1]
            d[k] = akk - l1[k] * l1[k] * d[k - 1] - l2[k] * l2[k] * d[k - 2]
            y[k] = rhs - l1[k] * y[k - 1] - l2[k] * y[k - 2]
        for kk in range(count - 2):  # L^T x = y / d, from the end
            k = count - 2 - kk
            x = y[k] / d[k]
            if k + 1 <= count - 2:
                x = x - l1[k + 1] * y[k + 1]
            if k + 2 <= count - 2:
                x = x - l2[k + 2] * y[k + 2]
            y[k] = x
        for k in range(1, count - 1):  # dp = W D^T dlam
            lam[k] = lam[k] + y[k]
            p[k - 1] = p[k - 1] + w[k - 1] * y[k]
            p[k] = p[k] - S(2.0) * w[k] * y[k]
            p[k + 1] = p[k + 1] + w[k + 1] * y[k]

    return bend
