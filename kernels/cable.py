"""Cable dynamics as device code: one environment per thread, its cable a chain of particles.

Each substep: forward kinematics poses the links the cable is attached to or may touch
(``tree_fk``, inside the kernel); attached particles (and, where a control point clamps the
tangent, their ghost neighbour) move rigidly with their links; free particles fall under gravity.
Contact (``cable_contact``) keeps them out of the link meshes and the floor. Then the chain is
made inextensible exactly: a few Newton steps on all its distance constraints at once, a
tridiagonal system solved in linear time (a direct solve, not Gauss-Seidel sweeps, so long cables
do not stretch under their weight). Bending follows by XPBD on the discrete curvature x[i-1] -
2 x[i] + x[i+1] with compliance l^3 / EI, then the lengths are restored and contact again.
Velocities are the positions' change, damped. Each frame reports the peak tension, the tightest
bend, the twist, the stretch between attachments, and the least clearance per link and to the
floor: the statistics the host reads, while the state stays where the kernel runs.
"""

from typing import Any

import warp as wp

from .cable_contact import BIG, CableParams, near_function, sharpest_function, stretch_function, twist_function
from .cache import cached, module_name
from .fk import emit_local, pose_functions, tree_fk
from .types import Chain, types_of

NEWTON_STEPS = 3  # exact-length projections per substep (quadratic convergence)

# columns of a frame's statistics, per environment
TENSION, BEND, BEND_AT, TWIST, STRETCH = range(5)
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


@cached
def cable_kernel(chain: Chain, links, particles: int, bending_iterations: int):
    """``step``: one frame for each environment, in as many substeps as ``qs`` (envs, substeps,
    dof: the joints at each substep's end) has rows; the state is updated in place and the frame's
    statistics written (``STATS`` columns; the least clearance to each link, the floor last, and
    the particle where). An environment that blows up stops, frozen, with its status set."""
    S = wp.float32
    M34 = types_of(S).mat34
    n_links = max(len(chain.parent), 1)
    slots = n_links + 1  # each link, then the floor
    P = capacity(particles)
    advance = _advance_function(chain, links)
    near = near_function(n_links)
    substep = _substep_function(P, bending_iterations, near)
    sharpest, twist, stretch, commit = sharpest_function(), twist_function(), stretch_function(), _commit_function()
    copy_out = _copy_function()
    module = module_name("cable", chain, links, P, bending_iterations)

    @wp.kernel(enable_backward=False, module=module)
    def step(
        # Model:
        params: CableParams,
        dt: S,
        # In:
        qs: wp.array3d(dtype=S),
        # Out (the state, read and updated in place):
        x_out: wp.array2d(dtype=wp.vec3),
        v_out: wp.array2d(dtype=wp.vec3),
        status_out: wp.array(dtype=wp.int32),
        # Out (the frame's statistics):
        stats_out: wp.array2d(dtype=S),
        clear_out: wp.array2d(dtype=S),
        at_out: wp.array2d(dtype=wp.int32),
    ):
        e = wp.tid()
        if status_out[e] != RUNNING:
            return
        poses = wp.zeros(shape=n_links, dtype=M34)
        p = wp.zeros(shape=P, dtype=wp.vec3)
        gap = wp.zeros(shape=slots, dtype=S)
        where = wp.zeros(shape=slots, dtype=wp.int32)
        for j in range(slots):
            gap[j] = S(BIG)
            where[j] = -1
        h = dt / S(qs.shape[1])
        peak = S(0.0)
        tightest = S(BIG)
        tightest_at = int(-1)
        for s in range(qs.shape[1]):
            advance(params, poses, qs[e], s, h, x_out, v_out, e, p)
            peak = wp.max(peak, substep(p, params, poses, h, gap, where))
            r, k_r = sharpest(p, params)
            if r < tightest:
                tightest = r
                tightest_at = k_r
            failed = commit(p, params, h, x_out, v_out, e)
            if failed != RUNNING:
                status_out[e] = failed
                return
        near(p, params, poses, params.reach, 0, gap, where)
        stats_out[e, TENSION] = peak
        stats_out[e, BEND] = tightest
        stats_out[e, BEND_AT] = S(tightest_at)
        stats_out[e, TWIST] = twist(p, params, poses)
        stats_out[e, STRETCH] = stretch(p, params)
        copy_out(gap, where, e, clear_out, at_out)

    return step


