"""The Cosserat rod's types, declared once: the model struct the rod kernel reads (``RodParams``),
the groups of arrays it updates (``RodBodies``, ``RodWear``, ``RodFrame``), the per-body and
per-contact work records it keeps in scratch, and the column layouts of what it writes out (the
slots and statuses: ``slots``). Everything is float64: a stiff rod's tension is a strain of 1e-4
on positions of metres, which float32 cannot hold to a percent."""

import warp as wp

F64 = wp.float64
V3 = wp.vec3d
Q = wp.quatd
M33 = wp.mat33d
M44 = wp.mat44d  # a link's pose
M66 = wp.types.matrix((6, 6), F64)
V6 = wp.types.vector(6, F64)

TINY = 1.0e-12
MAX_CONTACTS = 4  # per body and substep: the deepest are kept
Forces = wp.types.vector(MAX_CONTACTS, wp.float64)  # a body's contacts' normal forces, N

# the columns of a cable's statistics per frame (``stats_out[e, cable, :]``); PINCH_A and PINCH_B
# are the slots that pinch the cable hardest, -1 where nothing does
(TENSION, TENSION_AT, BEND, BEND_AT, TWIST, TWIST_RATE, TORQUE, TORQUE_AT, STRETCH, NORMAL, SLIDING,
 CONTACT_AT, PINCH, PINCH_AT, PINCH_A, PINCH_B) = range(16)
STATS = 16
# the columns of an attachment's load per frame (``load_out[e, attachment, :]``): the greatest force
# and moment over the frame's substeps, then the force and moment vectors at its end (world axes)
FORCE_PEAK, MOMENT_PEAK, FORCE, MOMENT = 0, 1, 2, 5
LOADS = 8


@wp.struct
class RodParams:
    """Every cable of one mechanism as one set of rigid segments (bodies), cable after cable (SI).

    Per body: its half length, mass and inertia (about its cross-section axes, then its own axis),
    radius, cable, arc of its start along its cable, the stiffness of the joint to the next body in
    that body's frame (kappa G A, kappa G A, E A, E I, E I, G J, each over the joint's length; all
    zero where the next body is another cable's), the contact stiffness of its surface, and
    ``touch[k, j]``: body k may touch link j (it is not beside its own attachment to j).
    Per attachment (a control point held by a link), sorted by body: the body, which end (+1: its
    end, -1: its start), the link, the point and frame at the zero position (world), the joint's
    stiffness as above (rotation zero for a ball joint); ``attach_first[k]`` indexes body k's.
    Per cable: its bodies (``cable_first``), its clamped ends for the twist (attachment indices, -1:
    none), consecutive attachments for the stretch (``pair_*``).
    Per mesh a rod may touch (the links', then the environment's, fixed in the world): its
    ``wp.Mesh`` in its zero-position frame (id 0: none), a bounding sphere and box, the link that carries it
    (-1: the world) and its fixed pose.

    Designs: each environment runs one design of the cables (the kernel's ``design`` input): every
    per-body and per-cable-body array has a row per design, padded past its ``bodies``, and so have
    the attachments' places, frames and stiffnesses and the lengths between them. The designs share
    the attachments' order, ends and links, the clamps and the cables' ratings."""

    bodies: wp.array(dtype=wp.int32)  # per design: its bodies (the per-body rows are padded past them)
    half: wp.array2d(dtype=F64)
    mass: wp.array2d(dtype=F64)
    inertia: wp.array2d(dtype=wp.vec2d)
    radius: wp.array2d(dtype=F64)
    cable: wp.array2d(dtype=wp.int32)
    arc: wp.array2d(dtype=F64)
    stiff: wp.array2d(dtype=V6)
    contact_stiff: wp.array2d(dtype=F64)
    touch: wp.array3d(dtype=wp.int32)
    allowed: wp.array(dtype=F64)  # per cable: the least bend radius allowed (bending cycles count below it)

    attach_body: wp.array2d(dtype=wp.int32)
    attach_end: wp.array(dtype=F64)
    attach_link: wp.array(dtype=wp.int32)
    attach_point: wp.array2d(dtype=V3)
    attach_frame: wp.array2d(dtype=Q)
    attach_stiff: wp.array2d(dtype=V6)
    attach_first: wp.array2d(dtype=wp.int32)

    cable_first: wp.array2d(dtype=wp.int32)
    clamp_a: wp.array(dtype=wp.int32)
    clamp_b: wp.array(dtype=wp.int32)
    pair_a: wp.array(dtype=wp.int32)  # attachment indices
    pair_b: wp.array(dtype=wp.int32)
    pair_cable: wp.array(dtype=wp.int32)
    pair_length: wp.array2d(dtype=F64)

    mesh: wp.array(dtype=wp.uint64)
    sphere: wp.array(dtype=wp.vec4d)
    box: wp.array2d(dtype=V3)  # per mesh: its vertices' least and greatest corner in its own frame
    mesh_link: wp.array(dtype=wp.int32)
    mesh_pose: wp.array(dtype=M44)

    gravity: V3
    damping: F64  # 1/s
    friction: F64  # Coulomb's coefficient
    slip: F64  # m/s: below this sliding speed a contact grips (the static regime)
    floor: F64  # z of the floor
    margin: wp.array(dtype=F64)  # per design: the contact query distance beyond the radii, per substep
    reach: F64  # clearance query distance beyond the radius, per frame
    lowering: int  # 1: a frame measures a mesh's clearance only where it lowers ``RodWear.least``
    max_speed: F64  # a point faster than this has blown up


