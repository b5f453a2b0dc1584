"""The joints a RAPID move goes to: a jointtarget's axes, or the inverse kinematics of a robtarget
picked as the controller picks it (ConfJ/ConfL on: the solution with the target's confdata; off:
the one nearest where the robot is). A target the robot cannot take is a message for a
``file:line`` error, never a wrong pose: out of reach, only outside the limits, no solution with
its confdata, an axis the robot does not have (a track, a positioner, a coordinated work object)."""

from __future__ import annotations

import numpy as np

from ..kernels.ik import NO_LIMITS, OK, SHOULDER
from ..rapid import data as rd
from .ik import QUADRANT_SLACK, WRIST_AMPLIFIED, ArmConstants, conf_matches, quadrant_axes, wrist_axis
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


def external_axes(motion, robot: str) -> str | None:
    """Why ``motion`` needs axes the robot does not have, or None."""
    for name, target in zip(motion.names, motion.targets):
        for axis, value in zip(EXTERNAL, target.extax):
            if value is not None:
                return (f"'{name}' puts the external axis {axis} at {value:g}: '{robot}' has no external axes "
                        "(--external-axes ignore runs the robot's own axes)")
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


def pick(sol, k: int, conf, q_now: np.ndarray, checked: bool, name: str, arm=None, bounds=None) -> tuple:
    """The solution of pose ``k`` the controller moves to: with ``checked`` the one with ``conf``
    (nearest ``q_now`` if several), else the one nearest ``q_now``; or why there is none. At the
    wrist singularity (q5 = 0, axes 4 and 6 in line) only q4 + q6 counts: they are shared out to
    fit ``conf``'s quadrants where they can."""
    ok = sol.status[k] == OK
    if not ok.any():
        return None, unreachable(sol, k, name)
    cands = sol.q[k]
    if checked and not sol.numerical:
        match = ok & conf_matches(cands, sol.conf[k], conf, quadrant_axes(arm), wrist_axis(arm))
        if not match.any():
            fitted = wrist_fit(arm, cands[ok], sol.conf[k][ok], conf, bounds, q_now)
            if fitted is not None:
                return fitted, None
            return None, f"'{name}' has no solution with confdata {list(conf)}; {nearest_confs(sol.conf[k][ok], conf)}"
        ok = match
    dist = np.where(ok, np.sum((cands - q_now) ** 2, axis=1), np.inf)
    return cands[int(np.argmin(dist))].copy(), None


def nearest_confs(confs: np.ndarray, conf, shown: int = 4) -> str:
    """The configurations a pose's solutions have, those nearest ``conf`` first, a few of them."""
    have = sorted({tuple(int(v) for v in c) for c in confs},
                  key=lambda c: (sum(abs(a - b) for a, b in zip(c, conf)), c))
    text = ", ".join(str(list(c)) for c in have[:shown])
    more = f" and {len(have) - shown} more" if len(have) > shown else ""
    return f"the nearest it has: {text}{more}"


WRIST_SINGULAR = 1e-5  # rad: |q5| below this, axes 4 and 6 are in line (a quaternion's 6 decimals reach 2e-6)


def wrist_fit(arm, cands: np.ndarray, confs: np.ndarray, conf, bounds=None, q_now=None) -> np.ndarray | None:
    """A wrist-singular solution (|q5| < WRIST_SINGULAR) with q4 and q6 shared out so cf4 and cf6
    are ``conf``'s: q4 + d and q6 - d (q6 + d where the axes point opposite ways) leave the flange
    where it is while axes 4 and 6 are in line. q4 stays as near where the robot is (``q_now``)
    as the quadrants let it: the split is rounding, the robot's own q4 is not."""
    if not isinstance(arm, ArmConstants):
        return None
    along = float(np.dot(arm.w4, arm.w6))
    if abs(abs(along) - 1.0) > 1e-9:
        return None
    sign = 1.0 if along > 0 else -1.0
    quarter = 0.5 * np.pi
    # a joint this near a quadrant's edge is in either; axes 4 and 6 at the wrist singularity take a
    # target's rounding amplified, as ``conf_matches`` has them (near the shoulder's too, q1's error)
    slack, wide = QUADRANT_SLACK, QUADRANT_SLACK * WRIST_AMPLIFIED
    a4, b4 = conf[1] * quarter - wide, (conf[1] + 1) * quarter + wide
    a6, b6 = conf[2] * quarter - wide, (conf[2] + 1) * quarter + wide
    a1, b1 = conf[0] * quarter - slack, (conf[0] + 1) * quarter + slack
    for q, c in zip(cands, confs):
        if abs(q[4]) >= WRIST_SINGULAR or not a1 <= q[0] <= b1 or (int(c[3]) | 1) != (int(conf[3]) | 1):
            continue
        lo = max(a4 - q[3], q[5] - b6 if sign > 0 else a6 - q[5])
        hi = min(b4 - q[3], q[5] - a6 if sign > 0 else b6 - q[5])
        if lo < hi - 1e-9:
            d = 0.5 * (lo + hi) if q_now is None else float(np.clip(q_now[3] - q[3], lo + 1e-9, hi - 1e-9))
            out = q.copy()
            out[3], out[4], out[5] = q[3] + d, 0.0, q[5] - sign * d
            if bounds is None or (np.all(out >= bounds[0]) and np.all(out <= bounds[1])):
                return out
    return None


SHOULDER_STEP = 1e-6  # m: how far a wrist centre on axis 1 is moved off it to solve it


SHOULDER_SLACK = 1e-5  # m: a wrist centre this near axis 1 is on it (a robtarget's rounding, not a side)


def off_the_axis(kin, poses: np.ndarray, sol, q1: float, confs=None) -> None:
    """Poses whose wrist centre is on axis 1, or within SHOULDER_SLACK of it, solved again with
    the centre put ``SHOULDER_STEP`` from the axis where the arm points at ``q1``: any q1 reaches
    such a pose, and which side of the axis rounding left the centre on is no choice of the
    programmer's. With ``confs`` ((N, 4), rows None where unchecked) q1 is kept within the
    target's cf1 quadrant and the side is its cfx's. The solutions, in ``sol`` (in place), miss
    the pose by SHOULDER_SLACK at most."""
    arm = kin._ik_form()
    if not isinstance(arm, ArmConstants):
        return
    w, h, cf = (np.asarray(v, float) for v in (arm.w1, arm.h0, arm.cf))
    rel = poses[:, :3, :3] @ cf + poses[:, :3, 3] - np.asarray(arm.p1)
    radial = rel - (rel @ w)[:, None] * w
    on_axis = ~(sol.status == OK).any(axis=1) & (sol.status == SHOULDER).any(axis=1)
    rows = np.flatnonzero(on_axis | (np.linalg.norm(radial, axis=1) < SHOULDER_SLACK))
    if not len(rows):
        return
    moved = poses[rows].copy()
    for i, row in enumerate(rows):
        angle, conf = q1, None if confs is None else confs[row]
        if conf is not None:
            quarter = 0.5 * np.pi
            angle = float(np.clip(q1, conf[0] * quarter, (conf[0] + 1) * quarter))  # an edge is in either
            angle += np.pi if int(conf[3]) & 4 else 0.0
        towards = h * np.cos(angle) + np.cross(w, h) * np.sin(angle) + w * np.dot(w, h) * (1 - np.cos(angle))
        moved[i, :3, 3] += SHOULDER_STEP * towards - radial[row]
    again = kin.solutions64(moved)
    sol.q[rows], sol.conf[rows], sol.status[rows] = again.q, again.conf, again.status


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
