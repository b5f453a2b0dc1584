"""Inverse kinematics of one mechanism: flange poses to joint values, every solution, with ABB's
configuration data (cf1, cf4, cf6, cfx).

An arm with axes 2 and 3 parallel and axes 4, 5 and 6 meeting in a point is solved in closed form
(``kernels/ik.py``), from the RSXML axes alone: ``arm_constants`` finds that shape, and proves the
closed form on the mechanism's own forward kinematics before it is used. Any other mechanism is
solved numerically (``ik_numeric``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..kernels.ik import BRANCHES, CONF, NO_LIMITS, NO_REACH, OK, SAME, SHOULDER, ArmConstants
from ..rsxml.model import Mechanism

PARALLEL = 1e-9  # |w2 x w3| below this: axes 2 and 3 are parallel
MEETS = 1e-7  # m: wrist axes closer than this meet in a point
NO_LIMIT = 1e30  # rad: a joint with no limit (a finite stand-in the device code can fold in)
WHY = {OK: "", NO_REACH: "out of reach", NO_LIMITS: "outside the joint limits",
       SHOULDER: "the wrist centre on axis 1 (a shoulder singularity)", SAME: "the singular wrist's twin"}


@dataclass(frozen=True)
class IKSolutions:
    """Every solution of N flange poses: ``q`` (N, S, dof) joint values (rad, m), ``conf`` (N, S,
    4) ABB configuration data, ``status`` (N, S) 0 for a solution, else why not (``WHY``), and
    whether they came from the numerical solver. For the closed form, S = 8 branches, index
    4·shoulder + 2·elbow + wrist; ``turns`` adds the whole turns of axes 4 and 6."""

    q: np.ndarray
    conf: np.ndarray
    status: np.ndarray
    numerical: bool = False

    @property
    def ok(self) -> np.ndarray:
        return self.status == OK


def _axes(mech: Mechanism):
    """(unit axes, points) of the six active joints if they are revolute and in one serial chain."""
    graph = mech.graph
    joints = graph.active
    if len(joints) != 6 or not all(j.revolute for j in joints) or graph.closing:
        return None
    for a, b in zip(joints, joints[1:]):
        if b.parent != a.child:
            return None
    return np.array([j.axis for j in joints]), np.array([j.point1 for j in joints], float)


def _nearest(p, u, q, v) -> tuple[np.ndarray, float]:
    """The point of line (q, v) nearest line (p, u), and the lines' distance (u, v unit, not
    parallel)."""
    n = np.cross(u, v)
    d = q - p
    t = np.dot(np.cross(d, u), n) / np.dot(n, n)
    point = q + t * v
    return point, abs(np.dot(d, n)) / np.linalg.norm(n)


def arm_constants(mech: Mechanism) -> ArmConstants | None:
    """The closed form's constants when the mechanism is a 6-axis arm of that shape (axes 2 and 3
    parallel, 4, 5 and 6 through one point, a flange); None otherwise."""
    axes = _axes(mech)
    if axes is None or not mech.flanges:
        return None
    w, p = axes
    if np.linalg.norm(np.cross(w[1], w[2])) > PARALLEL:
        return None
    if min(np.linalg.norm(np.cross(w[i], w[j])) for i, j in ((0, 1), (3, 4), (4, 5))) < 1e-6:
        return None
    c0, gap = _nearest(p[3], w[3], p[4], w[4])
    if gap > MEETS or np.linalg.norm(np.cross(c0 - p[5], w[5])) > MEETS:
        return None
    m = mech.flanges[0].pose.matrix()
    cf = m[:3, :3].T @ (c0 - m[:3, 3])
    h = (c0 - p[0]) - np.dot(c0 - p[0], w[0]) * w[0]
    if np.linalg.norm(h) < 1e-9:  # the wrist centre on axis 1 at zero: the arm's direction across it
        h = np.cross(w[1], w[0])
    h0 = h / np.linalg.norm(h)
    side = np.dot(w[1], np.cross(p[2] - p[1], c0 - p[1]))
    lo, hi = (np.clip(np.nan_to_num(b, nan=0.0, posinf=NO_LIMIT, neginf=-NO_LIMIT), -NO_LIMIT, NO_LIMIT)
              for b in mech.bounds())
    t = lambda v: tuple(float(x) for x in np.ravel(v))  # noqa: E731
    return ArmConstants(w1=t(w[0]), p1=t(p[0]), w2=t(w[1]), p2=t(p[1]), s3=float(np.sign(np.dot(w[1], w[2]))),
                        p3=t(p[2]), w4=t(w[3]), w5=t(w[4]), w6=t(w[5]), c0=t(c0), cf=t(cf), rm=t(m[:3, :3]),
                        h0=t(h0), side0=1.0 if side >= 0 else -1.0, lo=t(lo), hi=t(hi))


def quadrant(q) -> np.ndarray:
    """ABB's cf1, cf4, cf6: quadrant k holds [k·90°, (k+1)·90°); negative ones count down from -1."""
    return np.floor(np.asarray(q) / (0.5 * np.pi)).astype(np.int32)