def _copy_function():
    """``copy_out(gap, where, e, clear_out, at_out)``: an environment's clearance slots into the
    frame's statistics."""

    @wp.func
    def copy_out(gap: Any, where: Any, e: int, clear_out: wp.array2d(dtype=wp.float32),
                 at_out: wp.array2d(dtype=wp.int32)):
        for j in range(clear_out.shape[1]):
            clear_out[e, j] = gap[j]
            at_out[e, j] = where[j]

    return copy_out


def _advance_function(chain: Chain, links: set):
    """``advance(params, poses, q, s, h, x, v, e, p)``: forward kinematics for substep ``s``, then the
    predicted positions: carried particles where their links are, free ones by their velocity
    and gravity (the velocity updated)."""
    S = wp.float32
    fk = tree_fk(chain, links or {chain.root}, emit_local(S), S)
    apply = pose_functions(S)[2]

    @wp.func
    def advance(params: CableParams, poses: Any, q: wp.array2d(dtype=S), s: int, h: S,
                x: Any, v: Any, e: int, p: Any):
        fk(q, s, poses)
        for k in range(params.w.shape[0]):
            if params.link[k] >= 0:
                p[k] = apply(poses[params.link[k]], params.local[k])
            else:
                v[e, k] = v[e, k] + params.gravity * h
                p[k] = x[e, k] + v[e, k] * h

    return advance


def _substep_function(P: int, bending_iterations: int, near):
    """``substep(p, params, poses, h, gap, where) -> tension``: contact, exact lengths, bending,
    lengths and contact again on the predicted positions; the greatest segment tension (N)."""
    S = wp.float32
    project = _length_projection(P, S)
    bend = _bending_solve(P, S)

    @wp.func
    def substep(p: Any, params: CableParams, poses: Any, h: S, gap: Any, where: Any) -> S:
        near(p, params, poses, params.margin, 1, gap, where)
        impulse = wp.zeros(shape=P, dtype=S)  # each segment's constraint impulse this substep
        project(p, params.rest, params.w, impulse)
        lam = wp.zeros(shape=P, dtype=wp.vec3)  # XPBD multipliers of the curvature constraints
        for _ in range(bending_iterations):
            bend(p, lam, params.w, params.compliance, h)
            project(p, params.rest, params.w, impulse)
        near(p, params, poses, params.margin, 1, gap, where)
        peak = S(0.0)
        for k in range(params.rest.shape[0]):
            peak = wp.max(peak, -impulse[k] / (h * h))
        return peak

    return substep


def _commit_function():
    """``commit(p, params, h, x, v, e) -> status``: the substep's positions and damped velocities
    into the state, unless a particle is not finite or faster than ``max_speed``: then the state
    stays as it was and the failure is returned."""

    @wp.func
    def commit(p: Any, params: CableParams, h: float, x: wp.array2d(dtype=wp.vec3), v: wp.array2d(dtype=wp.vec3),
               e: int) -> int:
        keep = wp.exp(-params.damping * h)
        for k in range(params.w.shape[0]):
            speed = wp.length(p[k] - x[e, k]) / h * keep
            if not wp.isfinite(speed):
                return NOT_FINITE
            if speed > params.max_speed:
                return RUNAWAY
        for k in range(params.w.shape[0]):
            v[e, k] = (p[k] - x[e, k]) / h * keep
            x[e, k] = p[k]
        return RUNNING

    return commit


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
        for _ in range(NEWTON_STEPS):
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
