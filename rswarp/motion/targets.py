"""The joints a RAPID move goes to: a jointtarget's axes, or the inverse kinematics of a robtarget
picked as the controller picks it (ConfJ/ConfL on: the solution with the target's confdata; off:
the one nearest where the robot is). A target the robot cannot take is a message for a
``file:line`` error, never a wrong pose: out of reach, only outside the limits, no solution with
its confdata, an axis the robot does not have (a track, a positioner, a coordinated work object)."""

from __future__ import annotations

import numpy as np

from ..kernels.ik import NO_LIMITS, OK, SHOULDER
from ..kinematics.ik import INSIDE, QUADRANT_SLACK, ArmConstants, conf_matches, quadrant_axes, with_conf, wrist_axis
from ..kinematics.ik_numeric import flange64, jacobian, pose_error
from ..rapid import data as rd
from .shortfall import arm_reach

EXTERNAL = ("eax_a", "eax_b", "eax_c", "eax_d", "eax_e", "eax_f")


def extax_values(motion) -> list[tuple[str, float]]:
    """(axis, value) of each external-axis value the motion's targets give (not 9E9)."""
    return [(axis, value) for target in motion.targets for axis, value in zip(EXTERNAL, target.extax)
            if value is not None]


def coordinated(motion, robot: str) -> str | None:
    """Why the motion's work object needs a unit the robot does not have, or None."""
    if motion.wobj is not None and motion.wobj.coordinated:
        unit = motion.wobj.ufmec or "a mechanical unit"
        return (f"the work object is moved by {unit} (ufprog FALSE), an axis '{robot}' does not have "
                "(--external-axes ignore runs it as a fixed frame)")
    return None


def joint_values(mech, target: rd.JointTarget, name: str) -> tuple[np.ndarray | None, str | None]:
    """A jointtarget's robax as the active joints' SI values, or why it cannot be."""
    joints = mech.graph.active
    if len(joints) > len(target.robax):
        return None, f"a jointtarget holds 6 axes; '{mech.name}' has {len(joints)}"
    vals = target.robax[:len(joints)]
    for j, v in zip(joints, vals):
        if v is None:
            return None, f"'{name}' leaves {j.name} unset (9E9)"
    q = np.array([np.radians(v) if j.revolute else v / 1000.0 for v, j in zip(vals, joints)])
    return q, outside(mech, q, name)


def outside(mech, q: np.ndarray, name: str) -> str | None:
    """Why joint values ``q`` are outside the joint limits (in the file's units), or None."""
    from ..rsxml.units import format_number

    lower, upper = mech.bounds()
    for j, v, lo, hi in zip(mech.graph.active, q, lower, upper):
        if not lo - 1e-9 <= v <= hi + 1e-9:
            f = mech.joint_factor(j)
            return (f"'{name}' puts {j.name} at {format_number(v, f)}, outside its limits "
                    f"[{format_number(lo, f)}, {format_number(hi, f)}]")
    return None


def pick(sol, k: int, conf, q_now: np.ndarray, checked: bool, name: str, arm=None, bounds=None,
         speeds=None) -> tuple:
    """The solution of pose ``k`` the controller moves to: with ``checked`` the one with ``conf``
    (nearest ``q_now`` if several), else the one nearest ``q_now``; or why there is none. At or
    near the wrist singularity (q5 = 0, axes 4 and 6 in line) only q4 + q6 counts: they are
    shared out to fit ``conf``'s quadrants where they can, q4 as near where the robot is as they
    let it (``ik.with_conf``)."""
    ok = sol.status[k] == OK
    if not ok.any():
        return None, unreachable(sol, k, name)
    cands = sol.q[k][ok]
    if checked and not sol.numerical:
        q, has = with_conf(cands[None], sol.conf[k][ok][None], np.ones((1, len(cands)), bool), conf, arm, bounds,
                           q_now[3], rounded=True)
        if not has.any():
            return None, f"'{name}' has no solution with confdata {plain(conf)}; {nearest_confs(sol.conf[k][ok], conf)}"
        cands = q[0][has[0]]
    return cands[nearest(cands, q_now, speeds)].copy(), None


