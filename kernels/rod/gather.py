"""Finding a rod's contacts at the start of a substep (and its clearances at a frame's end): each
segment's capsule against every mesh it may touch and the floor (``surfaces``), and every two
capsules of the mechanism's cables that are not neighbours along one cable (``capsule_pairs``).
Each gap found lowers its cable's least clearance to that slot (``slots``: a mesh's own, the
floor's or the cables'); with ``make``, gaps under the query distance become contacts of the
substep. A frame's clearances to the meshes are ``clearance``'s."""

import warp as wp

from .algebra import rotation_vector
from .contact import (
    BOX_HAIR,
    box_distance,
    closest_on_segments,
    contact,
    from_frame,
    keep,
    may_touch,
    mesh_pose,
    note,
    past_sphere,
    segment_mesh,
    to_frame,
    turn,
)
from .joint import axis_of
from .slots import CABLES, FLOOR
from .types import F64, M44, TINY, V3, BodyWork, Contact, Q, RodParams

# two segments of one cable closer than this along it (beyond their half lengths, in radii) never
# touch: a straight cable's neighbours would
NEIGHBOURS = 2.0
FOLD = 3.141592653589793  # along a hose, pi allowed bend radii: the least arc that turns back on itself
# a contact is made ahead for what may meet in the substep: within the query distance plus this many
# times the bodies' predicted sweeps (a snapping cable accelerates past its prediction)
AHEAD = 2.0
# m: more than rounding may take from a straightness bound (``_straightness``: sums of metres in
# float64, each link shorter than TINY left out)
STRAIGHT_HAIR = 1.0e-6


@wp.func
def swept(params: RodParams, d: int, work: wp.array2d(dtype=BodyWork), x_s: wp.array2d(dtype=V3),
          q_s: wp.array2d(dtype=Q), e: int, row: int, k: int) -> F64:
    """How far body k's capsule may move in the substep: AHEAD times its predicted sweep."""
    b = work[row, k]
    turn = wp.length(rotation_vector(b.q_pred * wp.quat_inverse(q_s[e, k])))
    return F64(AHEAD) * (wp.length(b.x_pred - x_s[e, k]) + turn * params.half[d, k])


@wp.func
def every_surface(params: RodParams, d: int, poses: wp.array3d(dtype=M44), e: int, s_old: int, s_new: int,
                  x_s: wp.array2d(dtype=V3), q_s: wp.array2d(dtype=Q), work: wp.array2d(dtype=BodyWork), query: F64,
                  contacts: wp.array2d(dtype=Contact), count: wp.array2d(dtype=wp.int32), row: int,
                  clear_out: wp.array3d(dtype=F64), at_out: wp.array3d(dtype=F64)):
    """Every body against the meshes and the floor (``surfaces``), within ``query`` plus the body's
    sweep: the substep's contacts."""
    for k in range(params.bodies[d]):
        surfaces(params, d, poses, e, s_old, s_new, k, x_s[e, k], q_s[e, k], query + work[row, k].sweep, contacts,
                 count, row, clear_out, at_out)


@wp.func
def every_floor(params: RodParams, d: int, e: int, x_s: wp.array2d(dtype=V3), q_s: wp.array2d(dtype=Q), query: F64,
                contacts: wp.array2d(dtype=Contact), count: wp.array2d(dtype=wp.int32), row: int,
                clear_out: wp.array3d(dtype=F64), at_out: wp.array3d(dtype=F64)):
    """Every body's clearance to the floor, within ``query`` (a frame's end; no contacts)."""
    for k in range(params.bodies[d]):
        x = x_s[e, k]
        q = q_s[e, k]
        half = params.half[d, k]
        axis = axis_of(q)
        _floor(params, d, e, k, x, q, x - half * axis, x + half * axis, query, 0, contacts, count, row, clear_out,
               at_out)


