"""A frame's least clearance of each cable to each mesh, mesh by mesh and cable by cable. The body
whose centre lies nearest the mesh's box is measured first, and its gap bounds the others: a body
whose box distance already exceeds it is skipped, and the queries of the rest reach no further
than the least gap so far. Every body measured in order, each query reaching the whole distance,
gives the same least clearance and arc, bit for bit: the bound skips only bodies whose gap exceeds
it, and a nearer face is found by a shorter query as by a longer one (``tests/test_rod_culling.py``).
With ``lowering`` (a design sweep, which keeps only each run's least), the least of the frames
before bounds them too, from the nearest body's query on: a frame then measures a clearance only
where it is lower (``tests/test_rod_lowering.py``).
A clearance's queries reach 0.25 m (``REACH``), far past a contact's, so each one taken in full
walks much of a link's mesh."""

import warp as wp

from ..values import fresh
from .contact import BOX_HAIR, box_distance, may_touch, mesh_pose, note, past_sphere, segment_mesh, to_frame
from .joint import axis_of
from .slots import BIG
from .types import F64, M44, V3, Q, RodParams


@wp.func
def mesh_clearances(params: RodParams, d: int, poses: wp.array3d(dtype=M44), e: int, s: int,
                    x_s: wp.array2d(dtype=V3), q_s: wp.array2d(dtype=Q), reach: F64, least: wp.array3d(dtype=F64),
                    clear_out: wp.array3d(dtype=F64), at_out: wp.array3d(dtype=F64)):
    """Every cable's least clearance to every mesh at pose row ``s``, within ``reach`` (and where it
    is under ``least``, the least so far: BIG where there is none)."""
    bodies = params.bodies[d]
    for j in range(params.mesh.shape[0]):
        if params.mesh[j] == wp.uint64(0):
            continue
        m = mesh_pose(params, poses, e, s, j)
        first = int(0)
        while first < bodies:
            last = first + 1
            while last < bodies and params.cable[d, last] == params.cable[d, first]:
                last += 1
            _cable(params, d, m, j, first, last, x_s, q_s, e, reach, least, clear_out, at_out)
            first = last


@wp.func
def _within(params: RodParams, d: int, m: M44, j: int, k: int, x: V3, reach: F64) -> F64:
    """Body k's centre's distance outside mesh j's box, or BIG where it cannot touch the mesh or
    lies beyond its sphere."""
    if not may_touch(params, d, k, j):
        return F64(BIG)
    centre = to_frame(m, x)
    if past_sphere(params, j, centre, params.radius[d, k], params.half[d, k], reach):
        return F64(BIG)
    return box_distance(params.box[j, 0], params.box[j, 1], centre)


@wp.func
def _gap(params: RodParams, d: int, m: M44, j: int, k: int, x: V3, q: Q, query: F64):
    """(found, gap, arc) of body k's capsule to mesh j, its queries reaching ``query`` past its
    axis."""
    half = params.half[d, k]
    axis = axis_of(q)
    found, t, dist, p, n = segment_mesh(params.mesh[j], m, x - half * axis, x + half * axis, query)
    return found, dist - params.radius[d, k], params.arc[d, k] + t * F64(2.0) * half


@wp.func
def _cable(params: RodParams, d: int, m: M44, j: int, first: int, last: int, x_s: wp.array2d(dtype=V3),
           q_s: wp.array2d(dtype=Q), e: int, reach: F64, least: wp.array3d(dtype=F64),
           clear_out: wp.array3d(dtype=F64), at_out: wp.array3d(dtype=F64)):
    """Bodies first..last (one cable) against mesh j: the bound first, then each body in order."""
    cable = params.cable[d, first]
    hint = int(-1)
    nearest = fresh(F64(BIG))
    for k in range(first, last):
        lower = _within(params, d, m, j, k, x_s[e, k], reach)
        if lower < nearest:
            nearest = lower
            hint = k
    if hint < 0:
        return
    # the hint's gap, its queries as long as every body's are in order (none past its box), or
    # only as long as the least so far where its axis lies outside the box
    r = params.radius[d, hint]
    so_far = least[e, cable, j]
    room_h = wp.max(wp.min(r + reach, so_far + r), F64(0.0))
    query_h = r + reach
    if nearest >= params.half[d, hint]:
        query_h = wp.min(query_h, room_h + F64(BOX_HAIR))
    found_h = int(0)
    gap_h = F64(BIG)
    arc_h = F64(0.0)
    if nearest < room_h + params.half[d, hint] + F64(BOX_HAIR):
        found_h, gap_h, arc_h = _gap(params, d, m, j, hint, x_s[e, hint], q_s[e, hint], query_h)
    bound = F64(BIG)
    if found_h != 0:
        bound = gap_h
    for k in range(first, last):
        if k == hint:
            if found_h != 0:
                note(clear_out, at_out, e, cable, j, gap_h, arc_h)
            continue
        box = _within(params, d, m, j, k, x_s[e, k], reach)
        r = params.radius[d, k]
        half = params.half[d, k]
        # a capsule wholly outside the box is outside the mesh, no nearer than its box distance
        # less its half length: one that cannot come under the least gap so far changes nothing
        room = wp.max(wp.min(r + reach, wp.min(clear_out[e, cable, j], wp.min(bound, so_far)) + r), F64(0.0))
        if box >= room + half + F64(BOX_HAIR):
            continue
        query = r + reach
        if box >= half:  # its whole axis outside: no face past the room can lower the clearance
            query = wp.min(query, room + F64(BOX_HAIR))
        found, gap, arc = _gap(params, d, m, j, k, x_s[e, k], q_s[e, k], query)
        if found != 0:
            note(clear_out, at_out, e, cable, j, gap, arc)
