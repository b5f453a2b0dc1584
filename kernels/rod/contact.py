"""What a rod's segments meet, as device code: each segment is a capsule (its axis and the cable's
radius) against the link meshes (``wp.Mesh`` queries in each link's zero-position frame), the
environment's meshes, the floor, and every other capsule of the mechanism's cables, its own
included (self-contact). A contact is found at the start of a substep and linearized there; in
the implicit step it is a stiff spring along its normal (the hose's own squash stiffness) and
Coulomb friction with a static regime (below a slip speed the contact grips), the friction
bounded by mu times the normal force at the substep's start. A contact pressed as deep as the
cable's radius gives way (``squash``): only a robot driving the cable through something gets it
there, and the push stays bounded. Each contact and clearance names its slot (``slots``: the
meshes, then the floor, then the cables)."""

import warp as wp

from .algebra import add_outer, pair
from .slots import BIG
from .types import F64, M44, M66, MAX_CONTACTS, TINY, V3, V6, Contact, Q, RodParams

BOX_HAIR = 1e-5  # m: what a bound on a mesh's distance allows for the mesh queries' float32 points


@wp.func
def to_frame(m: M44, p: V3) -> V3:
    """``p`` in the frame of pose ``m``."""
    d = p - V3(m[0, 3], m[1, 3], m[2, 3])
    return V3(m[0, 0] * d[0] + m[1, 0] * d[1] + m[2, 0] * d[2],
              m[0, 1] * d[0] + m[1, 1] * d[1] + m[2, 1] * d[2],
              m[0, 2] * d[0] + m[1, 2] * d[1] + m[2, 2] * d[2])


@wp.func
def from_frame(m: M44, p: V3) -> V3:
    return V3(m[0, 0] * p[0] + m[0, 1] * p[1] + m[0, 2] * p[2] + m[0, 3],
              m[1, 0] * p[0] + m[1, 1] * p[1] + m[1, 2] * p[2] + m[1, 3],
              m[2, 0] * p[0] + m[2, 1] * p[1] + m[2, 2] * p[2] + m[2, 3])


@wp.func
def turn(m: M44, d: V3) -> V3:
    return V3(m[0, 0] * d[0] + m[0, 1] * d[1] + m[0, 2] * d[2],
              m[1, 0] * d[0] + m[1, 1] * d[1] + m[1, 2] * d[2],
              m[2, 0] * d[0] + m[2, 1] * d[1] + m[2, 2] * d[2])


@wp.func
def mesh_pose(params: RodParams, poses: wp.array3d(dtype=M44), e: int, s: int, j: int) -> M44:
    """Mesh j's pose at pose row ``s``: its link's, or its fixed place in the world."""
    link = params.mesh_link[j]
    if link >= 0:
        return poses[e, s, link]
    return params.mesh_pose[j]


@wp.func
def may_touch(params: RodParams, d: int, k: int, j: int) -> bool:
    """Whether body k may touch mesh j: not a link's beside the body's own attachment to it."""
    link = params.mesh_link[j]
    if link >= 0:
        if params.touch[d, k, link] == 0:
            return False
    return True


@wp.func
def past_sphere(params: RodParams, j: int, centre: V3, r: F64, half: F64, query: F64) -> bool:
    """Whether a capsule (centre in mesh j's frame, radius, half length) lies beyond ``query`` of
    mesh j's bounding sphere."""
    sp = params.sphere[j]
    return wp.length(centre - V3(sp[0], sp[1], sp[2])) >= sp[3] + r + half + query


@wp.func
def box_distance(lo: V3, hi: V3, p: V3) -> F64:
    """How far ``p`` lies outside the box ``lo``-``hi`` (0 inside)."""
    return wp.length(wp.max(wp.max(lo - p, p - hi), V3()))


