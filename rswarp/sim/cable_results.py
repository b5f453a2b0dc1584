"""What a cable run reports, and how it is gathered: per environment, the extremes of each quantity
and when and where they happened (``RunningExtremes``, fed a solver's named statistics frame by
frame); over time, their spread across environments (``Series``). Kept as running extremes so
memory grows with environments plus frames, never with their product. A run cut into tasks puts
its pieces together in a ``CableTally``, exactly as one run would have gathered them."""

from __future__ import annotations

import tempfile
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from .cable_solver import RUNNING, CableSolver

MAX_RECORDED = 20_000  # frames kept for playback; longer runs keep every k-th frame
MAX_VALUES_BYTES = 16 << 30  # a cut run's per-frame values, kept in a file: 16 GiB at most


def values_bytes(envs: int, frames: int, cables: int) -> int:
    """The size of a cut run's file of per-frame values (checked against MAX_VALUES_BYTES first)."""
    return frames * len(SERIES) * envs * 4 * cables
FRAME_BLOCK = 1024  # frames read back at a time to take their spread


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


class RunningExtremes:
    """Running extremes of one cable's environments, fed each frame's statistics (by name, from its
    ``CableSolver``); per frame the spread of each of SERIES across them, or with ``values`` every
    environment's value (frames, 3, envs) float32, which holds the kernels' float32 results exactly:
    a piece of a cut run keeps these, and the tally takes the spread of all environments."""

    def __init__(self, solver: CableSolver, envs: int, slots: int, frames: int, record: int, values: bool = False):
        self.solver = solver
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

    def start(self, state) -> None:
        """The twist at the end of settling: its turns are counted from here on."""
        self.twist_prev = self.solver.statistics(state)["twist"].copy()
        self.twist = self.twist_prev.copy()

    def add(self, state, t: float) -> None:
        stats = self.solver.statistics(state)
        status = stats["status"]
        live = status == RUNNING
        gone = ~live & np.isnan(self.failed_t)
        self.failed_t[gone], self.failed_why[gone] = t, status[gone]
        tension = np.where(live, stats["tension"], np.nan)
        _higher(self.peak, tension, t, self.peak_t)
        bend = np.where(live, stats["bend_radius"], np.nan)
        _lower(self.bend, bend, t, self.bend_t, self.bend_at, stats["bend_at"])
        gap = self._clearances(stats, live, t)
        _higher(self.stretch, np.where(live, stats["stretch"], np.nan), t, self.stretch_t)
        self._twist(stats["twist"], live)
        if self.values is not None:
            self.values[self.frame] = (tension, bend, gap)
        else:
            for key, values in zip(SERIES, (tension, bend, gap)):
                self.series[key].append(spread(values))
        if self.record >= 0 and self.frame % self.stride == 0:
            self.recorded.append(self.solver.points(state, min(self.record, len(live) - 1)))
        self.frame += 1

    def _clearances(self, stats: dict, live: np.ndarray, t: float) -> np.ndarray:
        """Least clearance per link and the floor; the first contact. Returns each environment's
        least clearance to anything this frame."""
        c = np.where(live[:, None], stats["clearance"], np.nan)
        where = stats["clearance_at"]
        _lower(self.clear, c, t, self.clear_t, self.clear_at, where)
        first = (c <= 0) & np.isnan(self.contact_t)
        self.contact_t[first], self.contact_at[first] = t, where[first]
        return c.min(axis=1)

    def _twist(self, raw: np.ndarray, live: np.ndarray) -> None:
        """Whole turns counted: each frame's change is taken in (-pi, pi]."""
        step = (raw - self.twist_prev + np.pi) % (2 * np.pi) - np.pi
        self.twist = np.where(live, self.twist + step, self.twist)
        self.twist_prev = np.where(live, raw, self.twist_prev)
        self.max_twist = np.maximum(self.max_twist, np.abs(self.twist))

    def result(self, allowed: float, links: tuple[str, ...], state) -> CableResult:
        why = self.solver.failures
        status = np.array(["ok" if np.isnan(t) else f"stopped at t = {t:.3f} s: {why.get(int(k), 'failed')}"
                           for t, k in zip(self.failed_t, self.failed_why)], dtype=object)
        solver = self.solver
        final = solver.points(state)
        recorded = np.asarray(self.recorded, np.float64).reshape(-1, final.shape[1], 3)
        series = {key: Series.of(self.series[key]) for key in SERIES}
        return CableResult(
            name=solver.name, length=solver.length, radius=solver.radius, allowed_bend_radius=float(allowed),
            torsion_stiffness=solver.torsion_stiffness, links=links, peak_tension=self.peak,
            peak_tension_time=self.peak_t, min_bend_radius=self.bend, min_bend_time=self.bend_t,
            min_bend_at=self.bend_at, clearance=self.clear, clearance_time=self.clear_t, clearance_at=self.clear_at,
            contact_time=self.contact_t, contact_at=self.contact_at, stretch=self.stretch,
            stretch_time=self.stretch_t, max_twist=self.max_twist, status=status, failed_time=self.failed_t,
            final_points=final, recorded=recorded, stride=self.stride, **series)


