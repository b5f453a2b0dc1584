"""How a cable's results are gathered: running extremes of each quantity per environment and when
and where they happened, fed a model's named statistics frame by frame; per frame the spread of
the main quantities across environments. Kept as running extremes so memory grows with
environments plus frames, never with their product."""

from __future__ import annotations

import numpy as np

from .results import MAX_RECORDED, SERIES, VALUE, CableResult, Series, spread
from .solver import RUNNING, CableInfo


class RunningExtremes:
    """Running extremes of one cable's environments. Per frame: the spread of each of SERIES across
    them, or with ``values`` every environment's value (frames, len(SERIES), envs) ``VALUE``: a piece
    of a cut run keeps these, and the tally takes the spread of all environments."""

    def __init__(self, info: CableInfo, slots: int, envs: int, frames: int, record: int, values: bool = False,
                 dof: int = 0, max_strain: float = 0.005, frame_clearances: bool = True):
        self.info = info
        self.taut_force = max_strain * info.axial_stiffness  # N: past it, the first time is noted (taut_t)
        nan = lambda *shape: np.full(shape, np.nan)  # noqa: E731
        a = len(info.attachments)
        self.tension, self.tension_t, self.tension_at = np.zeros(envs), nan(envs), nan(envs)
        self.taut_t = nan(envs)
        self.bend, self.bend_t, self.bend_at = np.full(envs, np.inf), nan(envs), nan(envs)
        self.clear, self.clear_t, self.clear_at = np.full((envs, slots), np.inf), nan(envs, slots), nan(envs, slots)
        self.contact_t, self.contact_at = nan(envs, slots), nan(envs, slots)
        self.stretch, self.stretch_t = np.zeros(envs), nan(envs)
        self.twist_prev, self.twist, self.max_twist = np.zeros(envs), np.zeros(envs), np.zeros(envs)
        self.rate, self.torque, self.torque_t, self.torque_at = np.zeros(envs), np.zeros(envs), nan(envs), nan(envs)
        self.normal, self.normal_t, self.normal_at, self.sliding = np.zeros(envs), nan(envs), nan(envs), np.zeros(envs)
        self.pinch, self.pinch_t, self.pinch_at = np.zeros(envs), nan(envs), nan(envs)
        self.pinch_slots, self.pinch_q = np.full((envs, 2), -1, np.int64), nan(envs, dof)
        self.force, self.force_t, self.moment, self.moment_t = np.zeros((envs, a)), nan(envs, a), np.zeros((envs, a)), \
            nan(envs, a)
        self.final_force, self.final_moment = np.zeros((envs, a, 3)), np.zeros((envs, a, 3))
        self.failed_t, self.failed_why = nan(envs), np.zeros(envs, np.int32)
        self.settled = np.ones(envs, bool)
        self.series: dict[str, list] = {key: [] for key in SERIES}
        self.values = np.empty((frames, len(SERIES), envs), VALUE) if values else None
        self.record, self.stride = record, max(1, -(-frames // MAX_RECORDED))
        self.recorded: list[np.ndarray] = []
        self.frame = 0
        self.frame_clearances = frame_clearances  # False: a frame's clearances only where lower, no series

    def start(self, stats: dict) -> None:
        """The twist at the end of settling: its turns are counted from here on. An environment
        that stopped while settling stopped at t = 0, before the trajectory."""
        self.twist_prev = stats["twist"].copy()
        self.twist = self.twist_prev.copy()
        self.settled = stats["status"] == RUNNING
        self.failed_t[~self.settled], self.failed_why[~self.settled] = 0.0, stats["status"][~self.settled]

    def add(self, stats: dict, t: float, q: np.ndarray, points=None) -> None:
        """One frame's statistics at trajectory time ``t``, the joints ``q`` (envs, dof) at its
        end; ``points()`` gives the recorded environment's points when this frame is kept for
        playback."""
        status = stats["status"]
        live = status == RUNNING
        gone = ~live & np.isnan(self.failed_t)
        self.failed_t[gone], self.failed_why[gone] = t, status[gone]
        only = lambda key: np.where(live, stats[key], np.nan)  # noqa: E731
        tension, bend, torque = only("tension"), only("bend_radius"), only("torque")
        _higher(self.tension, tension, t, self.tension_t, self.tension_at, stats["tension_at"])
        self.taut_t[np.isnan(self.taut_t) & (tension > self.taut_force)] = t
        _lower(self.bend, bend, t, self.bend_t, self.bend_at, stats["bend_at"])
        gap = self._clearances(stats, live, t)
        _higher(self.stretch, only("stretch"), t, self.stretch_t)
        _higher(self.torque, torque, t, self.torque_t, self.torque_at, stats["torque_at"])
        self.rate = np.fmax(self.rate, only("twist_rate"))
        _higher(self.normal, only("normal_force"), t, self.normal_t, self.normal_at, stats["contact_at"])
        self.sliding = np.fmax(self.sliding, only("sliding_speed"))
        self._pinch(stats, only("pinch"), t, q)
        self._clamps(stats, live, t)
        self._twist(stats["twist"], live)
        row = (tension, bend, gap if self.frame_clearances else np.full_like(gap, np.nan), torque)
        if self.values is not None:
            self.values[self.frame] = row
        else:
            for key, values in zip(SERIES, row):
                self.series[key].append(spread(values))
        if self.record >= 0 and self.frame % self.stride == 0 and points is not None:
            self.recorded.append(points())
        self.frame += 1

    def _clearances(self, stats: dict, live: np.ndarray, t: float) -> np.ndarray:
        """Least clearance per slot; the first contact. Returns each environment's least clearance
        to anything this frame."""
        c = np.where(live[:, None], stats["clearance"], np.nan)
        where = stats["clearance_at"]
        _lower(self.clear, c, t, self.clear_t, self.clear_at, where)
        first = (c <= 0) & np.isnan(self.contact_t)
        self.contact_t[first], self.contact_at[first] = t, where[first]
        return c.min(axis=1)

    def _pinch(self, stats: dict, pinch: np.ndarray, t: float, q: np.ndarray) -> None:
        """The hardest pinch: its force, time, place, the slots pressing, and the robot's joints."""
        harder = pinch > self.pinch
        _take(harder, self.pinch, pinch, t, self.pinch_t, self.pinch_at, stats["pinch_at"])
        self.pinch_slots[harder] = stats["pinch_slots"][harder]
        self.pinch_q[harder] = q[harder]

    def _clamps(self, stats: dict, live: np.ndarray, t: float) -> None:
        _higher(self.force, np.where(live[:, None], stats["clamp_force_peak"], np.nan), t, self.force_t)
        _higher(self.moment, np.where(live[:, None], stats["clamp_moment_peak"], np.nan), t, self.moment_t)
        self.final_force[live] = stats["clamp_force"][live]
        self.final_moment[live] = stats["clamp_moment"][live]

    def _twist(self, raw: np.ndarray, live: np.ndarray) -> None:
        """Whole turns counted: each frame's change is taken in (-pi, pi]."""
        step = (raw - self.twist_prev + np.pi) % (2 * np.pi) - np.pi
        self.twist = np.where(live, self.twist + step, self.twist)
        self.twist_prev = np.where(live, raw, self.twist_prev)
        self.max_twist = np.maximum(self.max_twist, np.abs(self.twist))

    def result(self, slots: tuple[str, ...], failures, final: np.ndarray, totals: dict) -> CableResult:
        """The cable's results: ``final`` its points at the end (envs, N, 3), ``totals`` its wear map;
        ``failures`` says why an environment stopped, by code: (in the run, while settling)."""
        status = np.array([_status(t, k, settled, failures) for t, k, settled in
                           zip(self.failed_t, self.failed_why, self.settled)], dtype=object)
        info = self.info
        recorded = np.asarray(self.recorded, np.float64).reshape(-1, final.shape[1], 3)
        series = {key: Series.of(self.series[key]) for key in SERIES}
        return CableResult(
            name=info.name, length=info.length, radius=info.radius, allowed_bend_radius=info.allowed_bend_radius,
            axial_stiffness=info.axial_stiffness, bending_stiffness=info.bending_stiffness,
            torsion_stiffness=info.torsion_stiffness, links=slots, attachments=info.attachments,
            segments=info.segments, peak_tension=self.tension, peak_tension_time=self.tension_t,
            peak_tension_at=self.tension_at, taut_time=self.taut_t,
            min_bend_radius=self.bend, min_bend_time=self.bend_t,
            min_bend_at=self.bend_at, clearance=self.clear, clearance_time=self.clear_t, clearance_at=self.clear_at,
            contact_time=self.contact_t, contact_at=self.contact_at, stretch=self.stretch,
            stretch_time=self.stretch_t, max_twist=self.max_twist, max_twist_rate=self.rate, max_torque=self.torque,
            max_torque_time=self.torque_t, max_torque_at=self.torque_at, peak_normal=self.normal,
            peak_normal_time=self.normal_t, peak_normal_at=self.normal_at, max_sliding_speed=self.sliding,
            pinch=self.pinch, pinch_time=self.pinch_t, pinch_at=self.pinch_at, pinch_slots=self.pinch_slots,
            pinch_q=self.pinch_q,
            clamp_force=self.force, clamp_force_time=self.force_t, clamp_moment=self.moment,
            clamp_moment_time=self.moment_t, final_clamp_force=self.final_force,
            final_clamp_moment=self.final_moment, wear_contact_time=totals["contact_time"],
            wear_peak_normal=totals["peak_normal"], wear=totals["wear"], bend_cycles=totals["bend_cycles"],
            fatigue_cycles=totals.get("fatigue_cycles", np.zeros_like(totals["contact_time"])),
            fatigue_sum=totals.get("fatigue_sum", np.zeros_like(totals["contact_time"])),
            status=status, failed_time=self.failed_t, final_points=final, recorded=recorded, stride=self.stride,
            **series)


def _lower(best: np.ndarray, value: np.ndarray, t: float, when: np.ndarray, where: np.ndarray | None = None,
           at: np.ndarray | None = None) -> None:
    """Where ``value`` is below ``best`` (NaN never is): take it, and note the time and place."""
    _take(value < best, best, value, t, when, where, at)


def _higher(best: np.ndarray, value: np.ndarray, t: float, when: np.ndarray, where: np.ndarray | None = None,
            at: np.ndarray | None = None) -> None:
    """Where ``value`` is above ``best`` (NaN never is): take it, and note the time and place."""
    _take(value > best, best, value, t, when, where, at)


def _take(better, best, value, t, when, where=None, at=None) -> None:
    best[better] = value[better]
    when[better] = t
    if where is not None:
        where[better] = at[better]


def _status(t: float, code: int, settled: bool, failures) -> str:
    if np.isnan(t):
        return "ok"
    if not settled:
        return f"stopped before t = 0, while settling: {failures[1].get(int(code), 'failed')}"
    return f"stopped at t = {t:.3f} s: {failures[0].get(int(code), 'failed')}"
