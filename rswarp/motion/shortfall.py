"""How far a pose the robot cannot take is from what it can, as a figure a programmer acts on: for
an arm (the closed form's ``ArmConstants``), the wrist centre beyond the arm's reach from axis 2
(or too near it for the arm to fold to); for a pose reachable only outside the joint limits, the
joint and how far past which bound. ``reach_margin`` and ``limit_margin`` of ``targets.margins``
are the same measures of a pose the robot takes."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..kernels.ik import NO_LIMITS, OK
from ..kinematics.ik import ArmConstants

REACH, INNER, LIMIT = "reach", "inner", "limit"


@dataclass(frozen=True)
class Shortfall:
    """``value`` against ``limit`` (m, or rad or m for a joint), ``excess`` past it (> 0);
    ``kind``: reach (the wrist centre beyond the arm), inner (too near axis 2), limit (a joint)."""

    kind: str
    value: float
    limit: float
    unit: str
    excess: float
    joint: str | None = None
    revolute: bool = True
    span: tuple[float, float] | None = None  # the joint's limits

    def words(self, up_to: bool = False) -> str:
        """What is wrong, in words; ``up_to``: the worst of several."""
        most = "up to " if up_to else ""
        if self.kind == REACH:
            return f"the wrist centre is {most}{mm(self.excess)} mm beyond the arm's reach from axis 2"
        if self.kind == INNER:
            return f"the wrist centre is {most}{mm(self.excess)} mm too near axis 2 for the arm to fold to"
        need, bound = self.figures()
        return f"{self.joint} would need {most}{need}, its limit is {bound}"

    def figures(self) -> tuple[str, str]:
        """A joint's value and bound as shown: degrees or mm, as many decimals as tell them apart."""
        scale, unit = (np.degrees(1.0), "°") if self.revolute else (1000.0, " mm")
        a, b = self.value * scale, self.limit * scale
        digits = next((d for d in (0, 1, 2) if f"{a:.{d}f}" != f"{b:.{d}f}"), 3)
        return f"{a:.{digits}f}{unit}", f"{b:.{digits}f}{unit}"

    def advice(self) -> str:
        if self.kind == REACH:
            return f"move the target {mm(self.excess)} mm closer to the robot's base"
        if self.kind == INNER:
            return f"move the target {mm(self.excess)} mm farther from the robot's base"
        lo, hi = (Shortfall(LIMIT, v, v, self.unit, 0.0, self.joint, self.revolute).figures()[0] for v in self.span)
        return f"{self.words()}: turn or move the target so {self.joint} stays within [{lo}, {hi}]"


def mm(metres: float) -> str:
    """A length in whole mm, or to 0.1 mm below 10 mm."""
    x = 1000.0 * float(metres)
    return f"{x:.0f}" if abs(x) >= 9.95 else f"{x:.1f}"


def arm_reach(form: ArmConstants) -> tuple[float, float]:
    """The farthest and the nearest the wrist centre gets from axis 2 (m): the upper arm's and the
    forearm's lengths across axis 2, stretched and folded."""
    w2, p2, p3, c0 = (np.asarray(v, float) for v in (form.w2, form.p2, form.p3, form.c0))
    a, b = across(p3 - p2, w2), across(c0 - p3, w2)
    return float(a + b), float(abs(a - b))


def across(v: np.ndarray, w: np.ndarray) -> np.ndarray:
    """The length of ``v`` (..., 3) across the unit axis ``w``."""
    return np.linalg.norm(v - (v @ w)[..., None] * w, axis=-1)


def axis2_distance(form: ArmConstants, flanges: np.ndarray) -> np.ndarray:
    """(N, 2): the wrist centre's distance from axis 2 of flange poses (N, 4, 4), with axis 1
    turned either way that puts the centre in the arm's plane (the nearest turn where none does)."""
    w1, p1, w2, p2, c0, cf = (np.asarray(v, float) for v in (form.w1, form.p1, form.w2, form.p2, form.c0, form.cf))
    u = flanges[:, :3, :3] @ cf + flanges[:, :3, 3] - p1
    along = (u @ w1)[:, None] * w1
    side = np.cross(w1, u)
    a, b = (u - along) @ w2, -(side @ w2)
    rho = np.maximum(np.hypot(a, b), 1e-12)
    ratio = np.clip(((c0 - p1) @ w2 - along @ w2) / rho, -1.0, 1.0)
    out = np.empty((len(u), 2))
    for k, sign in enumerate((1.0, -1.0)):
        t = np.arctan2(b, a) + sign * np.arccos(ratio)  # axis 1 turned back by t: the arm at zero
        centre = along + np.cos(t)[:, None] * (u - along) - np.sin(t)[:, None] * side + p1
        out[:, k] = across(centre - p2, w2)
    return out


def reach_shortfalls(form: ArmConstants, flanges: np.ndarray) -> list[Shortfall | None]:
    """How far beyond (or inside) the arm's reach from axis 2 each pose's wrist centre is."""
    far, near = arm_reach(form)
    d = axis2_distance(form, flanges)
    past = np.maximum(d - far, 0.0) + np.maximum(near - d, 0.0)
    best = np.argmin(past, axis=1)
    out = []
    for k, j in enumerate(best):
        dist = float(d[k, j])
        if past[k, j] <= 1e-9:
            out.append(None)
        elif dist > far:
            out.append(Shortfall(REACH, dist, far, "m", dist - far))
        else:
            out.append(Shortfall(INNER, dist, near, "m", near - dist))
    return out


def limit_shortfall(mech, cands: np.ndarray, status: np.ndarray, near: np.ndarray | None = None) -> Shortfall | None:
    """The joint furthest past its limit in the solution (S, dof) nearest ``near``, or, without
    it, in the solution that needs the least past its limits; None where it needs nothing past."""
    lower, upper = mech.bounds()
    usable = ((status == OK) | (status == NO_LIMITS)) & np.all(np.isfinite(cands), axis=1)
    if not usable.any():
        return None
    past = np.maximum(np.maximum(lower - cands, cands - upper), 0.0)  # the same measure as limit_margin
    score = np.max(np.abs(cands - near), axis=1) if near is not None else past.max(axis=1)
    k = int(np.argmin(np.where(usable, score, np.inf)))
    j = int(np.argmax(past[k]))
    if past[k, j] <= 0.0:
        return None
    joint = mech.active_joints[j]
    q = float(cands[k, j])
    bound = float(lower[j] if q < lower[j] else upper[j])
    return Shortfall(LIMIT, q, bound, "rad" if joint.revolute else "m", float(past[k, j]), joint.name,
                     joint.revolute, (float(lower[j]), float(upper[j])))


def shortfalls(kin, flanges: np.ndarray, limits: bool | list = True, near=None) -> list[Shortfall | None]:
    """Per flange pose (N, 4, 4) the robot cannot take: beyond the arm's reach, else past a joint
    limit (where ``limits``, one flag a pose or one for all; ``near``: joints each is reached
    from); None where neither is found."""
    n = len(flanges)
    if not n:
        return []
    form = kin._ik_form()
    out = reach_shortfalls(form, flanges) if isinstance(form, ArmConstants) else [None] * n
    wanted = [s is None and (limits if isinstance(limits, bool) else limits[k]) for k, s in enumerate(out)]
    rows = [k for k, w in enumerate(wanted) if w]
    if rows:
        sol = kin.solutions64(flanges[rows])
        for i, k in enumerate(rows):
            out[k] = limit_shortfall(kin.mech, sol.q[i], sol.status[i], None if near is None else near[k])
    return out
