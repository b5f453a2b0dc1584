"""Numerical inverse kinematics for a mechanism the closed form does not cover: damped least
squares (Levenberg-Marquardt) on the flange pose from several seeds, on the mechanism's own float64
forward kinematics (loops included), with a finite-difference Jacobian. Its answers are flagged
``numerical``: it may miss solutions the seeds do not lead to."""

from __future__ import annotations

import numpy as np

from ..kernels.ik import CONF, NO_LIMITS, NO_REACH, OK, SAME
from .ik import IKSolutions, quadrant

SEEDS = 8  # starts per pose: the zero position, then uniform draws within the limits (seed 0)
STEPS = 100  # damped least-squares steps at most
TOLERANCE = 1e-10  # m and rad: a pose matched closer than this is solved
DAMPING = 1e-4  # lambda^2 of the step (J^T J + lambda^2 I) dq = J^T e
CHUNK = 2048  # poses solved at once (memory: CHUNK x SEEDS x (2 dof + 1) flange poses)
H = 1e-7  # the finite-difference step (rad, m)


def _seeds(lower: np.ndarray, upper: np.ndarray, dof: int) -> np.ndarray:
    lo = np.where(np.isfinite(lower), lower, -np.pi)
    hi = np.where(np.isfinite(upper), upper, np.pi)
    draws = np.random.default_rng(0).uniform(lo, hi, (SEEDS - 1, dof))
    return np.vstack([np.clip(np.zeros(dof), lo, hi), draws])


def pose_error(target: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """(M, 6): the position error and the rotation vector from pose to target (world)."""
    from scipy.spatial.transform import Rotation

    turn = Rotation.from_matrix(target[:, :3, :3] @ np.swapaxes(pose[:, :3, :3], 1, 2)).as_rotvec()
    return np.concatenate([target[:, :3, 3] - pose[:, :3, 3], turn], axis=1)


def _refine(kin, targets: np.ndarray, q: np.ndarray, lower, upper) -> tuple[np.ndarray, np.ndarray]:
    """Damped least-squares steps of every (target, start) row: (q, residual norm)."""
    dof = q.shape[1]
    err = pose_error(targets, flange64(kin, q))
    for _ in range(STEPS):
        res = np.linalg.norm(err, axis=1)
        live = res > TOLERANCE
        if not live.any():
            break
        ql, el, tl = q[live], err[live], targets[live]
        jac = jacobian(kin, tl, ql, H)
        jt = np.swapaxes(jac, 1, 2)
        lhs = jt @ jac + DAMPING * np.eye(dof)
        dq = np.linalg.solve(lhs, (jt @ el[:, :, None]))[:, :, 0]
        ql = np.clip(ql + dq, lower, upper)
        q[live] = ql
        err[live] = pose_error(tl, flange64(kin, ql))
    return q, np.linalg.norm(err, axis=1)


def jacobian(kin, targets: np.ndarray, q: np.ndarray, h: float) -> np.ndarray:
    """(M, 6, dof): how each row's pose error to its target falls as each joint moves by ``h``
    (forward differences, every row's steps in one launch)."""
    dof = q.shape[1]
    base = pose_error(targets, flange64(kin, q))
    moved = flange64(kin, (q[:, None, :] + h * np.eye(dof)[None]).reshape(-1, dof)).reshape(len(q), dof, 4, 4)
    return np.stack([(base - pose_error(targets, moved[:, j])) / h for j in range(dof)], axis=2)


def flange64(kin, q: np.ndarray) -> np.ndarray:
    link, m = kin.flange_frame()
    return kin.fk64(q)[:, link] @ m


def solve(kin, poses: np.ndarray) -> IKSolutions:
    """``SEEDS`` solutions of each flange pose, numerically; duplicates (within 1e-6) marked."""
    lower, upper = kin.mech.bounds()
    dof = kin.dof
    seeds = _seeds(lower, upper, dof)
    n = len(poses)
    q = np.empty((n, SEEDS, dof))
    status = np.empty((n, SEEDS), np.int32)
    for lo in range(0, n, CHUNK):
        part = poses[lo:lo + CHUNK]
        m = len(part)
        rows, res = _refine(kin, np.repeat(part, SEEDS, axis=0), np.tile(seeds, (m, 1)), lower, upper)
        q[lo:lo + m] = rows.reshape(m, SEEDS, dof)
        status[lo:lo + m] = np.where(res.reshape(m, SEEDS) < 1e-6, OK, NO_REACH)
    inside = np.all((q >= lower - 1e-12) & (q <= upper + 1e-12), axis=-1)
    status[(status == OK) & ~inside] = NO_LIMITS
    for s in range(1, SEEDS):  # a start that found an earlier start's solution
        same = np.any(np.all(np.abs(q[:, :s] - q[:, s:s + 1]) < 1e-6, axis=-1) & (status[:, :s] == OK), axis=1)
        status[:, s][same & (status[:, s] == OK)] = SAME
    conf = np.zeros((n, SEEDS, CONF), np.int32)
    conf[..., 0] = quadrant(q[..., 0])
    return IKSolutions(q, conf, status, numerical=True)
