"""What a cable run reports, and its tally: per environment, the extremes of each quantity and
when and where they happened; over time, their spread across environments (``Series``). Kept as
running extremes so memory grows with environments plus frames, never with their product."""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from ..kernels.cable import BEND, BEND_AT, NOT_FINITE, RUNAWAY, RUNNING, TENSION, TWIST
from .cable import MAX_SPEED, CableModel, CableState

UNMEASURED = 1.0e29  # the kernel's "nothing within reach" (BIG) reads as +inf
MAX_RECORDED = 20_000  # frames kept for playback; longer runs keep every k-th frame


@dataclass(frozen=True)
class Series:
    """One quantity over time across environments: least, median and greatest per frame."""

    low: np.ndarray
    median: np.ndarray
    high: np.ndarray

    @classmethod
    def of(cls, rows: list[tuple[float, float, float]]) -> "Series":
        a = np.asarray(rows, np.float64).reshape(len(rows), 3)
        return cls(a[:, 0], a[:, 1], a[:, 2])


def spread(values: np.ndarray) -> tuple[float, float, float]:
    """(least, median, greatest) of one frame's finite values; NaN when none is."""
    v = values[np.isfinite(values)]
    if len(v) == 0:
        return (np.nan, np.nan, np.nan)
    return (float(v.min()), float(np.median(v)), float(v.max()))


@dataclass(frozen=True)
class CableResult:
    """One cable over the run, per environment (arrays of length envs) and over time (``Series``
    of frames). Times in seconds of the trajectory, lengths in metres, arc lengths from the
    cable's first control point; NaN where a quantity never occurred."""

    name: str
    length: float
    radius: float
    allowed_bend_radius: float
    torsion_stiffness: float  # GJ, N m^2
    links: tuple[str, ...]  # clearance slots: the links, then "floor"
    peak_tension: np.ndarray
    peak_tension_time: np.ndarray
    min_bend_radius: np.ndarray
    min_bend_time: np.ndarray
    min_bend_at: np.ndarray
    clearance: np.ndarray  # (envs, slots): least clearance; +inf where never within reach
    clearance_time: np.ndarray
    clearance_at: np.ndarray
    contact_time: np.ndarray  # (envs, slots): first contact
    contact_at: np.ndarray
    stretch: np.ndarray  # greatest straight distance between consecutive attachments / their cable length
    stretch_time: np.ndarray
    max_twist: np.ndarray  # rad, greatest |twist| between clamped ends
    status: np.ndarray  # "ok" or why the environment stopped
    failed_time: np.ndarray
    final_points: np.ndarray  # (envs, N, 3)
    tension: Series = field(repr=False)
    bend: Series = field(repr=False)
    gap: Series = field(repr=False)  # least clearance to anything, per frame
    recorded: np.ndarray = field(repr=False)  # (kept frames, N, 3) of options.record
    stride: int = 1  # recorded keeps every stride-th frame

    @property
    def envs(self) -> int:
        return len(self.peak_tension)

    @property
    def too_tight(self) -> np.ndarray:
        return self.min_bend_radius < self.allowed_bend_radius

    @property
    def touching(self) -> np.ndarray:
        """(envs,) the environments where the cable met a link or the floor."""
        return np.isfinite(self.contact_time).any(axis=1)


SERIES = ("tension", "bend", "gap")
# CableResult's fields with one row per environment (the others describe the cable or the run)
PER_ENV = ("peak_tension", "peak_tension_time", "min_bend_radius", "min_bend_time", "min_bend_at", "clearance",
           "clearance_time", "clearance_at", "contact_time", "contact_at", "stretch", "stretch_time", "max_twist",
           "status", "failed_time", "final_points")


