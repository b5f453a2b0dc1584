"""What the rod reports, as device functions for the step kernel (``kernel``): after each substep, the
greatest axial force (E A times the stretch at each joint, in newtons) and where, the least bend
radius and where, the twist rate and the torque the rod carries, each clamp's load, and the
contacts' normal forces and sliding, summed into the wear map (time in contact, peak normal force,
normal force times sliding distance per slot, bending cycles below the allowed radius) and the
hardest pinch (a segment pressed from opposite sides); at a
frame's end, the twist between each cable's clamped ends and the stretch between its
attachments."""

import warp as wp

from ..values import fresh
from .contact import contact_outcome
from .joint import axis_of, joint_forces, joint_strain, twist_angle
from .slots import BIG
from .step import attachment_pose
from .types import (
    BEND,
    BEND_AT,
    CONTACT_AT,
    F64,
    FORCE,
    FORCE_PEAK,
    M44,
    MAX_CONTACTS,
    MOMENT,
    MOMENT_PEAK,
    NORMAL,
    PINCH,
    PINCH_A,
    PINCH_AT,
    PINCH_B,
    SLIDING,
    STRETCH,
    TENSION,
    TENSION_AT,
    TINY,
    TORQUE,
    TORQUE_AT,
    TWIST,
    TWIST_RATE,
    V3,
    V6,
    BodyWork,
    Contact,
    Forces,
    Q,
    RodFrame,
    RodParams,
    RodWear,
)


@wp.func
def bend_radius(ta: V3, tb: V3, length: F64) -> F64:
    """The bend radius of a turn from tangent ta to tb over ``length``: l / (2 tan(angle / 2)),
    the discrete curvature of elastic rods; BIG when straight."""
    s = wp.length(wp.cross(ta, tb))
    if s < F64(TINY):
        return F64(BIG)
    return length * (F64(1.0) + wp.dot(ta, tb)) / (F64(2.0) * s)


@wp.func
def _joint(stats_out: wp.array3d(dtype=F64), e: int, c: int, gap: V3, rot: V3, rel: Q, k: V6,
           ta: V3, tb: V3, length: F64, arc: F64) -> F64:
    """One joint's tension, bend and twist into its cable's frame extremes; its bend radius."""
    tension = k[2] * gap[2]
    if tension > stats_out[e, c, TENSION]:
        stats_out[e, c, TENSION] = tension
        stats_out[e, c, TENSION_AT] = arc
    radius = bend_radius(ta, tb, length)
    if radius < stats_out[e, c, BEND]:
        stats_out[e, c, BEND] = radius
        stats_out[e, c, BEND_AT] = arc
    torque = wp.abs(k[5] * rot[2])
    if k[5] > F64(0.0):
        if torque > stats_out[e, c, TORQUE]:
            stats_out[e, c, TORQUE] = torque
            stats_out[e, c, TORQUE_AT] = arc
        stats_out[e, c, TWIST_RATE] = wp.max(stats_out[e, c, TWIST_RATE], wp.abs(twist_angle(rel)) / length)
    return radius


@wp.func
def _load(load_out: wp.array3d(dtype=F64), e: int, a: int, force: V3, moment: V3):
    load_out[e, a, FORCE_PEAK] = wp.max(load_out[e, a, FORCE_PEAK], wp.length(force))
    load_out[e, a, MOMENT_PEAK] = wp.max(load_out[e, a, MOMENT_PEAK], wp.length(moment))
    for i in range(3):
        load_out[e, a, FORCE + i] = force[i]
        load_out[e, a, MOMENT + i] = moment[i]


