"""Every pose of a task at every candidate base, solved in one batch (the closed-form IK of every
branch, ``Kinematics.ik64``), in chunks that keep memory bounded: whether some configuration within
the joint limits reaches it (with the target's confdata where ConfJ/ConfL check it), why not where
none does (out of reach, by how much; a joint limit; the confdata; the wrist centre on axis 1), and
how far the best configuration is from the arm's singularities: the wrist (|q5| from 0), the elbow
(q3 from the arm stretched) and the shoulder (the wrist centre from axis 1)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...kinematics.ik import NO_LIMITS, NO_REACH, OK, SHOULDER, ArmConstants
from ...motion.shortfall import across, arm_reach, axis2_distance
from ...motion.targets import stretched_q3
from ...motion.tcp import rigid_inverse

CHUNK = 131_072  # poses solved at once: 8 branches of 6 joints each, some 60 MB of work
REASONS = ("out of reach", "a joint limit", "the confdata", "the shoulder singularity")
FAR, LIMIT, CONF, AXIS1 = range(4)
SCALE = (30.0, 30.0, 300.0)  # deg, deg, mm: the singularity distances that count as clear of them


@dataclass
class Reach:
    """Per candidate (C,): poses reached, and the least wrist, elbow (degrees) and shoulder (mm)
    distances over the poses it reaches; per pose (P, reasons): the candidates each reason rules
    it out at, and (P,) the least and most it is beyond the arm's reach (mm; NaN: never)."""

    reached: np.ndarray
    singular: np.ndarray
    ruled_out: np.ndarray
    beyond: np.ndarray
    conf_missed: np.ndarray  # (C,) some pose reached only in another configuration than its confdata

    def merge(self, other: "Reach") -> None:
        """Another task's bases (each base is solved in one task: elsewhere its figures are 0 and NaN)."""
        self.reached += other.reached
        self.singular = np.fmin(self.singular, other.singular)
        self.ruled_out += other.ruled_out
        self.beyond[:, 0] = np.fmin(self.beyond[:, 0], other.beyond[:, 0])
        self.beyond[:, 1] = np.fmax(self.beyond[:, 1], other.beyond[:, 1])
        self.conf_missed |= other.conf_missed

    @property
    def score(self) -> np.ndarray:
        """(C,) the least of the three singularity distances, each over what counts as clear of it
        (capped at 1): the margin a base keeps on the program's worst pose."""
        return np.nan_to_num(_nanmin(np.minimum(self.singular / np.array(SCALE), 1.0)), nan=-1.0)


def reach(kin, bases: np.ndarray, poses, chunk: int | None = None, reached_all=None) -> Reach:
    """``Reach`` of the ``poses`` (``ProgramPoses``) at each base (C, 4, 4, the robot's base in the
    world); the robot ``kin`` must have the closed form of a 6-axis arm. ``reached_all(rows, q)``
    is given, chunk by chunk, the bases that reach every pose and their chosen configurations (n,
    P, 6): the collision check runs on them while they are at hand."""
    out = empty(len(bases), len(poses.world))
    per = per_chunk(len(poses.world), chunk)
    for lo in range(0, len(bases), per):
        solve_into(kin, bases, range(lo, min(lo + per, len(bases))), poses, out, reached_all)
    return out


def empty(bases: int, poses: int) -> Reach:
    """A ``Reach`` of ``bases`` bases and ``poses`` poses, none solved yet."""
    return Reach(np.zeros(bases, np.int64), np.full((bases, 3), np.nan), np.zeros((poses, len(REASONS)), np.int64),
                 np.full((poses, 2), np.nan), np.zeros(bases, bool))