class Tally:
    """Running extremes of one cable's environments, fed each frame's ``CableState``; per frame the
    spread of each of SERIES across them, or with ``values`` every environment's value (frames, 3,
    envs) float32, which holds the kernel's float32 results exactly: a task of a cluster run keeps
    these, and the driver takes the spread of all environments."""

    def __init__(self, model: CableModel, envs: int, slots: int, frames: int, record: int, values: bool = False):
        self.model = model
        self.arc = np.append(model.arc, np.nan)  # index -1 (none) reads NaN
        anchors = [k for k in range(model.cable.start, model.cable.stop) if model.link[k] >= 0]
        self.pairs = np.array(list(zip(anchors[:-1], anchors[1:])), np.int64).reshape(-1, 2)
        self.pair_length = model.arc[self.pairs[:, 1]] - model.arc[self.pairs[:, 0]]
        nan = lambda *shape: np.full(shape, np.nan)  # noqa: E731
        self.peak, self.peak_t = np.zeros(envs), nan(envs)
        self.bend, self.bend_t, self.bend_at = np.full(envs, np.inf), nan(envs), nan(envs)
        self.clear, self.clear_t, self.clear_at = np.full((envs, slots), np.inf), nan(envs, slots), nan(envs, slots)
        self.contact_t, self.contact_at = nan(envs, slots), nan(envs, slots)
        self.stretch, self.stretch_t = np.zeros(envs), nan(envs)
        self.twist_prev, self.twist, self.max_twist = np.zeros(envs), np.zeros(envs), np.zeros(envs)
        self.failed_t, self.failed_why = nan(envs), np.zeros(envs, np.int32)
        self.series: dict[str, list] = {key: [] for key in SERIES}
        self.values = np.empty((frames, len(SERIES), envs), np.float32) if values else None
        self.record, self.stride = record, max(1, -(-frames // MAX_RECORDED))
        self.recorded: list[np.ndarray] = []
        self.frame = 0

    def start(self, state: CableState) -> None:
        """The twist at the end of settling: its turns are counted from here on."""
        self.twist_prev = state.stats[:, TWIST].astype(np.float64)
        self.twist = self.twist_prev.copy()

    def add(self, state: CableState, t: float) -> None:
        live = state.status == RUNNING
        gone = ~live & np.isnan(self.failed_t)
        self.failed_t[gone], self.failed_why[gone] = t, state.status[gone]
        stats = state.stats.astype(np.float64)
        tension = np.where(live, stats[:, TENSION], np.nan)
        _higher(self.peak, tension, t, self.peak_t)
        bend = np.where(live, stats[:, BEND], np.nan)
        bend[bend > UNMEASURED] = np.inf
        where = self.arc[np.where(stats[:, BEND_AT] >= 0, stats[:, BEND_AT], -1).astype(np.int64)]
        _lower(self.bend, bend, t, self.bend_t, self.bend_at, where)
        gap = self._clearances(state, live, t)
        self._stretch(state, live, t)
        self._twist(stats[:, TWIST], live)
        if self.values is not None:
            self.values[self.frame] = (tension, bend, gap)
        else:
            for key, values in zip(SERIES, (tension, bend, gap)):
                self.series[key].append(spread(values))
        if self.record >= 0 and self.frame % self.stride == 0:
            self.recorded.append(state.x[min(self.record, len(state.x) - 1), self.model.cable].copy())
        self.frame += 1

    def _clearances(self, state: CableState, live: np.ndarray, t: float) -> np.ndarray:
        """Least clearance per link and the floor; the first contact. Returns each environment's
        least clearance to anything this frame."""
        c = np.where(live[:, None], state.clear.astype(np.float64), np.nan)
        c[c > UNMEASURED] = np.inf
        where = self.arc[state.at.astype(np.int64)]
        _lower(self.clear, c, t, self.clear_t, self.clear_at, where)
        first = (c <= 0) & np.isnan(self.contact_t)
        self.contact_t[first], self.contact_at[first] = t, where[first]
        return c.min(axis=1)

    def _stretch(self, state: CableState, live: np.ndarray, t: float) -> None:
        """The straight distance between consecutive attachments over the cable between them."""
        if not len(self.pairs):
            return
        x = state.x.astype(np.float64)
        d = np.linalg.norm(x[:, self.pairs[:, 1]] - x[:, self.pairs[:, 0]], axis=2) / self.pair_length
        _higher(self.stretch, np.where(live, d.max(axis=1), np.nan), t, self.stretch_t)

    def _twist(self, raw: np.ndarray, live: np.ndarray) -> None:
        """Whole turns counted: each frame's change is taken in (-pi, pi]."""
        step = (raw - self.twist_prev + np.pi) % (2 * np.pi) - np.pi
        self.twist = np.where(live, self.twist + step, self.twist)
        self.twist_prev = np.where(live, raw, self.twist_prev)
        self.max_twist = np.maximum(self.max_twist, np.abs(self.twist))

    def result(self, allowed: float, links: tuple[str, ...], state: CableState) -> CableResult:
        why = {NOT_FINITE: "positions became NaN or infinite",
               RUNAWAY: f"a particle passed {MAX_SPEED:g} m/s (runaway energy)"}
        status = np.array(["ok" if np.isnan(t) else f"stopped at t = {t:.3f} s: {why.get(int(k), 'failed')}"
                           for t, k in zip(self.failed_t, self.failed_why)], dtype=object)
        model = self.model
        own = state.x[:, model.cable].astype(np.float64)
        recorded = np.asarray(self.recorded, np.float64).reshape(-1, own.shape[1], 3)
        return CableResult(
            model.name, model.length, model.radius, float(allowed),
            model.torsion, links, self.peak, self.peak_t, self.bend, self.bend_t, self.bend_at, self.clear,
            self.clear_t, self.clear_at, self.contact_t, self.contact_at, self.stretch, self.stretch_t,
            self.max_twist, status, self.failed_t, own, Series.of(self.series["tension"]),
            Series.of(self.series["bend"]), Series.of(self.series["gap"]), recorded, self.stride)


def _lower(best: np.ndarray, value: np.ndarray, t: float, when: np.ndarray, where: np.ndarray | None = None,
           at: np.ndarray | None = None) -> None:
    """Where ``value`` is below ``best`` (NaN never is): take it, and note the time and place."""
    _take(value < best, best, value, t, when, where, at)


def _higher(best: np.ndarray, value: np.ndarray, t: float, when: np.ndarray) -> None:
    """Where ``value`` is above ``best`` (NaN never is): take it, and note the time."""
    _take(value > best, best, value, t, when)


def _take(better, best, value, t, when, where=None, at=None) -> None:
    best[better] = value[better]
    when[better] = t
    if where is not None:
        where[better] = at[better]
