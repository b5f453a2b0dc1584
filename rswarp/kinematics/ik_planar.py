"""Closed-form inverse kinematics of a palletizer: axis 1 vertical, an arm whose joints all turn
about one horizontal direction with angles linear in two active joints (the parallel rods' solved
loops: ``loops.passive_map``), a flange held level, and a last axis parallel to axis 1 through
the flange. Every ABB palletizer (IRB 460, 660, 760, 9460) has this shape; up to four branches
(shoulder front and back, elbow up and down). Host NumPy, vectorized, float64 or float32."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..kernels.ik import CONF, NO_LIMITS, NO_REACH, OK
from ..kernels.types import REVOLUTE, Chain
from .ik import IKSolutions, quadrant

BRANCHES = 4  # 2 shoulder + elbow


@dataclass(frozen=True)
class PlanarArm:
    """A palletizer's constants (world, metres, at the zero position)."""

    w1: np.ndarray
    p1: np.ndarray
    w2: np.ndarray
    plane: np.ndarray  # (2, 3): the arm plane's axes, right-handed about w2
    d0: float  # the flange's component along w2, from p1
    base: np.ndarray  # (2,): the planar vectors that never turn, summed (from p1's projection)
    a: np.ndarray  # (2,): the vectors turning with the first angle row, summed
    b: np.ndarray  # (2,): with the second
    inverse: np.ndarray  # (2, 2): joint values of the two arm joints from the two angles
    rows: np.ndarray  # (2, dof): the two angles as rows over q
    arm: tuple[int, int]  # the columns of q the arm angles read
    first: int  # axis 1's column
    last: int  # the last axis's column
    w6: np.ndarray
    rm: np.ndarray  # the flange's zero-position rotation
    h0: np.ndarray  # the arm's horizontal direction at zero


def _path(chain: Chain, link: int) -> list[int]:
    out = []
    while link >= 0 and chain.jtype[link] != 2:
        out.append(link)
        link = int(chain.parent[link])
    return out[::-1]


def _rows(chain: Chain, path: list[int]) -> list[np.ndarray] | None:
    """Each path joint's angle as a row over q, or None where one is not linear in q."""
    dof = chain.mimic.shape[1]
    rows = []
    for k in path:
        if chain.jtype[k] != REVOLUTE or chain.closed_form[k, 0] != 0 or chain.unknown[k] >= 0:
            return None
        row = np.zeros(dof)
        if chain.qidx[k] >= 0:
            row[chain.qidx[k]] = 1.0
        else:
            row = chain.mimic[k].astype(float)
        rows.append(row)
    return rows