@wp.func
def surfaces(params: RodParams, d: int, poses: wp.array3d(dtype=M44), e: int, s_old: int, s_new: int, k: int, x: V3,
             q: Q, query: F64, contacts: wp.array2d(dtype=Contact), count: wp.array2d(dtype=wp.int32), row: int,
             clear_out: wp.array3d(dtype=F64), at_out: wp.array3d(dtype=F64)):
    """Body k (at x, q) against every mesh it may touch and the floor: its contacts within
    ``query``, and its clearances."""
    cable = params.cable[d, k]
    r = params.radius[d, k]
    half = params.half[d, k]
    axis = axis_of(q)
    a = x - half * axis
    b = x + half * axis
    meshes = params.mesh.shape[0]
    for j in range(meshes):
        if params.mesh[j] == wp.uint64(0):
            continue
        if not may_touch(params, d, k, j):
            continue
        m_old = mesh_pose(params, poses, e, s_old, j)
        centre = to_frame(m_old, x)
        if past_sphere(params, j, centre, r, half, query):
            continue
        # the first query (from the centre, its reach and half) finds no face past the box (a hair
        # more for the queries' float32 points)
        if box_distance(params.box[j, 0], params.box[j, 1], centre) >= r + query + half + F64(BOX_HAIR):
            continue
        found, t, dist, s, n = segment_mesh(params.mesh[j], m_old, a, b, r + query)
        if found == 0:
            continue
        gap = dist - r
        arc = params.arc[d, k] + t * F64(2.0) * half
        note(clear_out, at_out, e, cable, j, gap, arc)
        if gap < query and gap > -r:  # deeper: the robot drove it through (``squash``)
            m_new = mesh_pose(params, poses, e, s_new, j)
            p = a + t * (b - a)
            moved = from_frame(m_new, s) - from_frame(m_old, s)
            keep(contacts, count, row, k, contact(j, wp.quat_rotate_inv(q, p - x), p, moved, turn(m_new, n), gap,
                                                 r, params.contact_stiff[d, k], arc))
    _floor(params, d, e, k, x, q, a, b, query, 1, contacts, count, row, clear_out, at_out)


@wp.func
def _floor(params: RodParams, d: int, e: int, k: int, x: V3, q: Q, a: V3, b: V3, query: F64, make: int,
           contacts: wp.array2d(dtype=Contact), count: wp.array2d(dtype=wp.int32), row: int,
           clear_out: wp.array3d(dtype=F64), at_out: wp.array3d(dtype=F64)):
    """Both ends of body k's capsule against the floor (a capsule lying on it rests on both)."""
    slot = params.mesh.shape[0] + FLOOR
    r = params.radius[d, k]
    up = V3(F64(0.0), F64(0.0), F64(1.0))
    for end in range(2):
        p = a
        t = F64(0.0)
        if end == 1:
            p = b
            t = F64(1.0)
        gap = p[2] - r - params.floor
        arc = params.arc[d, k] + t * F64(2.0) * params.half[d, k]
        note(clear_out, at_out, e, params.cable[d, k], slot, gap, arc)
        if make != 0 and gap < query and gap > -r:
            keep(contacts, count, row, k, contact(slot, wp.quat_rotate_inv(q, p - x), p, V3(), up, gap, r,
                                                 params.contact_stiff[d, k], arc))