@wp.func
def _attachments(params: RodParams, d: int, poses: wp.array3d(dtype=M44), e: int, s: int, k: int, b: BodyWork,
                 stats_out: wp.array3d(dtype=F64), load_out: wp.array3d(dtype=F64)) -> F64:
    """Body k's clamps: their joints' strain into the extremes, and the load each puts on its link
    (the force and moment the cable pulls it with, about the control point). The least bend radius
    at them."""
    c = params.cable[d, k]
    half = params.half[d, k]
    least = fresh(F64(BIG))
    for a in range(params.attach_first[d, k], params.attach_first[d, k + 1]):
        p, f = attachment_pose(params, d, poses, e, s, a)
        k6 = params.attach_stiff[d, a]
        clamped = k6[5] > F64(0.0)
        if params.attach_end[a] > F64(0.0):
            gap, rot, rel = joint_strain(b.x, b.q, half, p, f, F64(0.0))
            fb, tb, lever = joint_forces(b.x, b.q, half, p, f, F64(0.0), k6)
            _load(load_out, e, a, fb, tb)
            if clamped:
                least = wp.min(least, _joint(stats_out, e, c, gap, rot, rel, k6, axis_of(b.q), axis_of(f), half,
                                             params.arc[d, k] + F64(2.0) * half))
        else:
            gap, rot, rel = joint_strain(p, f, F64(0.0), b.x, b.q, -half)
            fb, tb, lever = joint_forces(p, f, F64(0.0), b.x, b.q, -half, k6)
            _load(load_out, e, a, -fb, -tb - wp.cross(lever, fb))
            if clamped:
                least = wp.min(least, _joint(stats_out, e, c, gap, rot, rel, k6, axis_of(f), axis_of(b.q), half,
                                             params.arc[d, k]))
        if not clamped:  # a ball joint: the stretch only
            tension = k6[2] * gap[2]
            if tension > stats_out[e, c, TENSION]:
                stats_out[e, c, TENSION] = tension
                stats_out[e, c, TENSION_AT] = params.arc[d, k] + (F64(1.0) + params.attach_end[a]) * half
    return least


@wp.func
def _wear(params: RodParams, d: int, k: int, b: BodyWork, contacts: wp.array2d(dtype=Contact),
          count: wp.array2d(dtype=wp.int32), row: int, h: F64, e: int, stats_out: wp.array3d(dtype=F64),
          wear_out: RodWear):
    """Body k's contacts at the step's end: normal force and sliding into the wear map. The slot a
    contact is crushed into, or -1, and each contact's normal force."""
    c = params.cable[d, k]
    total = F64(0.0)
    crushed = int(-1)
    forces = Forces()
    for i in range(count[row, k]):
        ct = contacts[row, k * MAX_CONTACTS + i]
        force, slide, crush = contact_outcome(ct, b.x, b.q, params.contact_stiff[d, k])
        forces[i] = force
        if crush:
            crushed = ct.slot
        if force > F64(0.0):
            total = total + force
            wear_out.wear[e, k, ct.slot] = wear_out.wear[e, k, ct.slot] + force * slide
            stats_out[e, c, SLIDING] = wp.max(stats_out[e, c, SLIDING], slide / h)
            if force > stats_out[e, c, NORMAL]:
                stats_out[e, c, NORMAL] = force
                stats_out[e, c, CONTACT_AT] = ct.arc
    if total > F64(0.0):
        wear_out.time[e, k] = wear_out.time[e, k] + h
        wear_out.peak[e, k] = wp.max(wear_out.peak[e, k], total)
    return crushed, forces


@wp.func
def _pinch(params: RodParams, d: int, k: int, forces: Forces, contacts: wp.array2d(dtype=Contact),
           count: wp.array2d(dtype=wp.int32), row: int, e: int, stats_out: wp.array3d(dtype=F64)):
    """Body k's pinch at the step's end into its cable's extremes: over each pair of its contacts
    (normal ``forces`` from ``_wear``), the lesser force times how far their normals oppose (0 for
    a segment that only rests or leans on things; the lesser force where two surfaces press it
    from opposite sides), and the pair's slots."""
    c = params.cable[d, k]
    for i in range(count[row, k]):
        ci = contacts[row, k * MAX_CONTACTS + i]
        for j in range(i + 1, count[row, k]):
            cj = contacts[row, k * MAX_CONTACTS + j]
            squeeze = wp.min(forces[i], forces[j]) * wp.max(-wp.dot(ci.n, cj.n), F64(0.0))
            if squeeze > stats_out[e, c, PINCH]:
                stats_out[e, c, PINCH] = squeeze
                stats_out[e, c, PINCH_AT] = F64(0.5) * (ci.arc + cj.arc)
                stats_out[e, c, PINCH_A] = F64(ci.slot)
                stats_out[e, c, PINCH_B] = F64(cj.slot)