def planar_arm(chain: Chain, flange_link: int, flange: np.ndarray) -> PlanarArm | None:
    """The palletizer's constants, or None when the chain to the flange has another shape."""
    path = _path(chain, flange_link)
    rows = _rows(chain, path)
    if rows is None or len(path) < 4:
        return None
    unit = lambda r: np.count_nonzero(r) == 1 and np.isclose(r.max(), 1.0)  # noqa: E731
    w1, w6 = chain.axis[path[0]], chain.axis[path[-1]]
    if not (unit(rows[0]) and unit(rows[-1]) and abs(abs(w1 @ w6) - 1) < 1e-12):
        return None
    f0 = flange[:3, 3]
    if np.linalg.norm(np.cross(f0 - chain.point[path[-1]], w6)) > 1e-9:
        return None  # the flange off the last axis
    w2 = chain.axis[path[1]]
    if abs(w1 @ w2) > 1e-12:
        return None
    signs = []
    for k in path[1:-1]:
        if np.linalg.norm(np.cross(chain.axis[k], w2)) > 1e-12:
            return None
        signs.append(float(np.sign(chain.axis[k] @ w2)))
    first, last = int(np.argmax(rows[0])), int(np.argmax(rows[-1]))
    turning = [s * r for s, r in zip(signs, rows[1:-1])]
    cumulative = np.cumsum(turning, axis=0)
    if np.abs(cumulative[-1]).max() > 1e-12 or np.abs(cumulative[:, [first, last]]).max() > 1e-12:
        return None  # the flange not held level, or the arm moved by axis 1 or the last axis
    ea = np.cross(w2, w1)
    plane = np.stack([ea, np.cross(w2, ea)])
    points = [chain.point[k] for k in path[1:-1]] + [f0]
    groups: dict[tuple, np.ndarray] = {}
    for row, p, p_next in zip(cumulative, points, points[1:]):
        key = tuple(np.round(row, 12))
        groups[key] = groups.get(key, np.zeros(2)) + plane @ (p_next - p)
    base = plane @ (points[0] - chain.point[path[0]]) + groups.pop(tuple(np.zeros(len(rows[0]))), np.zeros(2))
    if len(groups) != 2:
        return None
    (ra, a), (rb, b) = groups.items()
    arm = tuple(int(i) for i in np.nonzero(np.abs(np.array(ra)) + np.abs(np.array(rb)))[0])
    if len(arm) != 2:
        return None
    matrix = np.array([ra, rb])[:, arm]
    if abs(np.linalg.det(matrix)) < 1e-9:
        return None
    h = f0 - chain.point[path[0]]
    h = h - (h @ w1) * w1
    p1 = chain.point[path[0]]
    return PlanarArm(w1=w1, p1=p1, w2=w2, plane=plane, d0=float(w2 @ (f0 - p1)), base=base, a=a, b=b,
                     inverse=np.linalg.inv(matrix), rows=np.array([ra, rb]), arm=arm, first=first, last=last, w6=w6,
                     rm=flange[:3, :3], h0=h / max(np.linalg.norm(h), 1e-12))