def turns(sol: IKSolutions, lower: np.ndarray, upper: np.ndarray, axes: tuple[int, ...] = (3, 5),
          conf_columns: tuple[int, ...] = (1, 2)) -> IKSolutions:
    """Every solution with the whole turns (-2..2) of ``axes`` (an arm's 4 and 6) that fit their
    limits: S grows 5-fold per axis, the turns that do not fit marked outside the limits, and the
    configuration data's ``conf_columns`` (cf4, cf6) follow the axes' quadrants."""
    q, status, conf = sol.q, sol.status, sol.conf
    for axis, column in zip(axes, conf_columns):
        n, s, dof = q.shape
        base = np.mod(q[..., axis] + np.pi, 2 * np.pi) - np.pi
        q = np.repeat(q[:, :, None], 5, axis=2)
        q[..., axis] = base[:, :, None] + np.arange(-2, 3) * 2.0 * np.pi
        q = q.reshape(n, s * 5, dof)
        status = np.repeat(status, 5, axis=1)
        conf = np.repeat(conf, 5, axis=1)
        conf[..., column] = quadrant(q[..., axis])
    inside = np.all((q >= lower) & (q <= upper), axis=-1)
    status = np.where((status == OK) & ~inside, NO_LIMITS, status).astype(sol.status.dtype)
    return IKSolutions(q, conf, status, sol.numerical)


QUADRANT_SLACK = 1e-5  # rad: a joint this close to a quadrant's edge is in either (rounding, not a choice:
# a robtarget's quaternion of 6 decimals moves the joints by 2e-6)
WRIST_AMPLIFIED = 100.0  # at most this many times QUADRANT_SLACK for axes 4 and 6 near the wrist singularity


def quadrant_axes(form) -> tuple[tuple[int, int], ...]:
    """(configuration column, joint) pairs whose column is the joint's quadrant: an arm's cf1, cf4
    and cf6; a palletizer's (``ik_planar.PlanarArm``: ``first``, ``last``) cf1 and cf6."""
    if isinstance(form, ArmConstants):
        return ((0, 0), (1, 3), (2, 5))
    if hasattr(form, "first") and hasattr(form, "last"):
        return ((0, form.first), (2, form.last))
    return ()


def wrist_axis(form) -> int | None:
    """The joint whose sign is cfx's last bit (an arm's axis 5), or None (a palletizer has none)."""
    return 4 if isinstance(form, ArmConstants) else None


def conf_matches(q: np.ndarray, conf: np.ndarray, want, axes=(), wrist: int | None = None) -> np.ndarray:
    """(..., S) whether solutions ``q`` (..., S, dof) of configurations ``conf`` (..., S, 4) have
    ``want`` ((4,) or (..., 4)). A joint within QUADRANT_SLACK of its quadrant's edge counts in
    either quadrant: a pose read at q1 = 0 (CRobT) solves to q1 = -1e-12 as often as to 0; so
    does axis 5 (``wrist``) within it of 0 for cfx's last bit, its sign. An arm's axes 4 and 6
    have it 1 / |sin q5| times over (up to 100)."""
    want = np.asarray(want, np.int64)[..., None, :]
    same = conf == want
    quarter = 0.5 * np.pi
    # near the wrist's singularity axes 4 and 6 take a target's rounding 1 / |sin q5| times over
    amplified = 1.0 if wrist is None else 1.0 / np.maximum(np.abs(np.sin(q[..., wrist])), 1.0 / WRIST_AMPLIFIED)
    for column, axis in axes:
        x = q[..., axis] / quarter
        edge = np.round(x)
        near = np.abs(x - edge) * quarter < QUADRANT_SLACK * (1.0 if axis == 0 else amplified)
        w = want[..., column]
        same[..., column] |= near & ((w == edge) | (w == edge - 1))
    if wrist is not None:
        same[..., 3] |= (np.abs(q[..., wrist]) < QUADRANT_SLACK) & ((conf[..., 3] | 1) == (want[..., 3] | 1))
    return same.all(axis=-1)


WRIST_SINGULAR = 1e-5  # rad: |q5| below this, axes 4 and 6 are in line (a quaternion's 6 decimals reach 2e-6)
INSIDE = 1e-6  # rad: how far inside its quadrant a shared-out q4 or q6 is put (float32 keeps it there)


