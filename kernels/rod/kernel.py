"""Cables as discrete Cosserat rods, as device code: one environment per thread, every cable of the
mechanism in it, each a chain of rigid segments (a centre and a quaternion, its material frame)
joined by elastic joints that stretch and shear (E A, kappa G A), bend (E I) and twist (G J).

Each substep: the link poses (given per substep, so the kernel serves every mechanism) carry the
clamps; contacts are found and linearized (``gather``); implicit Euler is solved by Gauss-Newton
iterations, each a direct block-tridiagonal solve (``step``); what the substep did is measured
(``measure``) and committed. An environment that blows up stops, frozen, with its status set.
Each frame reports, per cable, the greatest tension, the least bend radius, the twist, twist rate
and torque, the stretch between attachments, the contacts' greatest normal force and sliding
speed, the least clearance to every slot, and each clamp's load; the wear map grows in place."""

import warp as wp

from ..cache import FUSED, INLINE_ALL, cached, cpu_flags, module_name
from .clearance import mesh_clearances
from .gather import capsule_pairs, every_floor, every_surface, swept
from .measure import frame_end, measure
from .slots import BIG, CRUSHED, RUNNING
from .step import commit, free_start, iterate, predict
from .types import (
    BEND,
    BEND_AT,
    CONTACT_AT,
    F64,
    LOADS,
    M44,
    PINCH_A,
    PINCH_AT,
    PINCH_B,
    STATS,
    TENSION_AT,
    TORQUE_AT,
    BodyWork,
    Contact,
    Factor,
    RodBodies,
    RodFrame,
    RodParams,
    RodWear,
)

AT_NONE = -1.0  # an "at" column where nothing was found
STEP_TOLERANCE = 1e-6  # m: an iteration that moves no segment's surface further has converged


@wp.func
def _start_frame(params: RodParams, e: int, frame_out: RodFrame):
    stats_out = frame_out.stats
    clear_out = frame_out.clear
    at_out = frame_out.at
    load_out = frame_out.load
    for c in range(stats_out.shape[1]):
        for i in range(STATS):
            stats_out[e, c, i] = F64(0.0)
        stats_out[e, c, BEND] = F64(BIG)
        stats_out[e, c, TENSION_AT] = F64(AT_NONE)
        stats_out[e, c, BEND_AT] = F64(AT_NONE)
        stats_out[e, c, TORQUE_AT] = F64(AT_NONE)
        stats_out[e, c, CONTACT_AT] = F64(AT_NONE)
        stats_out[e, c, PINCH_AT] = F64(AT_NONE)
        stats_out[e, c, PINCH_A] = F64(-1.0)
        stats_out[e, c, PINCH_B] = F64(-1.0)
        for j in range(clear_out.shape[2]):
            clear_out[e, c, j] = F64(BIG)
            at_out[e, c, j] = F64(AT_NONE)
    for a in range(load_out.shape[1]):
        for i in range(LOADS):
            load_out[e, a, i] = F64(0.0)


@wp.func
def _contacts(params: RodParams, d: int, poses: wp.array3d(dtype=M44), e: int, s: int, state: RodBodies,
              work: wp.array2d(dtype=BodyWork), contacts: wp.array2d(dtype=Contact),
              count: wp.array2d(dtype=wp.int32), row: int, frame_out: RodFrame):
    """The substep's contacts at its start (pose rows s and s + 1 before and after it)."""
    x_s = state.x
    q_s = state.q
    for k in range(params.bodies[d]):
        count[row, k] = 0
        b = work[row, k]
        b.sweep = swept(params, d, work, x_s, q_s, e, row, k)
        work[row, k] = b
    every_surface(params, d, poses, e, s, s + 1, x_s, q_s, work, params.margin[d], contacts, count, row,
                  frame_out.clear, frame_out.at)
    capsule_pairs(params, d, work, x_s, q_s, e, params.margin[d], 1, contacts, count, row, frame_out.clear,
                  frame_out.at)