@wp.struct
class RodBodies:
    """Every environment's bodies, read and updated in place by each step: each segment's centre,
    orientation, velocity, angular velocity and last acceleration (envs, bodies), and the
    environment's status (envs,): RUNNING, or why it stopped (``slots``), frozen since."""

    x: wp.array2d(dtype=V3)
    q: wp.array2d(dtype=Q)
    v: wp.array2d(dtype=V3)
    w: wp.array2d(dtype=V3)
    a: wp.array2d(dtype=V3)
    status: wp.array(dtype=wp.int32)


@wp.struct
class RodWear:
    """The wear map, accumulated in place over the steps (envs, bodies): each body's time in
    contact, peak normal force, normal force times sliding distance per slot (envs, bodies,
    slots), curvature (1/m, its tighter joint) at the last substep's end, and bending cycles
    below its cable's allowed radius; and with ``lowering``, each cable's least clearance to each
    slot so far (envs, cables, slots; BIG: none yet, and always without ``lowering``)."""

    time: wp.array2d(dtype=F64)
    peak: wp.array2d(dtype=F64)
    wear: wp.array3d(dtype=F64)
    bend: wp.array2d(dtype=F64)
    cycles: wp.array2d(dtype=wp.int32)
    least: wp.array3d(dtype=F64)


@wp.struct
class RodFrame:
    """A frame's statistics, written whole by each step: per cable its STATS columns (envs,
    cables, STATS), its least clearance to each slot and the arc where (envs, cables, slots), and
    each attachment's LOADS columns (envs, attachments, LOADS)."""

    stats: wp.array3d(dtype=F64)
    clear: wp.array3d(dtype=F64)
    at: wp.array3d(dtype=F64)
    load: wp.array3d(dtype=F64)


@wp.struct
class BodyWork:
    """One body in one substep: the iterate (position, orientation), the predicted pose that
    inertia and gravity draw it to, how far its capsule may sweep (``gather.swept``, once a
    substep: every capsule pair asks it), how far its centre is along its cable's chain of
    centres (``gather.capsule_pairs``), and the angular velocity the step gives it (``commit``)."""

    x: V3
    q: Q
    x_pred: V3
    q_pred: Q
    sweep: F64
    along: F64
    spin: V3


@wp.struct
class Factor:
    """One body's rows of the block-tridiagonal factorization: its pivot block's L_k D_k L_k^T
    (``algebra.ldl``: L_k below the diagonal, 1/D_k on it), D_k^-1 L_k^-1 B_k (B_k its coupling to
    the next body), and D_k^-1 L_k^-1 z_k (z_k its right-hand side carried down the sweep)."""

    lo: M66
    w: M66
    y: V6


@wp.struct
class Contact:
    """One contact of one body for a substep, linearized at its start: the touched slot (a mesh, the
    floor, or the cables), the point on the body (body frame) and where it was (world), the
    displacement it should follow (the surface's over the substep; against another body, the
    mean of the two), the normal (world), the gap this body closes (all of it against a surface,
    half against another body), the depth at which the contact gives way (``squash``), the normal
    force at the start (N: the friction's bound) and the arc of the point along its cable."""

    slot: wp.int32
    r: V3
    p_old: V3
    target: V3
    n: V3
    gap: F64
    give: F64
    force: F64
    arc: F64