def share_out(q: np.ndarray, conf: np.ndarray, want, arm, bounds=None, q4=0.0) -> tuple[np.ndarray, np.ndarray]:
    """(q (..., S, dof), fits (..., S)): solutions ``q`` (configurations ``conf`` (..., S, 4)) at or
    near the wrist singularity with q4 and q6 shared out so that cf4 and cf6 are ``want``'s
    ((4,) or (..., 4)). q4 + d and q6 - d (q6 + d where axes 4 and 6 point opposite ways) turn
    the flange by |d| |sin q5| at most: |d| is kept within QUADRANT_SLACK / |sin q5| (the flange
    turned by a target's rounding at most), and is free where |q5| < WRIST_SINGULAR, q5 then put
    at 0 (axes 4 and 6 in line, only q4 + q6 counts). q4 is kept as near ``q4`` (where the robot
    is) as the quadrants let it, inside them where it can be, else as little past their edges as
    it can be (within the slack ``conf_matches`` gives them). ``fits``: cf1 and cfx are
    ``want``'s as well (cfx's last bit, q5's sign, either at the singularity), the result within
    ``bounds`` ((lower, upper))."""
    fits = np.zeros(q.shape[:-1], bool)
    if not isinstance(arm, ArmConstants) or not q.size:
        return q, fits
    along = float(np.dot(arm.w4, arm.w6))
    if abs(abs(along) - 1.0) > 1e-9:
        return q, fits
    sign = 1.0 if along > 0 else -1.0
    want = np.asarray(want, np.int64)[..., None, :]
    have = np.asarray(conf, np.int64)
    quarter = 0.5 * np.pi
    q5 = q[..., 4]
    singular = np.abs(q5) < WRIST_SINGULAR
    s5 = np.abs(np.sin(q5))
    with np.errstate(divide="ignore"):
        reach = np.where(singular, np.inf, QUADRANT_SLACK / s5)  # how far d may go
        amplified = QUADRANT_SLACK * np.minimum(1.0 / s5, WRIST_AMPLIFIED)  # as ``conf_matches`` has it

    def window(slack):  # d's range: q4 and q6 within their quadrants, ``slack`` outside them
        a4, b4 = want[..., 1] * quarter - slack, (want[..., 1] + 1) * quarter + slack
        a6, b6 = want[..., 2] * quarter - slack, (want[..., 2] + 1) * quarter + slack
        lo = np.maximum(a4 - q[..., 3], q[..., 5] - b6 if sign > 0 else a6 - q[..., 5])
        hi = np.minimum(b4 - q[..., 3], q[..., 5] - a6 if sign > 0 else b6 - q[..., 5])
        return np.maximum(lo, -reach), np.minimum(hi, reach)

    lo, hi = window(-INSIDE)
    inside = lo <= hi
    lo_edge, hi_edge = window(amplified)
    # inside both quadrants where it can, q4 nearest ``q4``; else across both edges alike
    d = np.where(inside, np.clip(np.asarray(q4, float)[..., None] - q[..., 3], lo, hi),
                 np.clip(0.5 * (lo + hi), lo_edge, hi_edge))
    lo, hi = np.where(inside, lo, lo_edge), np.where(inside, hi, hi_edge)
    out = q.copy()
    out[..., 3] += d
    out[..., 5] -= sign * d
    out[..., 4] = np.where(singular, 0.0, q5)
    a1, b1 = want[..., 0] * quarter - QUADRANT_SLACK, (want[..., 0] + 1) * quarter + QUADRANT_SLACK
    fits = (lo <= hi) & (a1 <= q[..., 0]) & (q[..., 0] <= b1) & ((have[..., 3] | 1) == (want[..., 3] | 1))
    fits &= singular | (have[..., 3] == want[..., 3])
    if bounds is not None:
        fits &= np.all((out >= bounds[0]) & (out <= bounds[1]), axis=-1)
    return out, fits


