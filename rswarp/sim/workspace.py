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

from ..errors import InputError, model_error
from ..kinematics.kinematics import Kinematics
from ..options import checked
from ..rsxml.model import Mechanism
from .engine import Job, run_batch

SAMPLE_CHUNK = 1 << 18
TOP_K = 4  # best samples refined per extreme
UNREACHABLE = 1e9  # metres: the penalty the optimizer sees past a dead point
VIEW_BINS = 400  # pixels across a side or top view
MAX_VOXELS = 1 << 26  # cells per occupancy grid (64 MiB each as booleans): memory is bounded by this


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
    side: np.ndarray = field(repr=False, compare=False)  # (x, z) counts at J1 = 0: wrist centre, else flange
    top: np.ndarray = field(repr=False, compare=False)  # (x, y) counts: wrist centre, else flange
    view_extent: tuple[float, float, float, float] = (0, 0, 0, 0)  # half-width, z0, z1 of the views
    unreachable: int = 0  # samples skipped: a loop cannot close there (past a four-bar's dead point)

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
            "flange_voxels_occupied": int(self.flange_voxels.sum()), "unreachable_samples": self.unreachable,
        }


# -- sampling -----------------------------------------------------------------------------------------


METHODS = ("random", "sobol", "grid")


def sample_count(samples: int, method: str, dof: int) -> int:
    """How many configurations a sweep of ``samples`` visits (a grid rounds to whole points per axis)."""
    return grid_points(samples, dof) ** dof if method == "grid" else samples