def _rot(w: np.ndarray, c: np.ndarray, s: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Vectors v (N, 3) turned about the unit axis w by angles of cosine c and sine s (N,)."""
    return v * c[:, None] + np.cross(w, v) * s[:, None] + np.outer(v @ w, w) * (1 - c)[:, None]


def _wrap(x: np.ndarray) -> np.ndarray:
    return np.mod(x + np.pi, 2 * np.pi) - np.pi


def solve(arm: PlanarArm, poses: np.ndarray, lower: np.ndarray, upper: np.ndarray, dof: int) -> IKSolutions:
    """The four branches of each flange pose (N, 4, 4); orientations the level flange cannot take
    are out of reach."""
    poses = np.asarray(poses, np.float64)
    n = len(poses)
    q = np.zeros((n, BRANCHES, dof))
    status = np.full((n, BRANCHES), OK, np.int8)
    u = poses[:, :3, 3] - arm.p1
    par = u @ arm.w1
    a_, b_ = (u - np.outer(par, arm.w1)) @ arm.w2, -(np.cross(arm.w1, u) @ arm.w2)
    rho = np.hypot(a_, b_)
    ratio = (arm.d0 - par * (arm.w1 @ arm.w2)) / np.maximum(rho, 1e-12)
    far = (np.abs(ratio) > 1) | (rho < 1e-9)
    phi, spread = np.arctan2(b_, a_), np.arccos(np.clip(ratio, -1, 1))
    la, lb = np.linalg.norm(arm.a), np.linalg.norm(arm.b)
    turn0 = np.arctan2(arm.a[1], arm.a[0]) - np.arctan2(arm.b[1], arm.b[0])
    tol = 1e-6 if poses.dtype == np.float64 else 1e-4
    for s, sign in enumerate((1.0, -1.0)):
        q1 = _wrap(phi + sign * spread)
        y = _rot(arm.w1, np.cos(q1), -np.sin(q1), u) + arm.p1
        yd = (y - arm.p1) @ arm.plane.T - arm.base
        d2 = np.einsum("ni,ni->n", yd, yd)
        cg = (d2 - la * la - lb * lb) / (2 * la * lb)
        out = far | (np.abs(cg) > 1)
        for e, sign_e in enumerate((1.0, -1.0)):
            psi = sign_e * np.arccos(np.clip(cg, -1, 1)) + turn0
            z = arm.a + np.stack([np.cos(psi) * arm.b[0] - np.sin(psi) * arm.b[1],
                                  np.sin(psi) * arm.b[0] + np.cos(psi) * arm.b[1]], axis=1)
            phi_a = np.arctan2(z[:, 0] * yd[:, 1] - z[:, 1] * yd[:, 0], np.einsum("ni,ni->n", z, yd))
            joints = np.stack([phi_a, phi_a + psi], axis=1) @ arm.inverse.T
            r6 = _r1t(arm, q1) @ poses[:, :3, :3] @ arm.rm.T  # R1^T R_T R_M^T: a turn about w6
            off_axis = np.linalg.norm(r6 @ arm.w6 - arm.w6, axis=1) > tol
            n6 = np.cross(arm.w6, arm.w2)
            m = r6 @ n6
            q6 = np.arctan2(np.cross(n6, m) @ arm.w6, m @ n6)
            k = 2 * s + e
            q[:, k, arm.first], q[:, k, arm.last] = q1, q6
            q[:, k, arm.arm[0]], q[:, k, arm.arm[1]] = _wrap(joints[:, 0]), _wrap(joints[:, 1])
            status[:, k] = np.where(out | off_axis, NO_REACH, OK)
    q = _into(q, lower, upper)
    inside = np.all((q >= lower) & (q <= upper), axis=-1)
    status[(status == OK) & ~inside] = NO_LIMITS
    return IKSolutions(q.astype(poses.dtype), confdata(arm, q, poses[:, None, :3, 3]).astype(np.int8), status)


def confdata(arm: PlanarArm, q: np.ndarray, flange: np.ndarray) -> np.ndarray:
    """(..., 4) cf1, 0, cf6, cfx of joint values q (..., dof) with flange positions (..., 3):
    cfx = 4 (flange behind axis 1) + 2 (behind the arm: on the other side of its first part's line
    than at zero)."""
    q1 = q[..., arm.first]
    c, s = np.cos(q1), np.sin(q1)
    h = arm.h0
    along = c[..., None] * h + s[..., None] * np.cross(arm.w1, h)  # R1 h0 (h0 is across w1)
    behind1 = np.einsum("...i,...i->...", flange - arm.p1, along) < 0
    phi_a, phi_b = q @ arm.rows[0], q @ arm.rows[1]
    cross = lambda u, v: u[0] * v[1] - u[1] * v[0]  # noqa: E731
    side = np.sin(phi_b - phi_a + np.arctan2(arm.b[1], arm.b[0]) - np.arctan2(arm.a[1], arm.a[0]))
    behind = side * cross(arm.a, arm.a + arm.b) < 0
    out = np.zeros(q.shape[:-1] + (CONF,), np.int32)
    out[..., 0], out[..., 2] = quadrant(q1), quadrant(q[..., arm.last])
    out[..., 3] = 4 * behind1 + 2 * behind
    return out


def _r1t(arm: PlanarArm, q1: np.ndarray) -> np.ndarray:
    """(N, 3, 3) R1(q1)^T."""
    c, s = np.cos(q1), np.sin(q1)
    w = arm.w1
    skew = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    r = c[:, None, None] * np.eye(3) + s[:, None, None] * skew + (1 - c)[:, None, None] * np.outer(w, w)
    return np.swapaxes(r, 1, 2)


def _into(q: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """Each value turned by a whole turn into its limits where that fits and it does not."""
    out = q.copy()
    for k in (2 * np.pi, -2 * np.pi):
        moved = out + k
        fix = ((out < lower) | (out > upper)) & (moved >= lower) & (moved <= upper)
        out[fix] = moved[fix]
    return out