@wp.func
def measure(
    # In:
    params: RodParams,
    d: int,
    poses: wp.array3d(dtype=M44),
    e: int,
    s: int,
    h: F64,
    # Scratch (the substep's bodies and contacts, read):
    work: wp.array2d(dtype=BodyWork),
    contacts: wp.array2d(dtype=Contact),
    count: wp.array2d(dtype=wp.int32),
    row: int,
    # Out (the frame's extremes, and the wear map accumulated in place):
    frame_out: RodFrame,
    wear_out: RodWear,
) -> int:
    """The substep's strains, loads and contacts at its end, into the frame's extremes and the wear
    map; a body's curvature (its tighter joint); crossing back above the allowed radius is a cycle. The
    slot a cable was crushed into, or -1."""
    stats_out = frame_out.stats
    load_out = frame_out.load
    bend_out = wear_out.bend
    cycles_out = wear_out.cycles
    bodies = params.bodies[d]
    crushed = int(-1)
    before = fresh(F64(BIG))  # the bend radius at the current body's start joint
    for k in range(bodies):
        b = work[row, k]
        c = params.cable[d, k]
        after = F64(BIG)
        if k + 1 < bodies:
            if params.stiff[d, k][2] > F64(0.0):
                nb = work[row, k + 1]
                gap, rot, rel = joint_strain(b.x, b.q, params.half[d, k], nb.x, nb.q, -params.half[d, k + 1])
                after = _joint(stats_out, e, c, gap, rot, rel, params.stiff[d, k], axis_of(b.q), axis_of(nb.q),
                               params.half[d, k] + params.half[d, k + 1], params.arc[d, k + 1])
        least = wp.min(wp.min(before, after), _attachments(params, d, poses, e, s, k, b, stats_out, load_out))
        # its curvature (1/m), for fatigue; past the allowed one's and back is a cycle
        bend = F64(1.0) / wp.max(least, F64(TINY))
        if bend_out[e, k] * params.allowed[c] > F64(1.0) and least >= params.allowed[c]:
            cycles_out[e, k] = cycles_out[e, k] + 1
        bend_out[e, k] = bend
        slot, forces = _wear(params, d, k, b, contacts, count, row, h, e, stats_out, wear_out)
        _pinch(params, d, k, forces, contacts, count, row, e, stats_out)
        if slot >= 0:
            crushed = slot
        before = after
    return crushed


@wp.func
def twist_between(params: RodParams, d: int, poses: wp.array3d(dtype=M44), e: int, s: int, c: int,
                  x_s: wp.array2d(dtype=V3), q_s: wp.array2d(dtype=Q)) -> F64:
    """The twist (rad) between cable c's clamped ends: each joint's turn about the cable, summed
    from the first clamp to the last; 0 unless both ends are clamped."""
    a = params.clamp_a[c]
    z = params.clamp_b[c]
    if a < 0 or z < 0:
        return F64(0.0)
    first = params.attach_body[d, a]
    last = params.attach_body[d, z]
    pa, fa = attachment_pose(params, d, poses, e, s, a)
    pz, fz = attachment_pose(params, d, poses, e, s, z)
    gap, rot, rel = joint_strain(pa, fa, F64(0.0), x_s[e, first], q_s[e, first], -params.half[d, first])
    total = twist_angle(rel)
    for k in range(first, last):
        gap, rot, rel = joint_strain(x_s[e, k], q_s[e, k], params.half[d, k], x_s[e, k + 1], q_s[e, k + 1],
                                     -params.half[d, k + 1])
        total = total + twist_angle(rel)
    gap, rot, rel = joint_strain(x_s[e, last], q_s[e, last], params.half[d, last], pz, fz, F64(0.0))
    return total + twist_angle(rel)


@wp.func
def frame_end(params: RodParams, d: int, poses: wp.array3d(dtype=M44), e: int, s: int, x_s: wp.array2d(dtype=V3),
              q_s: wp.array2d(dtype=Q), stats_out: wp.array3d(dtype=F64)):
    """Each cable's twist between its clamps and the greatest straight distance between two
    consecutive attachments over the cable's length between them."""
    for c in range(params.cable_first.shape[1] - 1):
        stats_out[e, c, TWIST] = twist_between(params, d, poses, e, s, c, x_s, q_s)
        stats_out[e, c, STRETCH] = F64(0.0)
    for i in range(params.pair_a.shape[0]):
        pa, fa = attachment_pose(params, d, poses, e, s, params.pair_a[i])
        pb, fb = attachment_pose(params, d, poses, e, s, params.pair_b[i])
        c = params.pair_cable[i]
        stats_out[e, c, STRETCH] = wp.max(stats_out[e, c, STRETCH], wp.length(pb - pa) / params.pair_length[d, i])