@wp.func
def _clearances(params: RodParams, d: int, poses: wp.array3d(dtype=M44), e: int, s: int, state: RodBodies,
                work: wp.array2d(dtype=BodyWork), contacts: wp.array2d(dtype=Contact),
                count: wp.array2d(dtype=wp.int32), row: int, wear_out: RodWear, frame_out: RodFrame):
    """The frame's end: every clearance within ``reach``; with ``lowering``, a mesh's only where it
    lowers the least so far, which it then keeps."""
    least = wear_out.least
    mesh_clearances(params, d, poses, e, s, state.x, state.q, params.reach, least, frame_out.clear, frame_out.at)
    every_floor(params, d, e, state.x, state.q, params.reach, contacts, count, row, frame_out.clear, frame_out.at)
    capsule_pairs(params, d, work, state.x, state.q, e, params.reach, 0, contacts, count, row, frame_out.clear,
                  frame_out.at)
    if params.lowering != 0:
        for c in range(least.shape[1]):
            for j in range(params.mesh.shape[0]):
                least[e, c, j] = wp.min(least[e, c, j], frame_out.clear[e, c, j])


@wp.func
def _substep(
    # In:
    params: RodParams,
    d: int,
    poses: wp.array3d(dtype=M44),
    e: int,
    s: int,
    h: F64,
    iterations: int,
    # Scratch:
    work: wp.array2d(dtype=BodyWork),
    factor: wp.array2d(dtype=Factor),
    contacts: wp.array2d(dtype=Contact),
    count: wp.array2d(dtype=wp.int32),
    row: int,
    # Out (the state and the wear map updated in place, the frame's statistics):
    state_out: RodBodies,
    wear_out: RodWear,
    frame_out: RodFrame,
) -> int:
    """Substep ``s``: predict, find contacts, iterate, measure and commit. RUNNING, or why the
    environment stops (nothing committed then)."""
    predict(params, d, state_out.x, state_out.q, state_out.v, state_out.w, state_out.a, e, work, row, h)
    _contacts(params, d, poses, e, s, state_out, work, contacts, count, row, frame_out)
    free_start(params, d, work, count, row)
    for _ in range(iterations):
        # Newton's step length bounds what is left of the error: a step under STEP_TOLERANCE ends
        # the substep's iterations (a cable at rest takes one; a moving or rubbing one, all)
        if iterate(params, d, poses, e, s + 1, h, work, factor, contacts, count, row) < F64(STEP_TOLERANCE):
            break
    crushed = measure(params, d, poses, e, s + 1, h, work, contacts, count, row, frame_out, wear_out)
    if crushed >= 0:
        return CRUSHED + crushed
    return commit(params, d, work, row, h, state_out.x, state_out.q, state_out.v, state_out.w, state_out.a, e)


@cached
def rod_kernel():
    """``step``: one frame of every environment, in as many substeps as ``poses`` (envs, substeps +
    1, links: each link's pose at the frame's start, then at each substep's end) has rows after
    the first; the state and the wear map are updated in place and the frame's statistics
    written. One kernel serves every mechanism."""

    @wp.kernel(enable_backward=False, module=module_name("rod"))
    def step(
        # Model:
        params: RodParams,
        dt: F64,
        iterations: int,
        # In:
        poses: wp.array3d(dtype=M44),
        design: wp.array(dtype=wp.int32),  # each environment's design: its row of the per-design arrays
        # Scratch:
        work: wp.array2d(dtype=BodyWork),
        factor: wp.array2d(dtype=Factor),
        contacts: wp.array2d(dtype=Contact),
        count: wp.array2d(dtype=wp.int32),
        # Out (read and updated in place): the bodies and status; the wear map, accumulated
        state_out: RodBodies,
        wear_out: RodWear,
        # Out (written): the frame's statistics
        frame_out: RodFrame,
    ):
        e = wp.tid()
        if state_out.status[e] != RUNNING:
            return
        d = design[e]
        row = e  # this thread's rows of the scratch arrays
        _start_frame(params, e, frame_out)
        substeps = poses.shape[1] - 1
        h = dt / F64(substeps)
        for s in range(substeps):
            status = _substep(params, d, poses, e, s, h, iterations, work, factor, contacts, count, row, state_out,
                              wear_out, frame_out)
            if status != RUNNING:
                state_out.status[e] = status
                return
        frame_end(params, d, poses, e, substeps, state_out.x, state_out.q, frame_out.stats)
        _clearances(params, d, poses, e, substeps, state_out, work, contacts, count, row, wear_out, frame_out)

    # multiply-adds fused; the substep and the surfaces inlined: no copy of params a call
    cpu_flags(step.module, f"{FUSED} {INLINE_ALL}")
    return step
