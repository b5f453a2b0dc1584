"""Closed-form inverse kinematics of a palletizer: axis 1 vertical, an arm whose joints all turn
about one horizontal direction with angles linear in two active joints (the parallel rods' solved
loops: ``loops.passive_map``), a flange held level, and a last axis parallel to axis 1 through
the flange. Every ABB palletizer (IRB 460, 660, 760, 9460) has this shape; up to four branches
(shoulder front and back, elbow up and down). The solve is device code (``kernels/ik_planar.py``);
this module finds the shape and its constants, and the configuration data."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..kernels.ik import CONF, NO_LIMITS, OK
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


def constants(arm: PlanarArm, dtype) -> tuple:
    """The flat constants the device code folds in (``kernels.ik_planar``)."""
    la, lb = float(np.linalg.norm(arm.a)), float(np.linalg.norm(arm.b))
    n6 = np.cross(arm.w6, arm.w2)
    t = lambda v: tuple(float(x) for x in np.ravel(v))  # noqa: E731
    return (("w1", t(arm.w1)), ("p1", t(arm.p1)), ("w2", t(arm.w2)), ("ea", t(arm.plane[0])), ("eb", t(arm.plane[1])),
            ("w6", t(arm.w6)), ("n6", t(n6 / np.linalg.norm(n6))), ("rm", t(arm.rm)), ("d0", float(arm.d0)),
            ("lsum", la * la + lb * lb), ("lprod", 2.0 * la * lb),
            ("turn0", float(np.arctan2(arm.a[1], arm.a[0]) - np.arctan2(arm.b[1], arm.b[0]))),
            ("tol", 1e-6 if dtype == np.float64 else 1e-4), ("base", t(arm.base)), ("a", t(arm.a)), ("b", t(arm.b)),
            ("inverse", t(arm.inverse)), ("first", arm.first), ("last", arm.last), ("arm0", arm.arm[0]),
            ("arm1", arm.arm[1]))


def solve(launcher, arm: PlanarArm, poses: np.ndarray, lower: np.ndarray, upper: np.ndarray,
                 dof: int) -> IKSolutions:
    """The four branches of each flange pose (N, 4, 4), as device code on the launcher's device;
    the limits and the configuration data on the host. A flange that is not level is out of
    reach."""
    from ..kernels.ik_planar import planar_ik_kernel
    from ..launch import init_warp

    wp = init_warp()
    dtype = poses.dtype
    kernel = planar_ik_kernel(constants(arm, dtype), dof, wp.float32 if dtype == np.float32 else wp.float64)
    n = len(poses)
    q = np.empty((n, BRANCHES, dof), dtype)
    status = np.empty((n, BRANCHES), np.int8)
    launcher.launch(kernel, n, inputs=[np.ascontiguousarray(poses)], outputs=[q, status])
    q = _into(q, lower, upper)
    inside = np.all((q >= lower) & (q <= upper), axis=-1)
    status[(status == OK) & ~inside] = NO_LIMITS
    return IKSolutions(q, confdata(arm, q, poses[:, None, :3, 3]).astype(np.int8), status)


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


def _into(q: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """Each value turned by a whole turn into its limits where that fits and it does not."""
    out = q.copy()
    for k in (2 * np.pi, -2 * np.pi):
        moved = out + k
        fix = ((out < lower) | (out > upper)) & (moved >= lower) & (moved <= upper)
        out[fix] = moved[fix]
    return out