def with_conf(q: np.ndarray, conf: np.ndarray, ok: np.ndarray, want, arm, bounds=None, q4=0.0,
              rounded: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """(q (N, S, dof), has (N, S)): which of N poses' solutions ``q`` (configurations ``conf``
    (N, S, 4), ``ok`` (N, S) those within reach and limits) have the configuration ``want`` ((4,)
    or (N, 4)), as ``conf_matches`` says or once q4 and q6 are shared out (``share_out``, q4
    nearest ``q4``, a number or (N,)), where no solution has ``want`` as it is. With ``rounded``
    (a robtarget's pose, rounded to its digits) the shared-out one is taken at the wrist
    singularity in any case: the closed form's split of q4 and q6 is the rounding's there."""
    want = np.broadcast_to(np.asarray(want, np.int64), (q.shape[0], CONF))
    has = ok & conf_matches(q, conf, want, quadrant_axes(arm), wrist_axis(arm))
    if not isinstance(arm, ArmConstants):
        return q, has
    # only a solution near the singularity is shared out further than conf_matches' slack
    rows = np.flatnonzero(np.any(ok & (np.abs(np.sin(q[..., 4])) < 1.0 / WRIST_AMPLIFIED), axis=1))
    if not len(rows):
        return q, has
    qr, hr = q[rows], has[rows]
    shared, fits = share_out(qr, conf[rows], want[rows], arm, bounds,
                             np.broadcast_to(np.asarray(q4, float), q.shape[:1])[rows])
    fits &= ok[rows]
    use = fits & (((np.abs(qr[..., 4]) < WRIST_SINGULAR) & rounded) | ~hr.any(axis=1, keepdims=True))
    q, has = q.copy(), has.copy()
    q[rows] = np.where(use[..., None], shared, qr)
    has[rows] = hr | use
    return q, has


def pick(sol: IKSolutions, conf, axes=(), wrist: int | None = None, arm=None,
         bounds=None) -> tuple[np.ndarray, np.ndarray]:
    """(q (N, dof), found (N,)): for each pose, the solution with configuration ``conf`` ((4,) or
    (N, 4)); NaN and False where none has it. ``axes``: ``quadrant_axes`` of the solver. With the
    arm's constants (``arm``) and joint limits (``bounds``), a pose at or near the wrist
    singularity that no solution has ``conf`` for as it is has q4 and q6 shared out to fit it
    (``with_conf``), q4 as near 0 as they let it."""
    want = np.broadcast_to(np.asarray(conf, np.int32), (sol.q.shape[0], CONF))
    if isinstance(arm, ArmConstants):
        q, match = with_conf(sol.q, sol.conf, sol.ok, want, arm, bounds)
    else:
        q, match = sol.q, sol.ok & conf_matches(sol.q, sol.conf, want, axes, wrist)
    found = match.any(axis=1)
    first = np.argmax(match, axis=1)
    q = q[np.arange(len(first)), first].copy()
    q[~found] = np.nan
    return q, found


def closed_form(launcher, arm: ArmConstants, poses: np.ndarray, dtype, kernel=None,
                out: IKSolutions | None = None) -> IKSolutions:
    """The closed form's eight branches of ``poses`` on the launcher's device (``kernel``: the
    arm's, when the caller keeps it; else looked up by the arm's content), into ``out``'s arrays
    when given (checked: shaped and typed as the answer's, C-contiguous)."""
    if kernel is None:
        kernel = ik_kernel(arm, dtype)
    n = len(poses)
    # small codes for conf and status: a quarter of the memory traffic
    shapes = (((n, BRANCHES, 6), np.dtype(dtype)), ((n, BRANCHES, CONF), np.dtype(np.int8)),
              ((n, BRANCHES), np.dtype(np.int8)))
    if out is None:
        out = IKSolutions(*(np.empty(shape, t) for shape, t in shapes))
    else:
        for a, (shape, t), name in zip((out.q, out.conf, out.status), shapes, ("q", "conf", "status")):
            if type(a) is not np.ndarray or a.shape != shape or a.dtype != t or not a.flags.c_contiguous:
                raise ValueError(f"out.{name} must be a C-contiguous {t.name} array of shape {shape}")
    launcher.launch(kernel, n, inputs=[poses], outputs=[out.q, out.conf, out.status], overwrites=True)
    return out


def ik_kernel(arm: ArmConstants, dtype):
    """The arm's inverse kinematics kernel in one precision."""
    from ..kernels.ik import arm_ik_kernel
    from ..launch import init_warp

    wp = init_warp()
    return arm_ik_kernel(arm, wp.float32 if dtype == np.float32 else wp.float64)


def confdata(arm: ArmConstants, q: np.ndarray, poses: np.ndarray, links: tuple[int, ...]) -> np.ndarray:
    """(N, 4) cf1, cf4, cf6, cfx of joint values ``q`` (float64), from their link poses ``poses``
    (N, links, 4, 4) and the links the six joints move (``links``)."""
    def at(link: int, point) -> np.ndarray:
        m = poses[:, link]
        return m[:, :3, :3] @ np.asarray(point) + m[:, :3, 3]

    wc = at(links[5], arm.c0)
    r1 = poses[:, links[0], :3, :3]
    behind1 = np.einsum("ni,ni->n", wc - np.asarray(arm.p1), r1 @ np.asarray(arm.h0)) < 0
    p2, p3 = at(links[1], arm.p2), at(links[2], arm.p3)
    side = np.einsum("ni,ni->n", r1 @ np.asarray(arm.w2), np.cross(p3 - p2, wc - p2)) * arm.side0
    cfx = 4 * behind1 + 2 * (side < 0) + (q[:, 4] < 0)
    return np.stack([quadrant(q[:, 0]), quadrant(q[:, 3]), quadrant(q[:, 5]), cfx.astype(np.int32)], axis=1)
