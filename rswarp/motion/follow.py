"""Joint values along a path of flange poses, continuous from where the robot is: the branch an
arm's closed form gives, kept (its wrist twin taken where the path passes the wrist singularity),
with the turns of axes 4 and 6 followed; where no branch continues, the probe and why."""

from __future__ import annotations

import numpy as np

from ..kernels.ik import OK
from ..kinematics.ik import ArmConstants

JUMP = 0.5  # rad: an axis moving more between two probes has left its branch
FLIP = 0.5  # rad of axes 1 to 3 between probes: a change of configuration, which a path cannot follow


def follow(kin, sol, q0: np.ndarray):
    """Joint values along a path whose flange poses have the solutions ``sol``, continuous from
    ``q0``: (q, the first probe the path cannot reach or follow, why, the configuration data at
    the end or None). An arm keeps its shoulder and elbow; its wrist changes branch only where the
    path passes the wrist singularity; axes 4 and 6 keep their turns."""
    if not isinstance(kin._ik_form(), ArmConstants) or sol.numerical:
        return (*_follow_each(kin, sol, q0), None)
    lower, upper = bounds(kin)
    count = sol.q.shape[0]
    out = np.empty((count, len(q0)))
    k, prev, branch = 0, q0, None
    while k < count:
        picked = _pick(sol, k, prev, branch, lower, upper)
        if picked is None:
            why = "out of reach" if not sol.ok[k].any() else "a joint limit" if branch is not None else "out of reach"
            return out[:k], k, why, None
        best, start = picked
        if branch is not None and best // 2 != branch // 2 or np.max(np.abs(start[:3] - prev[:3])) > FLIP:
            return out[:k], k, "a configuration flip", None
        seg = _segment(sol, k, best, start, lower, upper)
        out[k:k + len(seg)] = seg
        prev, branch, k = seg[-1], best, k + len(seg)
    quarter = np.floor(out[-1, [0, 3, 5]] / (0.5 * np.pi)).astype(int)
    return out, None, "", (int(quarter[0]), int(quarter[1]), int(quarter[2]), int(sol.conf[-1, branch, 3]))


def bounds(kin) -> tuple[np.ndarray, np.ndarray]:
    """The robot's joint limits, made once per ``Kinematics``."""
    made = kin.__dict__.get("_follow_bounds")
    if made is None:
        made = kin.__dict__["_follow_bounds"] = kin.mech.bounds()
    return made


def _aligned(cand: np.ndarray, prev: np.ndarray) -> np.ndarray:
    """Candidates with axes 4 and 6 turned whole turns to lie nearest ``prev``."""
    cand = cand.copy()
    cand[..., _TURNS] += TWO_PI * np.round((prev[_TURNS] - cand[..., _TURNS]) / TWO_PI)
    return cand


def _pick(sol, k: int, prev: np.ndarray, branch, lower, upper):
    """(branch, its aligned joints) at probe ``k`` nearest ``prev``: among all at the start, else
    the branch and its wrist twin."""
    options = np.arange(sol.q.shape[1]) if branch is None else np.array([branch, branch ^ 1])
    cand = _aligned(sol.q[k] if branch is None else sol.q[k, options], prev)
    fine = (sol.status[k, options] == OK) & np.all((cand >= lower) & (cand <= upper), axis=1)
    if not fine.any():
        return None
    dist = np.where(fine, np.max(np.abs(cand - prev), axis=1), np.inf)
    best = int(np.argmin(dist))
    return int(options[best]), cand[best]


_TURNS = np.array([3, 5])  # axes 4 and 6, which turn without end
TWO_PI = 2 * np.pi


def _segment(sol, k: int, b: int, start: np.ndarray, lower, upper) -> np.ndarray:
    """Branch ``b`` from probe ``k`` on, turns unwrapped from ``start``, up to (not including) the
    first probe where it is not a solution, leaves the limits, or jumps."""
    seg = sol.q[k:, b].copy()
    turning = seg[:, _TURNS]
    turning[1:] -= TWO_PI * np.cumsum(np.round((turning[1:] - turning[:-1]) / TWO_PI), axis=0)
    seg[:, _TURNS] = turning + (start[_TURNS] - turning[0])
    ok = sol.status[k:, b] == OK
    step = np.abs(seg[1:] - seg[:-1]).max(axis=1)
    if len(seg) > 1 and _clear(seg, ok, step, lower, upper):
        return seg  # the common case, in a few whole-array checks
    bad = ~ok
    bad |= ((seg < lower) | (seg > upper) | ~np.isfinite(seg)).any(axis=1)
    bad[1:] |= step > JUMP
    stop = np.flatnonzero(bad)
    end = int(stop[0]) if len(stop) and stop[0] > 0 else (1 if len(stop) else len(seg))
    return seg[:end]


def _clear(seg: np.ndarray, ok: np.ndarray, step: np.ndarray, lower, upper) -> bool:
    """Whether a branch is a solution, finite, within the limits and without a jump at every probe."""
    lo, hi = seg.min(axis=0), seg.max(axis=0)  # NaN where any is
    return bool(ok.all() and step.max() <= JUMP and np.isfinite(lo).all() and np.isfinite(hi).all()
                and (lo >= lower).all() and (hi <= upper).all())


def _follow_each(kin, sol, q0: np.ndarray):
    """``follow`` one probe at a time, for mechanisms without the arm's branches: the solution
    nearest the one before."""
    lower, upper = kin.mech.bounds()
    out = np.empty((sol.q.shape[0], len(q0)))
    prev = q0
    for k in range(len(out)):
        cand = sol.q[k]
        ok = sol.ok[k] & np.all((cand >= lower) & (cand <= upper), axis=1)
        if not ok.any():
            return out[:k], k, "out of reach" if not sol.ok[k].any() else "a joint limit"
        dist = np.where(ok, np.abs(cand - prev).max(axis=1), np.inf)
        out[k] = prev = cand[int(np.argmin(dist))]
    return out, None, ""