@wp.func
def capsule_pairs(params: RodParams, d: int, work: wp.array2d(dtype=BodyWork), x_s: wp.array2d(dtype=V3),
                  q_s: wp.array2d(dtype=Q), e: int, query: F64, make: int, contacts: wp.array2d(dtype=Contact),
                  count: wp.array2d(dtype=wp.int32), row: int, clear_out: wp.array3d(dtype=F64),
                  at_out: wp.array3d(dtype=F64)):
    """Every two capsules of the cables within ``query`` of each other (with ``make``, plus their
    sweeps), but for neighbours along one cable: a contact for each (each closes half the gap,
    drawn to the pair's mean motion). A pair far apart skips the bodies after it along its cable
    that cannot be near either (``_chain``), and a cable that does not turn back on itself skips,
    at once, its own bodies too far along it to be near (``_straightness``)."""
    bodies = params.bodies[d]
    reach = _chain(params, d, work, x_s, e, make, row)
    straight = F64(0.0)
    for i in range(bodies):
        xi = x_s[e, i]
        ri = params.radius[d, i]
        hi = params.half[d, i]
        ci = params.cable[d, i]
        ai = params.arc[d, i]
        if i == params.cable_first[d, ci]:
            straight = _straightness(params, d, work, x_s, e, row, ci)
        along_i = work[row, i].along
        fold = F64(FOLD) * params.allowed[ci]
        own = hi + ri + query
        if make != 0:
            own = own + work[row, i].sweep
        j = i + 1
        while j < bodies:
            hj = params.half[d, j]
            rj = params.radius[d, j]
            if params.cable[d, j] == ci:
                if _along_only(params.arc[d, j] - ai, hi, hj, ri, rj, fold, make):
                    j += 1
                    continue
                # this body and every later one of the cable lie further than any pair's reach
                if straight * (work[row, j].along - along_i) >= own + reach + F64(STRAIGHT_HAIR):
                    j = params.cable_first[d, ci + 1]
                    continue
            ahead = query
            if make != 0:
                ahead = query + work[row, i].sweep + work[row, j].sweep
            xj = x_s[e, j]
            apart = xj - xi
            near = hi + hj + ri + rj + ahead
            if wp.dot(apart, apart) >= near * near:
                j = _past(params, d, work, row, j, wp.length(apart) - own - reach)
                continue
            _pair(params, d, work, q_s, e, i, j, xi, xj, ahead, make, contacts, count, row, clear_out, at_out)
            j += 1


@wp.func
def _along_only(along: F64, hi: F64, hj: F64, ri: F64, rj: F64, fold: F64, make: int) -> bool:
    """Whether two capsules of one cable, ``along`` apart (start to start), need no test:
    neighbours (a straight cable's would touch), and, for clearances alone (no ``make``), those
    within ``fold`` of each other along the cable, whose gap is never its clearance (``_pair``)."""
    if along - hi + hj < hi + hj + F64(NEIGHBOURS) * (ri + rj):
        return True
    return make == 0 and along + F64(2.0) * hj < fold


@wp.func
def _chain(params: RodParams, d: int, work: wp.array2d(dtype=BodyWork), x_s: wp.array2d(dtype=V3), e: int,
           make: int, row: int) -> F64:
    """Each body's distance along its cable's chain of centres (``BodyWork.along``): no two centres
    of a cable are further apart than the difference of theirs. The most any body adds to a pair's
    reach (its half length, radius and, with ``make``, sweep)."""
    reach = F64(0.0)
    along = F64(0.0)
    for k in range(params.bodies[d]):
        b = work[row, k]
        if k > 0:
            along = along + wp.length(x_s[e, k] - x_s[e, k - 1])
            if params.cable[d, k] != params.cable[d, k - 1]:
                along = F64(0.0)
        b.along = along
        work[row, k] = b
        extra = params.half[d, k] + params.radius[d, k]
        if make != 0:
            extra = extra + b.sweep
        reach = wp.max(reach, extra)
    return reach


@wp.func
def _straightness(params: RodParams, d: int, work: wp.array2d(dtype=BodyWork), x_s: wp.array2d(dtype=V3), e: int,
                  row: int, c: int) -> F64:
    """The least, over cable c's chain of centres, of each link's advance along the line from its
    first centre to its last, per metre along the chain (``_chain``'s ``along``); 0 if none
    advances. Where it is s > 0, two centres of the cable lie at least s times their distance
    along the chain apart (the links' advances sum to the chord's): a hose that does not turn back
    on itself skips, at once, all its pairs too far apart along it to touch."""
    first = params.cable_first[d, c]
    last = params.cable_first[d, c + 1] - 1
    chord = x_s[e, last] - x_s[e, first]
    span = wp.length(chord)
    if span <= F64(TINY):
        return F64(0.0)
    w = chord / span
    least = F64(1.0)
    for k in range(first + 1, last + 1):
        step = work[row, k].along - work[row, k - 1].along
        if step > F64(TINY):
            least = wp.min(least, wp.dot(x_s[e, k] - x_s[e, k - 1], w) / step)
    return wp.max(least, F64(0.0))


