"""Workspace sweeps over the joint limits: reach as ABB states it, the flange's reach, the lowest
and highest points, voxel occupancy of wrist-centre and flange positions, and the side and top
views of datasheets.

Samples are drawn chunk by chunk (memory stays bounded for any count); each chunk's samples depend
only on the seed and the chunk's index, so a sweep gives the same numbers on one core or many.
Extremes are the true ones, not the best sample: the best samples are refined by a bounded
optimizer on float64 kinematics.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .compile import fk64
from .kinematics import Kinematics
from .model import Mechanism

SAMPLE_CHUNK = 1 << 18
TOP_K = 4  # best samples refined per extreme
VIEW_BINS = 400  # pixels across a side or top view


@dataclass(frozen=True)
class Extreme:
    """An extreme of the workspace: its value (m) and the joint values (SI) that reach it."""

    value: float
    q: tuple[float, ...]
    sampled: float  # the best sample's value, before refinement


@dataclass(frozen=True)
class Workspace:
    """What a sweep found (SI units); grids are boolean occupancy, ``origin`` their lower corner."""

    mechanism: str
    samples: int
    method: str
    seed: int
    reach: Extreme | None  # horizontal distance J1 axis -> wrist centre (None below five axes)
    flange_reach: Extreme
    wrist_low: Extreme | None
    wrist_high: Extreme | None
    flange_low: Extreme
    flange_high: Extreme
    resolution: float
    origin: tuple[float, float, float]
    wrist_voxels: np.ndarray | None = field(repr=False, compare=False)
    flange_voxels: np.ndarray = field(repr=False, compare=False)
    side: np.ndarray | None = field(repr=False, compare=False)  # (x, z) counts at J1 = 0, wrist centre
    top: np.ndarray | None = field(repr=False, compare=False)  # (x, y) counts, wrist centre
    view_extent: tuple[float, float, float, float] = (0, 0, 0, 0)  # half-width, z0, z1 of the views

    def report(self) -> dict:
        """A JSON-ready summary (metres, radians, snake_case)."""
        def ext(e):
            return None if e is None else {"value": e.value, "q": list(e.q), "best_sample": e.sampled}

        return {
            "mechanism": self.mechanism, "samples": self.samples, "method": self.method, "seed": self.seed,
            "reach": ext(self.reach), "flange_reach": ext(self.flange_reach),
            "wrist_lowest": ext(self.wrist_low), "wrist_highest": ext(self.wrist_high),
            "flange_lowest": ext(self.flange_low), "flange_highest": ext(self.flange_high),
            "voxel_resolution": self.resolution, "voxel_origin": list(self.origin),
            "wrist_voxels_occupied": None if self.wrist_voxels is None else int(self.wrist_voxels.sum()),
            "flange_voxels_occupied": int(self.flange_voxels.sum()),
        }


# -- sampling -----------------------------------------------------------------------------------------


def sample_chunks(lower: np.ndarray, upper: np.ndarray, samples: int, method: str = "random", seed: int = 0,
                  chunk: int = SAMPLE_CHUNK):
    """Yield float64 joint-value chunks covering the box [lower, upper]."""
    dof = len(lower)
    span = upper - lower
    if method == "random":
        for k, lo in enumerate(range(0, samples, chunk)):
            rng = np.random.default_rng([seed, k])  # depends on (seed, chunk) only
            yield lower + span * rng.random((min(chunk, samples - lo), dof))
    elif method == "sobol":
        from scipy.stats import qmc

        engine = qmc.Sobol(dof, scramble=True, seed=seed)
        for lo in range(0, samples, chunk):
            with warnings.catch_warnings():  # balance is best for powers of two; any count is valid
                warnings.simplefilter("ignore", UserWarning)
                block = engine.random(min(chunk, samples - lo))
            yield lower + span * block
    elif method == "grid":
        per = max(2, int(round(samples ** (1.0 / dof))))
        axes = [np.linspace(a, b, per) for a, b in zip(lower, upper)]
        total = per ** dof
        for lo in range(0, total, chunk):
            idx = np.unravel_index(np.arange(lo, min(lo + chunk, total)), (per,) * dof)
            yield np.stack([ax[i] for ax, i in zip(axes, idx)], axis=1)
    else:
        raise ValueError(f"unknown sampling method '{method}' (random, sobol or grid)")


# -- float64 geometry used to refine extremes ---------------------------------------------------------


class _Exact:
    """Float64 wrist centre, flange and J1-axis distance for single configurations."""

    def __init__(self, kin: Kinematics):
        self.kin, self.tree, self.mech = kin, kin.tree, kin.mech
        j1 = self.mech.active_joints[0]
        self.j1_point, self.j1_axis = np.asarray(j1.point1, float), np.asarray(j1.axis, float)
        self.flange_link, self.flange_offset = kin.flange_frame()
        self.wrist = kin.wrist_axes() if kin.dof >= 5 else None

    def points(self, q: np.ndarray) -> tuple[np.ndarray | None, np.ndarray]:
        poses = fk64(self.tree, q)
        flange = (poses[:, self.flange_link] @ self.flange_offset)[:, :3, 3]
        if self.wrist is None:
            return None, flange
        (l4, p4, a4), (l5, p5, a5) = self.wrist
        t4, t5 = poses[:, l4], poses[:, l5]
        return nearest_on_line5(t4[:, :3, :3] @ p4 + t4[:, :3, 3], t4[:, :3, :3] @ a4,
                                t5[:, :3, :3] @ p5 + t5[:, :3, 3], t5[:, :3, :3] @ a5), flange

    def radial(self, pts: np.ndarray) -> np.ndarray:
        return radial_distance(pts, self.j1_point, self.j1_axis)


def nearest_on_line5(p4, d4, p5, d5):
    """The point of line 5 nearest line 4, vectorized in float64 (the generated wrist kernels
    compute the same in float32)."""
    w = p5 - p4
    b = np.einsum("ij,ij->i", d4, d5)
    den = 1.0 - b * b
    s = np.where(den < 1e-12, 0.0, (b * np.einsum("ij,ij->i", w, d4) - np.einsum("ij,ij->i", w, d5)) /
                 np.where(den < 1e-12, 1.0, den))
    return p5 + s[:, None] * d5


def radial_distance(pts: np.ndarray, point: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """Distance of points from a line (the J1 axis): the 'horizontal' distance of datasheets."""
    rel = pts - point
    return np.linalg.norm(rel - np.outer(rel @ axis, axis), axis=1)


def _refine(fun: Callable[[np.ndarray], float], starts: np.ndarray, lower, upper) -> tuple[float, np.ndarray]:
    """Maximize ``fun`` from several starts within the bounds (L-BFGS-B); best value and point."""
    from scipy.optimize import minimize

    best_v, best_q = -np.inf, None
    bounds = list(zip(lower, upper))
    for q0 in starts:
        res = minimize(lambda q: -fun(q), q0, method="L-BFGS-B", bounds=bounds,
                       options={"ftol": 1e-15, "gtol": 1e-12, "maxiter": 500})
        for v, q in ((-res.fun, res.x), (fun(q0), q0)):
            if v > best_v:
                best_v, best_q = float(v), np.asarray(q, float)
    return best_v, best_q


class _TopK:
    """The k largest values seen and their joint values, over chunks."""

    def __init__(self, k: int, dof: int):
        self.v = np.full(0, -np.inf)
        self.q = np.zeros((0, dof))
        self.k = k

    def add(self, values: np.ndarray, q: np.ndarray) -> None:
        take = np.argsort(values)[-self.k:]
        v = np.concatenate([self.v, values[take]])
        qq = np.concatenate([self.q, q[take]])
        keep = np.argsort(v, kind="stable")[-self.k:]
        self.v, self.q = v[keep], qq[keep]


# -- the sweep ----------------------------------------------------------------------------------------


def workspace(mech: Mechanism, samples: int = 100_000, seed: int = 0, method: str = "random",
              resolution: float = 0.025, kinematics: Kinematics | None = None,
              progress: Callable[[int, int], None] | None = None) -> Workspace:
    """Sweep ``samples`` joint configurations within the limits and measure the workspace."""
    if samples < 1:
        raise ValueError("samples must be at least 1")
    kin = kinematics or Kinematics(mech)
    exact = _Exact(kin)
    lower, upper = kin.tree.lower, kin.tree.upper
    if not (np.all(np.isfinite(lower)) and np.all(np.isfinite(upper))):
        raise ValueError("every active joint needs finite limits for a sweep")
    has_wrist = exact.wrist is not None
    radius = _radius(exact, lower, upper, seed)
    base = exact.j1_point
    origin = base - radius
    dims = (int(math.ceil(2 * radius / resolution)) + 1,) * 3
    wrist_vox = np.zeros(dims, bool) if has_wrist else None
    flange_vox = np.zeros(dims, bool)
    top = np.zeros((VIEW_BINS, VIEW_BINS), np.int64) if has_wrist else None
    side = np.zeros((VIEW_BINS, VIEW_BINS), np.int64) if has_wrist else None
    tops = {name: _TopK(TOP_K, kin.dof) for name in ("reach", "freach", "wlow", "whigh", "flow", "fhigh")}
    total = samples if method != "grid" else max(2, int(round(samples ** (1.0 / kin.dof)))) ** kin.dof
    done = 0
    for q in sample_chunks(lower, upper, samples, method, seed):
        wrist, flange = kin.wrist_flange(q, wrist=has_wrist)
        tops["freach"].add(exact.radial(flange.astype(float)), q)
        tops["flow"].add(-flange[:, 2].astype(float), q)
        tops["fhigh"].add(flange[:, 2].astype(float), q)
        _mark(flange_vox, flange, origin, resolution)
        if has_wrist:
            w = wrist.astype(float)
            tops["reach"].add(exact.radial(w), q)
            tops["wlow"].add(-w[:, 2], q)
            tops["whigh"].add(w[:, 2], q)
            _mark(wrist_vox, wrist, origin, resolution)
            top += np.histogram2d(w[:, 0], w[:, 1], bins=VIEW_BINS, range=[[base[0] - radius, base[0] + radius],
                                                                           [base[1] - radius, base[1] + radius]])[0].astype(np.int64)
            q0 = q.copy()
            q0[:, 0] = 0.0  # the side view: the plane of J1 = 0
            ws, _ = kin.wrist_flange(q0)
            side += np.histogram2d(ws[:, 0], ws[:, 2], bins=VIEW_BINS, range=[[base[0] - radius, base[0] + radius],
                                                                             [base[2] - radius, base[2] + radius]])[0].astype(np.int64)
        done += len(q)
        if progress:
            progress(done, total)

    def refined(name: str, fun: Callable[[np.ndarray], float], sign: float = 1.0) -> Extreme:
        t = tops[name]
        value, q = _refine(fun, t.q[::-1], lower, upper)
        return Extreme(value=sign * value, q=tuple(float(v) for v in q), sampled=sign * float(t.v[-1]))

    def wrist_at(q):
        return exact.points(q[None])[0][0]

    def flange_at(q):
        return exact.points(q[None])[1][0]

    return Workspace(
        mechanism=mech.name, samples=done, method=method, seed=seed,
        reach=refined("reach", lambda q: exact.radial(wrist_at(q)[None])[0]) if has_wrist else None,
        flange_reach=refined("freach", lambda q: exact.radial(flange_at(q)[None])[0]),
        wrist_low=refined("wlow", lambda q: -wrist_at(q)[2], -1.0) if has_wrist else None,
        wrist_high=refined("whigh", lambda q: wrist_at(q)[2]) if has_wrist else None,
        flange_low=refined("flow", lambda q: -flange_at(q)[2], -1.0),
        flange_high=refined("fhigh", lambda q: flange_at(q)[2]),
        resolution=resolution, origin=tuple(float(v) for v in origin),
        wrist_voxels=wrist_vox, flange_voxels=flange_vox, side=side, top=top,
        view_extent=(float(radius), float(base[0]), float(base[1]), float(base[2])),
    )


def _radius(exact: _Exact, lower: np.ndarray, upper: np.ndarray, seed: int) -> float:
    """The largest distance of a wrist centre or flange from the J1 axis point, found like any other
    extreme (pilot samples, then refined), plus a margin: the grids and views span it exactly."""
    q = next(sample_chunks(lower, upper, 4096, "random", seed))
    wrist, flange = exact.points(q)
    best = 0.0
    for which, pts in ((0, wrist), (1, flange)):
        if pts is None:
            continue
        d = np.linalg.norm(pts - exact.j1_point, axis=1)
        starts = q[np.argsort(d)[-4:]]
        value, _ = _refine(lambda x: float(np.linalg.norm(exact.points(x[None])[which][0] - exact.j1_point)),
                           starts, lower, upper)
        best = max(best, value)
    return best * 1.02 + 0.01


def _mark(grid: np.ndarray, pts: np.ndarray, origin: np.ndarray, resolution: float) -> None:
    idx = np.floor((pts - origin) / resolution).astype(np.int64)
    inside = np.all((idx >= 0) & (idx < np.array(grid.shape)), axis=1)
    idx = idx[inside]
    grid.reshape(-1)[np.ravel_multi_index(idx.T, grid.shape)] = True


def save_voxels(ws: Workspace, path) -> None:
    """The occupancy grids as .npz (written to a temporary file, then renamed)."""
    import io

    from .write import atomic_write

    buf = io.BytesIO()
    arrays = {"flange": ws.flange_voxels, "origin": np.array(ws.origin), "resolution": np.array(ws.resolution)}
    if ws.wrist_voxels is not None:
        arrays["wrist"] = ws.wrist_voxels
    np.savez_compressed(buf, **arrays)
    atomic_write(path, buf.getvalue())