@wp.func
def segment_mesh(mesh: wp.uint64, m: M44, a: V3, b: V3, reach: F64):
    """The point of segment a-b nearest the mesh (posed by ``m``) and the surface there, by two
    alternating projections (segment centre to surface, surface back to the segment, to the
    surface again): (found, t along a-b, signed distance from the axis, surface point and outward
    normal in the mesh's frame). Not found when no face is within ``reach`` of the axis."""
    al = to_frame(m, a)
    bl = to_frame(m, b)
    ab = bl - al
    half = F64(0.5) * wp.length(ab)
    centre = F64(0.5) * (al + bl)
    q = wp.mesh_query_point_sign_normal(mesh, wp.vec3f(centre), wp.float32(reach + half))
    if not q.result:
        return int(0), F64(0.0), F64(BIG), V3(), V3()
    s = V3(wp.mesh_eval_position(mesh, q.face, q.u, q.v))
    t = F64(0.5)
    if half > F64(TINY):
        t = wp.clamp(wp.dot(s - al, ab) / wp.dot(ab, ab), F64(0.0), F64(1.0))
    p = al + t * ab
    if wp.length(s - centre) - wp.length(p - centre) > reach + F64(BOX_HAIR):
        # the surface is at least this far from p (the centre's distance less p's from it): the
        # second query would find nothing
        return int(0), t, F64(BIG), V3(), V3()
    q = wp.mesh_query_point_sign_normal(mesh, wp.vec3f(p), wp.float32(reach))
    if not q.result:
        return int(0), t, F64(BIG), V3(), V3()
    s = V3(wp.mesh_eval_position(mesh, q.face, q.u, q.v))
    d = p - s
    dist = wp.length(d)
    sign = q.sign
    if sign < 0.0:
        # the nearest face's side is wrong past an edge of an open mesh (a CAD part that is not
        # closed): inside only where the winding number says so too
        sign = wp.mesh_query_point_sign_winding_number(mesh, wp.vec3f(p), wp.float32(reach)).sign
    n = V3(wp.mesh_eval_face_normal(mesh, q.face))
    if dist > F64(TINY):
        n = d / dist
        if sign < 0.0:
            n = -n
    if sign < 0.0:
        dist = -dist
    return int(1), t, dist, s, n


@wp.func
def closest_on_segments(p1: V3, q1: V3, p2: V3, q2: V3):
    """(s, t): the closest points p1 + s (q1 - p1) and p2 + t (q2 - p2) of two segments (Ericson,
    Real-Time Collision Detection 5.1.9)."""
    d1 = q1 - p1
    d2 = q2 - p2
    r = p1 - p2
    a = wp.dot(d1, d1)
    e = wp.dot(d2, d2)
    f = wp.dot(d2, r)
    c = wp.dot(d1, r)
    b = wp.dot(d1, d2)
    den = a * e - b * b
    s = F64(0.0)
    if den > F64(TINY) * a * e:
        s = wp.clamp((b * f - c * e) / den, F64(0.0), F64(1.0))
    t = (b * s + f) / wp.max(e, F64(TINY))
    if t < F64(0.0):
        t = F64(0.0)
        s = wp.clamp(-c / wp.max(a, F64(TINY)), F64(0.0), F64(1.0))
    elif t > F64(1.0):
        t = F64(1.0)
        s = wp.clamp((b - c) / wp.max(a, F64(TINY)), F64(0.0), F64(1.0))
    return s, t


@wp.func
def note(clear_out: wp.array3d(dtype=F64), at_out: wp.array3d(dtype=F64), e: int, cable: int, slot: int,
         gap: F64, arc: F64):
    """Lower the least clearance of one cable to one slot, noting the arc where."""
    if gap < clear_out[e, cable, slot]:
        clear_out[e, cable, slot] = gap
        at_out[e, cable, slot] = arc