def nearest(cands: np.ndarray, q_now: np.ndarray, speeds=None) -> int:
    """The solution the robot reaches soonest from ``q_now``: the least of each axis's travel over
    its top speed (the axes move synchronized, so the slowest decides), then the least squared
    travel; by squared travel alone without speeds. A flip over the top that moves every axis a
    little is not 'nearer' than one axis turning a long way fast."""
    travel = np.abs(cands - q_now)
    if speeds is None or len(cands) < 2:
        return int(np.argmin(np.sum(travel ** 2, axis=1)))
    time = np.max(travel / np.asarray(speeds, float), axis=1)
    best = np.flatnonzero(time <= time.min() * (1 + 1e-9) + 1e-12)
    return int(best[np.argmin(np.sum(travel[best] ** 2, axis=1))])


def plain(values) -> list:
    """Numbers as a message shows them (Python's ints and floats, never NumPy's reprs)."""
    return np.asarray(values).ravel().tolist()


def nearest_confs(confs: np.ndarray, conf, shown: int = 4) -> str:
    """The configurations a pose's solutions have, those nearest ``conf`` first, a few of them."""
    conf = [int(v) for v in conf]
    have = sorted({tuple(int(v) for v in c) for c in confs},
                  key=lambda c: (sum(abs(a - b) for a, b in zip(c, conf)), c))
    text = ", ".join(str(list(c)) for c in have[:shown])
    more = f" and {len(have) - shown} more" if len(have) > shown else ""
    return f"the nearest it has: {text}{more}"


SHOULDER_STEP = 1e-6  # m: how far a wrist centre on axis 1 is moved off it to solve it
SHOULDER_SLACK = 1e-5  # m: a wrist centre this near axis 1 is on it (a robtarget's rounding, not a side)
NEAR_AXIS = SHOULDER_SLACK / QUADRANT_SLACK  # m (1 m): nearer axis 1 than this, moving the wrist centre
# SHOULDER_SLACK turns q1 by more than its quadrant's slack, and a robtarget's rounding turns it more
GRID = np.radians(0.5)  # rad: the steps of q1 tried across what is left to it
BEARINGS = 36  # q1s tried where axis 4 passes axis 6 (the wrist in line): one per 5 degrees of q4


def _side_and_quadrant(conf) -> tuple[float, float, float]:
    """(pi where cfx puts the wrist centre behind axis 1 else 0, cf1's quadrant's ends) (rad)."""
    quarter = 0.5 * np.pi
    return (np.pi if int(conf[3]) & 4 else 0.0), int(conf[0]) * quarter, (int(conf[0]) + 1) * quarter