@dataclass(frozen=True)
class CablePiece:
    """What a run of some environments gave: each cable's results over them (from ``start`` on),
    each cable's per-frame values where the piece is not the whole run (else None: its results
    hold the spread already), and the recorded environment's joints."""

    start: int
    results: tuple[CableResult, ...]
    values: tuple[np.ndarray, ...] | None
    recorded_q: np.ndarray


class CableTally:
    """A cable run's pieces put together in place, as one run gathers them: per-environment arrays
    at their offsets; the per-frame values of a cut run in a file-backed (frames, 3, envs) array per
    cable (capped at MAX_VALUES_BYTES), whose spread is taken frame by frame at the end; the
    recorded environment from its piece. A task's own piece is kept as it is until merged."""

    def __init__(self, envs: int, frames: int, cables: int):
        self.envs, self.frames, self.cables = envs, frames, cables
        self.pieces: list[CablePiece] = []  # added here, not yet placed
        self.whole: CablePiece | None = None
        self.fields: list[dict[str, np.ndarray]] = []
        self.values: list[np.ndarray] = []
        self.recorded: list[CableResult | None] = [None] * cables
        self.recorded_q = np.zeros((0,))
        self.first: CablePiece | None = None
        self._folder: tempfile.TemporaryDirectory | None = None

    def add(self, piece: CablePiece) -> None:
        self.pieces.append(piece)

    def merge(self, other: "CableTally") -> None:
        for piece in other.pieces:
            self._place(piece)

    def _place(self, piece: CablePiece) -> None:
        if piece.values is None:  # the whole run in one piece
            self.whole = piece
            return
        if not self.fields:
            self._allocate(piece)
        for c, (r, v) in enumerate(zip(piece.results, piece.values)):
            for k in PER_ENV:
                self.fields[c][k][piece.start:piece.start + r.envs] = getattr(r, k)
            self.values[c][:, :, piece.start:piece.start + r.envs] = v
            if len(r.recorded):
                self.recorded[c], self.recorded_q = r, piece.recorded_q
        self.first = piece

    def _allocate(self, piece: CablePiece) -> None:
        self._folder = tempfile.TemporaryDirectory(prefix="rswarp-cables-")
        self.fields = [{k: np.empty((self.envs, *getattr(r, k).shape[1:]), getattr(r, k).dtype) for k in PER_ENV}
                       for r in piece.results]
        self.values = [np.lib.format.open_memmap(Path(self._folder.name) / f"values{c}.npy", "w+", np.float32,
                                                 (self.frames, len(SERIES), self.envs)) for c in range(self.cables)]

    def results(self) -> tuple[tuple[CableResult, ...], np.ndarray]:
        """Every cable's results over all environments, and the recorded environment's joints."""
        for piece in self.pieces:
            self._place(piece)
        self.pieces = []
        if self.whole is not None:
            return self.whole.results, self.whole.recorded_q
        try:
            out = []
            for c, first in enumerate(self.first.results):
                rec = self.recorded[c] or first
                out.append(replace(first, **self.fields[c], **_series(self.values[c]), recorded=rec.recorded,
                                   stride=rec.stride))
            return tuple(out), self.recorded_q
        finally:
            self.values = []
            if self._folder is not None:
                self._folder.cleanup()


def _series(values: np.ndarray) -> dict[str, Series]:
    """The spread of each quantity per frame over all environments, as one run takes it."""
    rows: dict[str, list] = {key: [] for key in SERIES}
    for lo in range(0, len(values), FRAME_BLOCK):
        block = np.asarray(values[lo:lo + FRAME_BLOCK], np.float64)
        for frame in block:
            for key, v in zip(SERIES, frame):
                rows[key].append(spread(v))
    return {key: Series.of(rows[key]) for key in SERIES}


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
