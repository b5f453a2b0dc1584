"""RAPID's frames fitted to measured points (DefAccFrame, CalcRotAxisFrame): least squares over
the targets' positions, with the largest and mean residual written back (mm), as the manual's
entries define them."""

from __future__ import annotations

import numpy as np

from . import poses
from .arguments import Arguments
from .errors import fail
from .values import Arr, Rec


def _points(interp, a: Arguments, k: int, count: int) -> np.ndarray:
    """The positions (mm) of the first ``count`` robtargets of the array argument ``k``."""
    arr = a.value(k)
    if not isinstance(arr, Arr) or not 3 <= count <= len(arr.items):
        fail(interp.path, a.line, f"{a.name}: needs an array of at least {max(count, 3)} robtargets")
    return np.array([[float(c) for c in t.vals[0].vals] for t in arr.items[:count]])


def _errors(a: Arguments, residuals: np.ndarray, first: int) -> None:
    a.reference(first).set(float(residuals.max()))
    a.reference(first + 1).set(float(residuals.mean()))


def _pose(origin, axes: np.ndarray) -> Rec:
    return poses.pose(tuple(float(c) for c in origin), poses.matrix_quat([tuple(map(float, c)) for c in axes.T]))


def def_acc_frame(interp, a: Arguments) -> Rec:
    """DefAccFrame(Original, Displaced, Count, MaxErr, MeanErr): the frame that best takes the
    original points to the displaced ones (Kabsch)."""
    a.need(5)
    count = int(a.number(2))
    p, q = _points(interp, a, 0, count), _points(interp, a, 1, count)
    pc, qc = p.mean(axis=0), q.mean(axis=0)
    u, _, vt = np.linalg.svd((p - pc).T @ (q - qc))
    d = np.sign(np.linalg.det(vt.T @ u.T)) or 1.0
    r = vt.T @ np.diag([1.0, 1.0, d]) @ u.T
    t = qc - r @ pc
    _errors(a, np.linalg.norm(p @ r.T + t - q, axis=1), 3)
    return _pose(t, r)


def calc_rot_axis_frame(interp, a: Arguments) -> Rec:
    """CalcRotAxisFrame(MechUnit, Targets, Count, MaxErr, MeanErr): the frame of a rotational
    axis from TCP points on its circle: z along the axis (the plane's normal, right-handed with the
    order of the points), origin at the circle's centre, x towards the first point."""
    a.need(5)
    count = int(a.number(2))
    p = _points(interp, a, 1, count)
    c = p.mean(axis=0)
    _, _, vt = np.linalg.svd(p - c)
    x0, y0 = vt[0], vt[1]
    uv = np.c_[(p - c) @ x0, (p - c) @ y0]
    lhs = np.c_[2 * uv, np.ones(len(uv))]
    (cx, cy, k), *_ = np.linalg.lstsq(lhs, (uv ** 2).sum(axis=1), rcond=None)
    centre = c + cx * x0 + cy * y0
    radius = np.sqrt(k + cx * cx + cy * cy)
    z = np.cross(p[0] - centre, p[1] - centre)
    if np.linalg.norm(z) < 1e-9:
        fail(interp.path, a.line, f"{a.name}: the first two points and the centre are on one line")
    z /= np.linalg.norm(z)
    x = (p[0] - centre) - ((p[0] - centre) @ z) * z
    x /= np.linalg.norm(x)
    residuals = np.hypot(np.linalg.norm(uv - [cx, cy], axis=1) - radius, (p - c) @ vt[2])
    _errors(a, residuals, 3)
    return _pose(centre, np.c_[x, np.cross(z, x), z])


FUNCTIONS = {"defaccframe": def_acc_frame, "calcrotaxisframe": calc_rot_axis_frame}