@wp.func
def keep(contacts: wp.array2d(dtype=Contact), count: wp.array2d(dtype=wp.int32), row: int, k: int, c: Contact):
    """Body k's contacts take ``c``: added while there is room, else in place of the shallowest
    when deeper."""
    n = count[row, k]
    base = k * MAX_CONTACTS
    if n < MAX_CONTACTS:
        contacts[row, base + n] = c
        count[row, k] = n + 1
        return
    worst = int(0)
    for i in range(1, MAX_CONTACTS):
        if contacts[row, base + i].gap > contacts[row, base + worst].gap:
            worst = i
    if c.gap < contacts[row, base + worst].gap:
        contacts[row, base + worst] = c


@wp.func
def squash(depth: F64, give: F64, stiffness: F64):
    """(normal force, its slope) of a contact pressed ``depth`` in: a spring to half the depth at
    which it gives way, then easing to nothing there, where the robot has driven the cable through
    (a trajectory through the floor), so the push it meets stays bounded."""
    if depth <= F64(0.0) or depth >= give:
        return F64(0.0), F64(0.0)
    if depth < F64(0.5) * give:
        return stiffness * depth, stiffness
    return stiffness * (give - depth), F64(0.0)


@wp.func
def contact(slot: int, r: V3, p_old: V3, target: V3, n: V3, gap: F64, give: F64, stiffness: F64, arc: F64) -> Contact:
    c = Contact()
    c.slot = slot
    c.r = r
    c.p_old = p_old
    c.target = target
    c.n = n
    c.gap = gap
    c.give = give
    force, slope = squash(-gap, give, stiffness)
    c.force = force
    c.arc = arc
    return c


@wp.func
def tangents(n: V3):
    """Two unit vectors across ``n``, and across each other."""
    helper = V3(F64(1.0), F64(0.0), F64(0.0))
    if wp.abs(n[0]) > F64(0.8):
        helper = V3(F64(0.0), F64(1.0), F64(0.0))
    t1 = wp.normalize(wp.cross(n, helper))
    return t1, wp.cross(n, t1)


@wp.func
def contact_terms(c: Contact, x: V3, q: Q, stiffness: F64, friction: F64, slip: F64):
    """(Hessian, gradient) of one contact at the iterate (x, q): the normal spring where the gap is
    closed, and friction as a lagged Coulomb law: a damper of mu F / max(|slip|, ``slip``) across
    the normal, so sliding is resisted by mu F and slower motion is held (the static regime)."""
    rw = wp.quat_rotate(q, c.r)
    disp = x + rw - c.p_old - c.target
    force, slope = squash(-(c.gap + wp.dot(c.n, disp)), c.give, stiffness)
    h = M66()
    g = V6()
    if force > F64(0.0):
        a = pair(c.n, wp.cross(rw, c.n))
        h = add_outer(h, a, slope)
        g = -force * a
    if c.force > F64(0.0) and friction > F64(0.0):
        ut = disp - wp.dot(disp, c.n) * c.n
        grip = friction * c.force / wp.max(wp.length(ut), slip)
        t1, t2 = tangents(c.n)
        h = add_outer(h, pair(t1, wp.cross(rw, t1)), grip)
        h = add_outer(h, pair(t2, wp.cross(rw, t2)), grip)
        g = g + grip * pair(ut, wp.cross(rw, ut))
    return h, g


@wp.func
def contact_outcome(c: Contact, x: V3, q: Q, stiffness: F64):
    """(normal force, sliding distance, crushed) of a contact at the step's end: the spring's push,
    how far the body's point moved across the surface over the substep, and whether it is pressed
    in past half the depth at which it gives way."""
    rw = wp.quat_rotate(q, c.r)
    disp = x + rw - c.p_old - c.target
    force, slope = squash(-(c.gap + wp.dot(c.n, disp)), c.give, stiffness)
    ut = disp - wp.dot(disp, c.n) * c.n
    return force, wp.length(ut), -(c.gap + wp.dot(c.n, disp)) > F64(0.5) * c.give