def chunk_count(samples: int, method: str, dof: int, chunk: int = SAMPLE_CHUNK) -> int:
    return -(-sample_count(samples, method, dof) // chunk)


def sample_chunks(lower: np.ndarray, upper: np.ndarray, samples: int, method: str = "random", seed: int = 0,
                  chunk: int = SAMPLE_CHUNK, chunks: range | None = None):
    """Yield float64 joint-value chunks in the box [lower, upper]: all of them, or those numbered
    ``chunks``. Chunk k holds samples ``k * chunk`` on and depends only on the method, the seed and
    k, so tasks anywhere draw the samples one run would."""
    dof = len(lower)
    span = upper - lower
    chunks = range(max(1, chunk_count(samples, method, dof, chunk))) if chunks is None else chunks
    if method == "random":
        for k in chunks:
            rng = np.random.default_rng([seed, k])
            yield lower + span * rng.random((min(chunk, samples - k * chunk), dof))
    elif method == "sobol":
        from scipy.stats import qmc

        engine = qmc.Sobol(dof, scramble=True, seed=seed)
        if chunks.start:  # (scipy refuses a skip of 0)
            engine.fast_forward(chunks.start * chunk)
        for k in chunks:
            with warnings.catch_warnings():  # balance is best for powers of two; any count is valid
                warnings.simplefilter("ignore", UserWarning)
                yield lower + span * engine.random(min(chunk, samples - k * chunk))
    elif method == "grid":  # values from indices: memory is one chunk, whatever the points per axis
        per = grid_points(samples, dof)
        for k in chunks:
            idx = np.unravel_index(np.arange(k * chunk, min((k + 1) * chunk, per ** dof)), (per,) * dof)
            yield lower + span * (np.stack(idx, axis=1) / (per - 1))
    else:
        raise ValueError(f"unknown sampling method '{method}' (random, sobol or grid)")


def grid_points(samples: int, dof: int) -> int:
    """Points per axis of a grid of about ``samples`` configurations (at least 2)."""
    return max(2, int(round(samples ** (1.0 / dof))))


# -- float64 geometry used to refine extremes ---------------------------------------------------------


class Float64Points:
    """Float64 wrist centre, flange and J1-axis distance: the same device code as the batches, in
    float64 (``Kinematics.wrist_flange64``), so an optimizer can refine extremes to the true ones."""

    def __init__(self, kin: Kinematics):
        self.kin = kin
        j1 = kin.graph.first_axis
        self.j1_point, self.j1_axis = np.asarray(j1.point1, float), np.asarray(j1.axis, float)
        self.has_wrist = kin.graph.wrist_joints is not None

    def points(self, q: np.ndarray) -> tuple[np.ndarray | None, np.ndarray]:
        return self.kin.wrist_flange64(np.atleast_2d(q))

    def radial(self, pts: np.ndarray) -> np.ndarray:
        return radial_distance(pts, self.j1_point, self.j1_axis)


def radial_distance(pts: np.ndarray, point: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """Distance of points from a line (the J1 axis): the 'horizontal' distance of datasheets."""
    rel = pts - point
    return np.linalg.norm(rel - np.outer(rel @ axis, axis), axis=1)


def _refine(fun: Callable[[np.ndarray], float], starts: np.ndarray, lower, upper) -> tuple[float, np.ndarray]:
    """Maximize ``fun`` from several starts within the bounds (L-BFGS-B); best value and point."""
    from scipy.optimize import minimize

    best_v, best_q = -np.inf, None
    bounds = list(zip(lower, upper))

    def value(q):  # past a dead point fun is NaN: far worse than any reachable value
        v = fun(q)
        return v if np.isfinite(v) else -UNREACHABLE

    for q0 in starts:
        res = minimize(lambda q: -value(q), q0, method="L-BFGS-B", bounds=bounds,
                       options={"ftol": 1e-15, "gtol": 1e-12, "maxiter": 500})
        for v, q in ((-res.fun, res.x), (value(q0), q0)):
            if v > best_v:
                best_v, best_q = float(v), np.asarray(q, float)
    return best_v, best_q


class TopK:
    """The k largest values seen, their sample indices and joint values. Of equal values the
    earliest sample wins, so the k kept are the same however the samples were split and merged."""

    def __init__(self, k: int, dof: int):
        self.v = np.full(0, -np.inf)
        self.i = np.zeros(0, np.int64)
        self.q = np.zeros((0, dof))
        self.k = k

    def add(self, values: np.ndarray, q: np.ndarray, index: np.ndarray) -> None:
        if len(values) > self.k:  # the k largest, and every sample tied with the k-th
            take = np.nonzero(values >= np.partition(values, -self.k)[-self.k])[0]
            values, q, index = values[take], q[take], index[take]
        self._keep(np.concatenate([self.v, values]), np.concatenate([self.i, index]), np.concatenate([self.q, q]))

    def merge(self, other: "TopK") -> None:
        self._keep(np.concatenate([self.v, other.v]), np.concatenate([self.i, other.i]),
                   np.concatenate([self.q, other.q]))

    def _keep(self, v: np.ndarray, i: np.ndarray, q: np.ndarray) -> None:
        keep = np.lexsort((-i, v))[-self.k:]  # ascending: the best value last
        self.v, self.i, self.q = v[keep], i[keep], q[keep]


@dataclass
class BestSamples:
    """The best samples of each extreme a sweep measures (lows are kept as the highest negatives)."""

    reach: TopK
    flange_reach: TopK
    wrist_low: TopK
    wrist_high: TopK
    flange_low: TopK
    flange_high: TopK

    @classmethod
    def empty(cls, dof: int) -> "BestSamples":
        return cls(*(TopK(TOP_K, dof) for _ in range(6)))

    def add(self, exact: Float64Points, q: np.ndarray, index: np.ndarray, wrist: np.ndarray | None,
            flange: np.ndarray) -> None:
        f = flange.astype(float)
        self.flange_reach.add(exact.radial(f), q, index)
        self.flange_low.add(-f[:, 2], q, index)
        self.flange_high.add(f[:, 2], q, index)
        if wrist is not None:
            w = wrist.astype(float)
            self.reach.add(exact.radial(w), q, index)
            self.wrist_low.add(-w[:, 2], q, index)
            self.wrist_high.add(w[:, 2], q, index)

    def merge(self, other: "BestSamples") -> None:
        for name in self.__dataclass_fields__:
            getattr(self, name).merge(getattr(other, name))


@dataclass
class Grids:
    """Voxel occupancy and the side and top views, filled chunk by chunk."""

    origin: np.ndarray
    resolution: float
    radius: float
    base: np.ndarray
    wrist: np.ndarray | None
    flange: np.ndarray
    side: np.ndarray
    top: np.ndarray

    @classmethod
    def empty(cls, base: np.ndarray, radius: float, resolution: float, has_wrist: bool) -> "Grids":
        dims = (voxels_per_side(radius, resolution),) * 3
        views = (np.zeros((VIEW_BINS, VIEW_BINS), np.int64) for _ in range(2))
        return cls(base - radius, resolution, radius, base, np.zeros(dims, bool) if has_wrist else None,
                   np.zeros(dims, bool), *views)

    def add(self, wrist: np.ndarray | None, flange: np.ndarray, side: np.ndarray) -> None:
        """One chunk's points; the views show the wrist centre, or the flange where there is none
        (``side``: the same point with J1 at 0)."""
        _mark(self.flange, flange, self.origin, self.resolution)
        if wrist is not None:
            _mark(self.wrist, wrist, self.origin, self.resolution)
        shown = flange if wrist is None else wrist
        self.top += self._histogram(shown[:, 0], shown[:, 1], 0, 1)
        self.side += self._histogram(side[:, 0], side[:, 2], 0, 2)

    def merge(self, other: "Grids") -> None:
        """Occupancy ORs, view counts add: exact in any order."""
        self.flange |= other.flange
        if self.wrist is not None:
            self.wrist |= other.wrist
        self.side += other.side
        self.top += other.top

    def _histogram(self, a: np.ndarray, b: np.ndarray, ia: int, ib: int) -> np.ndarray:
        r, c = self.radius, self.base
        box = [[c[ia] - r, c[ia] + r], [c[ib] - r, c[ib] + r]]
        return np.histogram2d(a, b, bins=VIEW_BINS, range=box)[0].astype(np.int64)


def voxels_per_side(radius: float, resolution: float) -> int:
    """Cells along each side of the cubic grid that spans ``radius`` around the base; more cells
    in all than ``MAX_VOXELS`` is an ``InputError`` naming the finest resolution that fits."""
    side = int(math.ceil(2 * radius / resolution)) + 1
    if side ** 3 > MAX_VOXELS:
        finest = 2 * radius / (round(MAX_VOXELS ** (1 / 3)) - 1)
        raise InputError(f"a {resolution * 1000:g} mm voxel grid over this robot's {radius:.3g} m reach has "
                         f"{side ** 3:.3g} cells, over the cap of {MAX_VOXELS:.3g}; use a resolution of "
                         f"{math.ceil(finest * 1000):g} mm or coarser")
    return side


# -- the sweep ----------------------------------------------------------------------------------------


@dataclass
class SweepTally:
    """What the samples of some chunks gave: the best samples, the grids and the counts. Tallies
    merge exactly in any order, so a sweep cut into tasks gives the numbers of one run."""

    best: BestSamples
    grids: Grids
    done: int = 0
    skipped: int = 0

    def merge(self, other: "SweepTally") -> None:
        self.best.merge(other.best)
        self.grids.merge(other.grids)
        self.done += other.done
        self.skipped += other.skipped


@dataclass(frozen=True)
class SweepJob(Job):
    """What every task of a sweep needs to draw and bin its samples the way one run would; its
    items are chunks of samples."""

    name = "sweep"
    unit = "sample"

    lower: np.ndarray
    upper: np.ndarray
    samples: int
    method: str
    seed: int
    radius: float
    resolution: float
    has_wrist: bool
    chunk: int  # samples per chunk: with the seed, it decides which samples a sweep draws
    base: np.ndarray  # the J1 axis point the grids are centred on

    @property
    def count(self) -> int:
        return chunk_count(self.samples, self.method, len(self.lower), self.chunk)

    @property
    def total(self) -> int:
        return sample_count(self.samples, self.method, len(self.lower))

    def task_items(self, cluster) -> int:
        return max(1, cluster.task_samples // self.chunk)

    def size(self, span: range) -> float:
        return float(max(0, min(span.stop * self.chunk, self.total) - span.start * self.chunk))

    def local_spans(self) -> list[range]:
        return [range(k, k + 1) for k in range(self.count)]

    def tools_key(self) -> tuple:
        return ("kinematics",)

    def tools(self, model, device: str, threads: int | None) -> Kinematics:
        return Kinematics(model.mech, device=device, threads=threads)

    def empty(self) -> SweepTally:
        return SweepTally(BestSamples.empty(len(self.lower)),
                          Grids.empty(self.base, self.radius, self.resolution, self.has_wrist))

    def run(self, kin: Kinematics, tally: SweepTally, span: range, tick) -> None:
        """The samples of chunks ``span`` into ``tally``."""
        exact = Float64Points(kin)
        for k, q in zip(span, sample_chunks(self.lower, self.upper, self.samples, self.method, self.seed,
                                            self.chunk, span)):
            wrist, flange = kin.wrist_flange(q, wrist=self.has_wrist)
            tally.done += len(q)
            index = k * self.chunk + np.arange(len(q))
            ok = np.isfinite(flange).all(axis=1)  # NaN: a loop cannot close there; skipped and counted
            if not ok.all():
                tally.skipped += int((~ok).sum())
                q, index, flange, wrist = q[ok], index[ok], flange[ok], None if wrist is None else wrist[ok]
            if len(q):
                tally.best.add(exact, q, index, wrist, flange)
                q0 = q.copy()
                q0[:, 0] = 0.0  # the side view: the plane of J1 = 0
                w0, f0 = kin.wrist_flange(q0, wrist=self.has_wrist)
                tally.grids.add(wrist, flange, f0 if w0 is None else w0)


def workspace(mech: Mechanism, samples: int = 100_000, seed: int = 0, method: str = "random",
              resolution: float = 0.025, kinematics: Kinematics | None = None,
              progress: Callable[[float, float], None] | None = None, cluster=None) -> Workspace:
    """Sweep ``samples`` joint configurations within the limits and measure the workspace;
    ``cluster`` (a ``rswarp.Cluster`` or a Ray address) runs the samples as tasks on Ray."""
    checked("samples", samples)
    checked("resolution", resolution)
    if method not in METHODS:
        raise InputError(f"unknown sampling method '{method}' (random, sobol or grid)")
    kin = kinematics or Kinematics(mech)
    if kin.dof == 0:
        raise model_error(mech, f"mechanism '{mech.name}' has no active joints: there is no workspace to sweep")
    kin.flange_frame()  # a mechanism without a flange has nothing to measure: a clear error
    exact = Float64Points(kin)
    lower, upper = mech.bounds()
    if not (np.all(np.isfinite(lower)) and np.all(np.isfinite(upper))):
        raise InputError("every active joint needs finite limits for a sweep")
    job = SweepJob(lower, upper, samples, method, seed, _radius(exact, lower, upper, seed), resolution,
                   exact.has_wrist, SAMPLE_CHUNK, exact.j1_point)
    tally = run_batch(job, mech, tools=kin, cluster=cluster, progress=progress)
    if tally.skipped == tally.done:
        raise model_error(mech, f"none of the {tally.done} samples closes the loops of '{mech.name}': every one "
                                "lies past a dead point")
    return _result(mech, exact, tally, method, seed, lower, upper)


def _result(mech, exact: Float64Points, tally: SweepTally, method: str, seed: int, lower, upper) -> Workspace:
    """The refined extremes and the grids as a Workspace."""
    best, grids = tally.best, tally.grids

    def refined(top: TopK, which: int, fun, sign: float = 1.0) -> Extreme:
        value, q = _refine(lambda x: sign * fun(exact.points(x)[which][0]), top.q[::-1], lower, upper)
        return Extreme(value=sign * value, q=tuple(float(v) for v in q), sampled=sign * float(top.v[-1]))

    def radial(p):
        return float(exact.radial(p[None])[0])

    w = exact.has_wrist
    return Workspace(
        mechanism=mech.name, samples=tally.done, method=method, seed=seed, unreachable=tally.skipped,
        reach=refined(best.reach, 0, radial) if w else None,
        flange_reach=refined(best.flange_reach, 1, radial),
        wrist_low=refined(best.wrist_low, 0, lambda p: p[2], -1.0) if w else None,
        wrist_high=refined(best.wrist_high, 0, lambda p: p[2]) if w else None,
        flange_low=refined(best.flange_low, 1, lambda p: p[2], -1.0),
        flange_high=refined(best.flange_high, 1, lambda p: p[2]),
        resolution=grids.resolution, origin=tuple(float(v) for v in grids.origin),
        wrist_voxels=grids.wrist, flange_voxels=grids.flange, side=grids.side, top=grids.top,
        view_extent=(float(grids.radius), *(float(v) for v in grids.base)),
    )


def _radius(exact: Float64Points, lower: np.ndarray, upper: np.ndarray, seed: int) -> float:
    """The largest distance of a wrist centre or flange from the J1 axis point, found like any other
    extreme (pilot samples, then refined), plus a margin: the grids and views span it exactly."""
    q = next(sample_chunks(lower, upper, 4096, "random", seed))
    wrist, flange = exact.points(q)
    best = 0.0
    for which, pts in ((0, wrist), (1, flange)):
        if pts is None:
            continue
        d = np.nan_to_num(np.linalg.norm(pts - exact.j1_point, axis=1), nan=-np.inf)
        starts = q[np.argsort(d)[-4:]]
        value, _ = _refine(lambda x, which=which: float(np.linalg.norm(exact.points(x)[which][0] - exact.j1_point)),
                           starts, lower, upper)
        best = max(best, value)
    return best * 1.02 + 0.01


def _mark(grid: np.ndarray, pts: np.ndarray, origin: np.ndarray, resolution: float) -> None:
    idx = np.floor((pts - origin) / resolution).astype(np.int64)
    inside = np.all((idx >= 0) & (idx < np.array(grid.shape)), axis=1)
    idx = idx[inside]
    grid.reshape(-1)[np.ravel_multi_index(idx.T, grid.shape)] = True