class _Axis1:
    """Axis 1 and the arm's direction across it, and where a pose's wrist centre is."""

    def __init__(self, arm: ArmConstants):
        self.w, self.h, self.cf, self.p1 = (np.asarray(v, float) for v in (arm.w1, arm.h0, arm.cf, arm.p1))
        self.across = np.cross(self.w, self.h)

    def centre(self, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(wrist centres, their radial vectors from axis 1, their distances from it)."""
        c = poses[:, :3, :3] @ self.cf + poses[:, :3, 3]
        rel = c - self.p1
        radial = rel - (rel @ self.w)[:, None] * self.w
        return c, radial, np.linalg.norm(radial, axis=1)

    def towards(self, angle) -> np.ndarray:
        """(n, 3): the arm's direction across axis 1 where q1 = ``angle`` ((n,))."""
        angle = np.atleast_1d(angle)[:, None]
        return self.h * np.cos(angle) + self.across * np.sin(angle) + self.w * (self.w @ self.h) * (1 - np.cos(angle))

    def azimuth(self, v: np.ndarray) -> np.ndarray:
        """The angle about axis 1 of directions ``v`` (..., 3) from the arm's at q1 = 0."""
        return np.arctan2(v @ self.across, v @ self.h)


def off_the_axis(kin, poses: np.ndarray, sol, q1: float, confs=None) -> None:
    """Poses whose wrist centre is on axis 1, or within SHOULDER_SLACK of it, solved again with
    the centre put ``SHOULDER_STEP`` from the axis where the arm points at ``q1``: any q1 reaches
    such a pose, and which side of the axis rounding left the centre on is no choice of the
    programmer's. With ``confs`` ((N, 4), rows None where unchecked) q1 is kept within the
    target's cf1 quadrant and the side is its cfx's; where no solution there has the target's
    confdata (the wrist takes what q1 leaves to it: at the wrist's singularity, a q1 off the
    target's turns axes 4 and 6 a quarter turn), q1 is sought across that quadrant, nearest
    ``q1``. A wrist centre nearer axis 1 than ``NEAR_AXIS``, where a robtarget's rounding turns
    q1 by more than its slack, is turned about the axis as well, as far as SHOULDER_SLACK lets
    it, where no solution has the target's confdata. The solutions, in ``sol`` (in place), miss
    the pose by SHOULDER_SLACK at most."""
    arm = kin._ik_form()
    if not isinstance(arm, ArmConstants):
        return
    axis = _Axis1(arm)
    _, radial, r = axis.centre(poses)
    on_axis = ~(sol.status == OK).any(axis=1) & (sol.status == SHOULDER).any(axis=1)
    on_axis |= r < SHOULDER_SLACK
    rows = np.flatnonzero(on_axis)
    if len(rows):
        moved = poses[rows].copy()
        for i, row in enumerate(rows):
            angle, conf = q1, None if confs is None else confs[row]
            if conf is not None:
                behind, lo, hi = _side_and_quadrant(conf)
                angle = float(np.clip(q1, lo, hi)) + behind  # an edge is in either
            moved[i, :3, 3] += SHOULDER_STEP * axis.towards(angle)[0] - radial[row]
        again = kin.solutions64(moved)
        sol.q[rows], sol.conf[rows], sol.status[rows] = again.q, again.conf, again.status
    if confs is None:
        return
    checked = [row for row, conf in enumerate(confs) if conf is not None]
    if not checked:
        return
    bounds = kin.mech.bounds()
    want = np.array([[int(v) for v in confs[row]] for row in checked])
    _, has = with_conf(sol.q[checked], sol.conf[checked], sol.status[checked] == OK, want, arm, bounds)
    for row in np.asarray(checked)[~has.any(axis=1)]:
        found, tried = None, None
        if on_axis[row] or r[row] < NEAR_AXIS:
            found, tried = _seek(kin, arm, axis, poses[row], confs[row], q1 if on_axis[row] else None, bounds)
        if found is not None:
            sol.q[row], sol.conf[row], sol.status[row] = found.q[0], found.conf[0], found.status[0]
            continue
        ok = sol.status[row] == OK
        q, c = sol.q[row][ok], sol.conf[row][ok]
        if tried is not None:  # and those of the q1s sought
            more = tried.status == OK
            q, c = np.concatenate([q, tried.q[more]]), np.concatenate([c, tried.conf[more]])
        nearby = _nearby(kin, arm, axis, poses[row], confs[row], q, c, bounds)
        if nearby is not None:  # into a slot that holds no solution (the first where all do)
            slot = int(np.argmax(sol.status[row] != OK))
            sol.q[row, slot], sol.conf[row, slot], sol.status[row, slot] = *nearby, OK


def _seek(kin, arm, axis: _Axis1, pose: np.ndarray, conf, q1: float | None, bounds):
    """The solutions (an ``IKSolutions`` of one pose) of ``pose`` with its wrist centre turned
    about axis 1 to where the arm at q1 has ``conf``, q1 within cf1's quadrant, on cfx's side of
    the axis: on the axis (``q1`` given) anywhere in it, nearest ``q1``; near it, as far as
    SHOULDER_SLACK lets the centre go, nearest where it is; None where no q1 gives ``conf``. And the
    solutions of every q1 tried (None where none was)."""
    behind, lo, hi = _side_and_quadrant(conf)
    centre, radial, r = axis.centre(pose[None])
    foot, r = centre[0] - radial[0], float(r[0])
    if q1 is not None:
        rho, prefer = SHOULDER_STEP, float(np.clip(q1, lo, hi))
    else:
        rho = r
        here = float(axis.azimuth(radial[0])) - behind  # q1 of the arm on cfx's side as the pose is
        here += 2 * np.pi * np.round((0.5 * (lo + hi) - here) / (2 * np.pi))
        reach = 2 * np.arcsin(min(1.0, SHOULDER_SLACK / (2 * r)))
        lo, hi = max(lo, here - reach), min(hi, here + reach)
        if lo > hi:
            return None, None
        prefer = float(np.clip(here, lo, hi))

    def solve(angles: np.ndarray):
        moved = np.repeat(pose[None], len(angles), axis=0)
        moved[:, :3, 3] += foot + rho * axis.towards(angles + behind) - centre[0]
        sol = kin.solutions64(moved)
        ok = sol.status == OK
        _, has = with_conf(sol.q, sol.conf, ok, conf, arm, bounds)
        return sol, has.any(axis=1)

    steps = max(2, int(np.ceil((hi - lo) / GRID)) + 1)
    angles = np.unique(np.concatenate([[prefer, lo, hi], np.linspace(lo, hi, steps)]))
    sol, fits = solve(angles)
    extra = _in_line(kin, arm, axis, sol, angles, conf, lo, hi)  # where the wrist is in line
    if len(extra):
        more, more_fits = solve(extra)
        angles, fits = np.concatenate([angles, extra]), np.concatenate([fits, more_fits])
        sol = _stack(sol, more)
    if not fits.any():
        return None, sol
    best = int(np.argmin(np.where(fits, np.abs(angles - prefer), np.inf)))
    if angles[best] != prefer:  # nearer: between the best and the nearest that does not fit, towards ``prefer``
        between = (angles - prefer) * (angles[best] - prefer) >= 0
        between &= (np.abs(angles - prefer) < abs(angles[best] - prefer)) & ~fits
        if between.any():
            near = angles[between][int(np.argmax(np.abs(angles[between] - prefer)))]
            finer = np.linspace(near, angles[best], 18)[1:-1]
            fine, fine_fits = solve(finer)
            if fine_fits.any():
                k = int(np.argmin(np.where(fine_fits, np.abs(finer - prefer), np.inf)))
                return _row(fine, k), None
    return _row(sol, best), None


def _in_line(kin, arm, axis: _Axis1, sol, angles: np.ndarray, conf, lo: float, hi: float) -> np.ndarray:
    """q1s within [lo, hi] where axis 4 passes axis 6: the wrist in line (q5 = 0) where they meet,
    q4 swinging half a turn as axis 4 passes (one q1 per ``BEARINGS``-th of it). Read off the
    solutions ``sol`` of the arm's branch on ``conf``'s side (cfx's first two bits) at q1s
    ``angles``: q1 turns axis 4 about axis 1, axis 6 stays where the pose puts it."""
    ok = (sol.status == OK) & ((sol.conf[..., 3].astype(np.int64) & 6) == (int(conf[3]) & 6))
    n, s = np.nonzero(ok)
    if not len(n):
        return np.zeros(0)
    n, s = n[:1], s[:1]  # one solution will do: q1 turns the arm's branch about axis 1 as a whole
    q = sol.q[n, s]
    links = kin._arm_links
    zero = kin.fk64(np.zeros((1, q.shape[1])))[0]
    frames = kin.fk64(q)
    sign = 1.0 if np.dot(arm.w4, arm.w6) > 0 else -1.0
    u = frames[:, links[3], :3, :3] @ (zero[links[3], :3, :3].T @ np.asarray(arm.w4))
    a6 = sign * frames[:, links[5], :3, :3] @ (zero[links[5], :3, :3].T @ np.asarray(arm.w6))
    sin_a = np.linalg.norm(np.cross(u, axis.w), axis=1)
    keep = sin_a > 1e-6  # axis 4 along axis 1: q1 turns the wrist about itself, q4 + q6 takes it
    if not keep.any():
        return np.zeros(0)
    turn = axis.azimuth(a6) - axis.azimuth(u)
    turn = (turn + np.pi) % (2 * np.pi) - np.pi
    meet = angles[n] + turn
    gap = np.abs(np.arccos(np.clip(u @ axis.w, -1, 1)) - np.arccos(np.clip(a6 @ axis.w, -1, 1)))
    bearing = np.linspace(0.0, np.pi, BEARINGS + 1)[1:-1]
    offsets = (gap / sin_a)[:, None] / np.tan(bearing)[None]
    out = np.concatenate([meet[keep], (meet[:, None] + offsets)[keep].ravel()])
    mid = 0.5 * (lo + hi)
    out += 2 * np.pi * np.round((mid - out) / (2 * np.pi))
    return np.unique(out[(out >= lo) & (out <= hi)])


STARTS = 4  # damped least-squares starts at most (the solutions nearest the target's quadrants)
CLOSE = 0.05  # m and rad: a start farther than this from the pose once in the quadrants is not tried
STEPS = 60  # damped least-squares steps at most
SPREAD = 8  # starts across q4's quadrant where the wrist is near its singularity
OFF_ZERO = 1e-4  # rad: q5 of those starts
EDGE = 0.5 * QUADRANT_SLACK  # rad: how far past its quadrant's edge (q5: past 0) a joint is let go


def _nearby(kin, arm, axis: _Axis1, pose: np.ndarray, conf, q: np.ndarray, confs: np.ndarray, bounds) -> tuple | None:
    """(joint values, their configuration) with ``conf`` that meet ``pose`` within SHOULDER_SLACK
    (m) and QUADRANT_SLACK (rad), or None. Near a singularity (the arm stretched with the wrist
    in line, a q1 at its quadrant's edge over axis 1 as well) a target's rounding is amplified past
    the slacks, and no exact solution of the rounded pose may have the target's own confdata,
    though the configuration it came from meets the pose within the rounding. Sought by damped
    least squares from the solutions ``q`` (configurations ``confs``) of the arm's branch on
    ``conf``'s side, nearest the target's quadrants once put in them, kept within them (EDGE past
    their edges at most), within q5's sign and on the elbow's side."""
    mine = (confs[:, 3].astype(np.int64) & 6) == (int(conf[3]) & 6)
    if not mine.any():
        return None
    lo, hi = _box(arm, conf, q[mine], bounds)
    found = _starts(kin, arm, pose, conf, q[mine].copy(), lo, hi)
    if found is None:
        return None
    q, err = _descend(kin, pose, *found)
    good = (np.abs(err[:, :3]).max(axis=1) <= SHOULDER_SLACK) & (np.abs(err[:, 3:]).max(axis=1) <= QUADRANT_SLACK)
    if not good.any():
        return None
    best = q[good][int(np.argmin(np.sum(err[good] ** 2, axis=1)))]
    have = kin.confdata(best[None])
    if axis.centre(flange64(kin, best[None]))[2][0] < SHOULDER_SLACK:  # on axis 1: either side of it
        have[0, 3] = (have[0, 3] & 3) | (int(conf[3]) & 4)
    if not conf_matches(best[None], have, conf, quadrant_axes(arm), wrist_axis(arm))[0]:
        return None
    return best, have[0]


def _box(arm, conf, start: np.ndarray, bounds) -> tuple[np.ndarray, np.ndarray]:
    """Per start, the joints' bounds within ``conf``'s quadrants (EDGE past their edges), q5's
    sign, and the elbow's side the start is on."""
    quarter = 0.5 * np.pi
    lower, upper = (np.array(b, float) for b in bounds)
    lo = np.repeat(lower[None], len(start), axis=0)
    hi = np.repeat(upper[None], len(start), axis=0)
    for column, joint in ((0, 0), (1, 3), (2, 5)):
        lo[:, joint] = np.maximum(lo[:, joint], int(conf[column]) * quarter - EDGE)
        hi[:, joint] = np.minimum(hi[:, joint], (int(conf[column]) + 1) * quarter + EDGE)
    if int(conf[3]) & 1:
        hi[:, 4] = np.minimum(hi[:, 4], EDGE)
    else:
        lo[:, 4] = np.maximum(lo[:, 4], -EDGE)
    straight = stretched_q3(arm)  # the elbow's side: between two of these, half a turn apart
    k = np.floor((start[:, 2] - straight) / np.pi)
    lo[:, 2] = np.maximum(lo[:, 2], straight + k * np.pi + INSIDE)
    hi[:, 2] = np.minimum(hi[:, 2], straight + (k + 1) * np.pi - INSIDE)
    return lo, hi


def _starts(kin, arm, pose: np.ndarray, conf, start: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> tuple | None:
    """(starts, their bounds) for the descent: the solutions put in their quadrants (q4 and q6
    shared out as at the singularity where they can be), the STARTS nearest the pose within CLOSE,
    and near the wrist's singularity q4 spread across its quadrant; None where none is near."""
    sign = 1.0 if np.dot(arm.w4, arm.w6) > 0 else -1.0
    low = np.maximum(lo[:, 3] - start[:, 3], start[:, 5] - hi[:, 5] if sign > 0 else lo[:, 5] - start[:, 5])
    high = np.minimum(hi[:, 3] - start[:, 3], start[:, 5] - lo[:, 5] if sign > 0 else hi[:, 5] - start[:, 5])
    d = np.where(low <= high, np.clip(0.0, low, high), np.clip(start[:, 3], lo[:, 3], hi[:, 3]) - start[:, 3])
    start[:, 3] += d
    start[:, 5] -= sign * d
    live = np.all(lo <= hi, axis=1)
    if not live.any():
        return None
    start, lo, hi = np.clip(start[live], lo[live], hi[live]), lo[live], hi[live]
    err = pose_error(np.repeat(pose[None], len(start), axis=0), flange64(kin, start))
    near = np.argsort(np.abs(err).max(axis=1))[:STARTS]
    near = near[np.abs(err[near]).max(axis=1) < CLOSE]
    if not len(near):
        return None
    q, lo, hi = start[near], lo[near], hi[near]
    # near the wrist's singularity q4 + q6 is all a start says: q4 spread across its quadrant, q5
    # off zero on cfx's side (at q5 = 0 no step turns the flange across axes 4 and 5)
    spread = np.abs(q[:, 4]) < CLOSE
    if spread.any():
        base, blo, bhi = q[spread], lo[spread], hi[spread]
        more = np.repeat(base[:, None], SPREAD, axis=1)
        more[..., 3] = blo[:, None, 3] + (bhi - blo)[:, None, 3] * np.linspace(0.0, 1.0, SPREAD + 2)[None, 1:-1]
        more[..., 5] -= sign * (more[..., 3] - base[:, None, 3])
        more[..., 4] = np.where(int(conf[3]) & 1, -1.0, 1.0) * np.maximum(np.abs(base[:, None, 4]), OFF_ZERO)
        q = np.concatenate([q, np.clip(more, blo[:, None], bhi[:, None]).reshape(-1, q.shape[1])])
        lo = np.concatenate([lo, np.repeat(blo, SPREAD, axis=0)])
        hi = np.concatenate([hi, np.repeat(bhi, SPREAD, axis=0)])
    return q, lo, hi


def _descend(kin, pose: np.ndarray, q: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> tuple:
    """(q, pose errors) after damped least-squares steps from each start, kept within its bounds
    (a joint at its bound that the step would push past is held), the damping adapted per row."""
    target = np.repeat(pose[None], len(q), axis=0)
    err = pose_error(target, flange64(kin, q))
    damping = np.full(len(q), 1e-6)
    dof = q.shape[1]
    for _ in range(STEPS):
        cost = np.sum(err ** 2, axis=1)
        jac = jacobian(kin, target, q, 1e-7)
        down = np.einsum("nij,ni->nj", jac, err)  # the way down: a joint at its bound pushed past it is held
        held = ((q <= lo + 1e-12) & (down < 0)) | ((q >= hi - 1e-12) & (down > 0))
        jac = jac * ~held[:, None, :]
        jt = np.swapaxes(jac, 1, 2)
        step = np.linalg.solve(jt @ jac + damping[:, None, None] * np.eye(dof), jt @ err[:, :, None])[:, :, 0]
        tried = np.clip(q + step, lo, hi)
        new = pose_error(target, flange64(kin, tried))
        better = np.sum(new ** 2, axis=1) < cost
        q[better], err[better] = tried[better], new[better]
        damping = np.where(better, np.maximum(damping * 0.1, 1e-10), damping * 10.0)
        if np.all(np.abs(err).max(axis=1) < 1e-12) or np.all(damping > 1e6):
            break
    return q, err


def stretched_q3(arm) -> float:
    """q3 where the arm is stretched: the wrist centre on the line through axes 2 and 3, beyond 3."""
    w3 = arm.s3 * np.asarray(arm.w2)
    a, b = np.asarray(arm.c0) - np.asarray(arm.p3), np.asarray(arm.p3) - np.asarray(arm.p2)
    a, b = a - (a @ w3) * w3, b - (b @ w3) * w3
    return float(np.arctan2(w3 @ np.cross(a, b), a @ b))


def _stack(a, b):
    return type(a)(np.concatenate([a.q, b.q]), np.concatenate([a.conf, b.conf]), np.concatenate([a.status, b.status]),
                   a.numerical)


def _row(sol, k: int):
    return type(sol)(sol.q[k:k + 1], sol.conf[k:k + 1], sol.status[k:k + 1], sol.numerical)


def unreachable(sol, k: int, name: str) -> str:
    status = sol.status[k]
    if (status == NO_LIMITS).any():
        return f"'{name}' is reachable only outside the joint limits"
    if (status == SHOULDER).any():
        return f"'{name}' puts the wrist centre on axis 1 (a shoulder singularity)"
    return f"'{name}' is out of reach"


def margins(kin, q: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    """Per joint configuration (N, dof): the margin to the nearest joint limit (rad or m, negative
    outside) and, for an arm, how much farther the wrist centre could reach from axis 2 (m)."""
    lower, upper = kin.mech.bounds()
    limit = np.min(np.minimum(q - lower, upper - q), axis=1)
    form = kin._ik_form()
    if not isinstance(form, ArmConstants) or not len(q):
        return limit, None
    reach = arm_reach(form)[0]  # the upper arm and the forearm across axis 2, stretched (``shortfall``)
    wrist, _ = kin.wrist_flange64(q)
    link = kin.graph.link_index(kin.graph.active[1].child)
    moved = kin.fk64(q)[:, link] @ np.linalg.inv(kin.fk64(np.zeros((1, q.shape[1])))[0, link])  # from zero
    w2 = moved[:, :3, :3] @ np.asarray(form.w2)  # axis 2 where the joints put it, not where it is at zero
    v = wrist - (moved[:, :3, :3] @ np.asarray(form.p2) + moved[:, :3, 3])
    return limit, reach - np.linalg.norm(v - np.sum(v * w2, axis=1)[:, None] * w2, axis=1)