def per_chunk(poses: int, chunk: int | None = None) -> int:
    """Bases solved at once: ``chunk`` poses' worth (``CHUNK``), at least one."""
    return max(1, (chunk or CHUNK) // poses)


def solve_into(kin, bases: np.ndarray, rows: range, poses, out: Reach, reached_all=None) -> None:
    """The bases ``rows`` of ``bases`` solved into ``out`` (a whole batch's ``Reach``)."""
    form = kin._ik_form()
    if not isinstance(form, ArmConstants):
        from ...errors import InputError

        raise InputError(f"'{kin.mech.name}' is not a 6-axis arm with a spherical wrist: rswarp place solves the "
                         "arm's closed form (a palletizer or another shape is not placed yet)")
    _chunk(kin, form, bases[rows.start:rows.stop], poses, out, rows.start, reached_all)


def solve(kin, form, bases: np.ndarray, poses) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(q (n, P, 6) the best configuration of each pose at each base, NaN where none reaches it;
    ok (n, P); the status (n, P, branches); the flange poses in the robot's frame (n, P, 4, 4))."""
    local = _in_bases(bases, poses.world)
    if poses.mount is not None:  # a carried robot: its base at each pose the carrier's frame times the mount
        local = rigid_inverse(poses.mount)[None] @ local
    n, count = local.shape[:2]
    sol = kin.ik64(local.reshape(-1, 4, 4))
    good = sol.status == OK
    if poses.checked.any():
        good &= _conf_ok(kin, sol, np.tile(poses.conf, (n, 1)), np.tile(poses.checked, n))
    with np.errstate(invalid="ignore"):  # a branch that has no solution is NaN, and not taken
        q5, q3 = sol.q[..., 4].astype(np.float32), (sol.q[..., 2] - stretched_q3(form)).astype(np.float32)
        value = np.where(good, np.minimum(np.abs(np.sin(q5)), np.abs(np.sin(q3))), -np.inf)  # float32: a choice
    best = np.argmax(value, axis=1)
    rows = np.arange(len(best))
    ok = good[rows, best]
    q = np.where(ok[:, None], sol.q[rows, best], np.nan)
    return q.reshape(n, count, -1), ok.reshape(n, count), sol.status.reshape(n, count, -1), local


def _in_bases(bases: np.ndarray, world: np.ndarray) -> np.ndarray:
    """(n, P, 4, 4): the world poses ``world`` (P, 4, 4) in each base's frame (``bases`` (n, 4, 4)),
    as one matrix product (the bases' inverses stacked against the poses side by side)."""
    n, count = len(bases), len(world)
    inverse = rigid_inverse(bases).reshape(n * 4, 4)
    side = world.transpose(1, 0, 2).reshape(4, count * 4)
    return np.ascontiguousarray((inverse @ side).reshape(n, 4, count, 4).transpose(0, 2, 1, 3))


def _chunk(kin, form, bases: np.ndarray, poses, out: Reach, at: int, reached_all) -> None:
    """One chunk of candidates (from ``at``) solved, its figures added to ``out``."""
    q, ok, status, local = solve(kin, form, bases, poses)
    n, count = ok.shape
    every = ok.all(axis=1)
    if reached_all is not None and every.any():
        reached_all(at + np.flatnonzero(every), q[every])
    out.reached[at:at + n] = ok.sum(axis=1)
    flat = q.reshape(n * count, -1)
    wrist, elbow = _branch_margins(form, flat[:, None])
    shoulder = _shoulder(form, local)
    for k, v in enumerate((wrist[:, 0].reshape(n, count), elbow[:, 0].reshape(n, count), shoulder)):
        out.singular[at:at + n, k] = _nanmin(np.where(ok, v, np.nan))
    missed = np.flatnonzero(~every)  # the reasons are looked for where a base misses a pose
    if len(missed):
        _reasons(form, ok[missed], status[missed], local[missed], out, at + missed)


def _reasons(form, ok, status, local, out: Reach, rows_at: np.ndarray) -> None:
    """Why each pose is missed at each base of the chunk: counted per pose, and how far beyond reach."""
    miss = ~ok
    limit = (status == NO_LIMITS).any(axis=2)
    any_ok = (status == OK).any(axis=2)
    axis1 = (status == SHOULDER).any(axis=2)
    far = miss & ~any_ok & ~limit & ~axis1 & (status == NO_REACH).any(axis=2)
    for k, mask in ((FAR, far), (LIMIT, miss & ~any_ok & limit), (CONF, miss & any_ok),
                    (AXIS1, miss & ~any_ok & ~limit & axis1)):
        out.ruled_out[:, k] += mask.sum(axis=0)
    out.conf_missed[rows_at] = (miss & any_ok).any(axis=1)
    if far.any():
        rows, cols = np.nonzero(far)
        gap = np.min(axis2_distance(form, local[rows, cols]), axis=1) - arm_reach(form)[0]
        mm = np.maximum(gap, 0.0) * 1000.0
        least, most = np.full(len(out.beyond), np.inf), np.full(len(out.beyond), -np.inf)
        np.minimum.at(least, cols, mm)
        np.maximum.at(most, cols, mm)
        hit = np.isfinite(least)
        out.beyond[hit, 0] = np.fmin(out.beyond[hit, 0], least[hit])
        out.beyond[hit, 1] = np.fmax(out.beyond[hit, 1], most[hit])


def _conf_ok(kin, sol, conf: np.ndarray, checked: np.ndarray) -> np.ndarray:
    """(N, branches): whether each branch has the target's confdata where it is checked: cf1 and
    cfx as the branch's, cf4 and cf6 its quadrant of axes 4 and 6 in some whole turn within the
    limits (ABB's cf4 and cf6 count the turns)."""
    lo, hi = kin.mech.bounds()
    c = conf[:, None, :]
    same = (sol.conf[..., 0] == c[..., 0]) & (sol.conf[..., 3] == c[..., 3])
    for col, axis in ((1, 3), (2, 5)):
        d = c[..., col] - sol.conf[..., col]
        turns = np.where(d % 4 == 0, d // 4, 0)
        moved = sol.q[..., axis] + 2.0 * np.pi * turns
        same &= (d % 4 == 0) & (moved >= lo[axis] - 1e-9) & (moved <= hi[axis] + 1e-9)
    return same | ~checked[:, None]


def _branch_margins(form, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(wrist, elbow) in degrees of configurations q (..., 6): |q5| from 0 (mod 180 degrees) and q3
    from the arm stretched (mod 180 degrees)."""
    wrist = np.degrees(np.abs(np.arcsin(np.clip(np.sin(q[..., 4]), -1.0, 1.0))))
    elbow = np.degrees(np.abs(np.arcsin(np.clip(np.sin(q[..., 2] - stretched_q3(form)), -1.0, 1.0))))
    return np.nan_to_num(wrist, nan=-1.0), np.nan_to_num(elbow, nan=-1.0)


def _shoulder(form, local: np.ndarray) -> np.ndarray:
    """(n, P) mm: the wrist centre's distance from axis 1 of flange poses in the robot's frame."""
    centre = local[..., :3, 3] + local[..., :3, :3] @ np.asarray(form.cf)
    return 1000.0 * across(centre - np.asarray(form.p1), np.asarray(form.w1))


def _nanmin(v: np.ndarray) -> np.ndarray:
    """The least of each row, NaN for a row of NaN (a base that reaches nothing)."""
    filled = np.where(np.isnan(v), np.inf, v).min(axis=1)
    return np.where(np.isinf(filled), np.nan, filled)