@wp.func
def _past(params: RodParams, d: int, work: wp.array2d(dtype=BodyWork), row: int, j: int, excess: F64) -> int:
    """The first body after j that may be near a capsule ``excess`` beyond reach of body j: those
    between along j's cable are no nearer to it than ``excess`` less their distance along from j."""
    bodies = params.bodies[d]
    k = j + 1
    if excess > F64(TINY):
        limit = work[row, j].along + excess - F64(TINY)
        while k < bodies and params.cable[d, k] == params.cable[d, j] and work[row, k].along < limit:
            k += 1
    return k


@wp.func
def _pair(params: RodParams, d: int, work: wp.array2d(dtype=BodyWork), q_s: wp.array2d(dtype=Q), e: int, i: int, j: int,
          xi: V3, xj: V3, query: F64, make: int, contacts: wp.array2d(dtype=Contact), count: wp.array2d(dtype=wp.int32),
          row: int, clear_out: wp.array3d(dtype=F64), at_out: wp.array3d(dtype=F64)):
    qi = q_s[e, i]
    qj = q_s[e, j]
    ai = axis_of(qi) * params.half[d, i]
    aj = axis_of(qj) * params.half[d, j]
    s, t = closest_on_segments(xi - ai, xi + ai, xj - aj, xj + aj)
    pi = xi - ai + s * F64(2.0) * ai
    pj = xj - aj + t * F64(2.0) * aj
    apart = pi - pj
    dist = wp.length(apart)
    gap = dist - params.radius[d, i] - params.radius[d, j]
    arc_i = params.arc[d, i] + s * F64(2.0) * params.half[d, i]
    arc_j = params.arc[d, j] + t * F64(2.0) * params.half[d, j]
    slot = params.mesh.shape[0] + CABLES
    # a hose cannot meet its own segments within pi allowed bend radii along it without folding
    # tighter than allowed: those are contacts, never its clearance to itself
    ci = params.cable[d, i]
    if ci != params.cable[d, j] or wp.abs(arc_j - arc_i) >= F64(FOLD) * params.allowed[ci]:
        note(clear_out, at_out, e, ci, slot, gap, arc_i)
        note(clear_out, at_out, e, params.cable[d, j], slot, gap, arc_j)
    give = wp.min(params.radius[d, i], params.radius[d, j])
    if make == 0 or gap >= query or gap <= F64(-2.0) * give:
        return
    n = apart / wp.max(dist, F64(TINY))
    if dist <= F64(TINY):  # axes that cross: apart across both
        n = wp.normalize(wp.cross(ai, aj))
    wi = work[row, i]
    wj = work[row, j]
    ri = wp.quat_rotate_inv(qi, pi - xi)
    rj = wp.quat_rotate_inv(qj, pj - xj)
    mean = F64(0.5) * (wi.x_pred + wp.quat_rotate(wi.q_pred, ri) - pi + wj.x_pred + wp.quat_rotate(wj.q_pred, rj) - pj)
    half = F64(0.5)
    # each side takes half the gap, and may give its own radius (two cables squash each other)
    keep(contacts, count, row, i, contact(slot, ri, pi, mean, n, half * gap, give, params.contact_stiff[d, i], arc_i))
    keep(contacts, count, row, j, contact(slot, rj, pj, mean, -n, half * gap, give, params.contact_stiff[d, j], arc_j))
