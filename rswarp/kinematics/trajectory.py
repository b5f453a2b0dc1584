"""Joint trajectories that cable environments follow: CSV files as the design notes define them (header
``time,<active joints in file order>``, time in seconds, joint values in the RSXML file's units,
linearly interpolated), and smooth random ones within the joint limits at plausible joint speeds,
reproducible for a seed. Several trajectories serve many environments round-robin.
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import Diagnostic, InputError, RsxmlError
from ..files import read_regular
from ..options import checked
from ..rsxml.model import Mechanism
from ..rsxml.parse import number
from ..rsxml.robot_data import axis_limits
from ..rsxml.units import format_number

LIMIT_SLACK = 1e-9  # SI: rounding in a file's units does not put a value outside its limits
WAYPOINT_SPAN = 0.6  # a random move goes at most this share of a joint's range
MAX_ROWS = 10_000_000  # rows of one trajectory file: memory stays bounded
EXTERNAL_AXES = ("eax_a", "eax_b", "eax_c", "eax_d", "eax_e", "eax_f")  # a cell's axes: columns after the joints


@dataclass(frozen=True)
class Trajectory:
    """Joint values over time: ``times`` (T,) seconds, increasing; ``q`` (T, dof) SI; between rows
    linear, or with ``smooth`` minimum-jerk moves at rest at every row (random motion, kept as its
    waypoints: memory does not grow with the duration)."""

    source: str
    times: np.ndarray
    q: np.ndarray
    smooth: bool = False
    until: float | None = None  # where it ends, if before its last row (random motion, cut at its length)
    ext: np.ndarray | None = None  # (T, axes) a cell's external axes (RAPID's mm and degrees), where given
    ext_axes: tuple[str, ...] = ()  # their logical axes (eax_a .. eax_f), the CSV's columns after the joints
    base: np.ndarray | None = None  # (T, 3) m: the robot's base moved from where it starts (a track's carriage)

    @property
    def duration(self) -> float:
        return float(self.times[-1]) if self.until is None else self.until

    def base_at(self, t) -> np.ndarray | None:
        """``(len(t), 3)`` the base's offset from its start at times ``t`` (linear between rows);
        None for a robot that stands still."""
        if self.base is None:
            return None
        t = np.atleast_1d(np.asarray(t, float))
        return np.stack([np.interp(t, self.times, self.base[:, c]) for c in range(3)], axis=1)

    def at(self, t) -> np.ndarray:
        """``(len(t), dof)`` joint values at times ``t``; held at the ends."""
        t = np.atleast_1d(np.asarray(t, float))
        if self.smooth and len(self.times) > 1:
            return _moves(self.times, self.q, np.clip(t, self.times[0], self.times[-1]))
        out = np.empty((len(t), self.q.shape[1]))
        for c in range(self.q.shape[1]):
            out[:, c] = np.interp(t, self.times, self.q[:, c])
        return out


def read_trajectory(path: str | Path, mech: Mechanism) -> Trajectory:
    """A trajectory CSV for ``mech``; ``RsxmlError`` (``file:line: message``) for a bad header,
    a bad cell, a time that does not increase, or a joint value outside its limits."""
    path = Path(path)
    try:
        data = read_regular(path)
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise _error(path, line, f"not UTF-8 text: {exc.reason} at byte {exc.start}") from None
    except OSError as exc:
        raise InputError(f"{path}: {exc.strerror or exc}") from None
    names = ["time"] + [j.name for j in mech.active_joints]
    rows = csv.reader(io.StringIO(text, newline=""))
    header = _next(rows, path)
    header = [h.strip() for h in header] if header is not None else None
    extra = tuple(header[len(names):]) if header is not None else ()
    if header is None or header[:len(names)] != names or not set(extra) <= set(EXTERNAL_AXES) or \
            len(set(extra)) != len(extra):
        raise _error(path, 1, f"the header must be '{','.join(names)}' (the active joints in file order), then "
                              "a cell's external axes where it has them (eax_a .. eax_f)")
    times, values = [], []
    while (row := _next(rows, path)) is not None:
        line = rows.line_num
        if not any(cell.strip() for cell in row):
            continue  # blank lines are allowed (a trailing newline, spacing)
        if len(times) >= MAX_ROWS:
            raise _error(path, line, f"more than {MAX_ROWS} rows: split the trajectory")
        t, q = _row(path, line, row, mech, len(header))
        if times and not t > times[-1]:
            raise _error(path, line, f"time {t:g} s does not come after {times[-1]:g} s")
        times.append(t)
        values.append(q)
    if not times:
        raise _error(path, 1, "no rows: a trajectory needs at least one time")
    values = np.array(values)
    dof = len(names) - 1
    return Trajectory(str(path), np.array(times), values[:, :dof], ext=values[:, dof:] if extra else None,
                      ext_axes=extra)


def _next(rows, path: Path) -> list[str] | None:
    """The next row of a CSV reader, None at the end; what the csv module refuses (a field over
    its limit, a stray quote) is the file's error at its line."""
    try:
        return next(rows, None)
    except csv.Error as exc:
        raise _error(path, rows.line_num, f"not a CSV row: {exc}") from None


def _row(path: Path, line: int, row: list[str], mech: Mechanism, width: int) -> tuple[float, np.ndarray]:
    """One row's time and SI joint values, checked against the limits."""
    if len(row) != width:
        raise _error(path, line, f"{len(row)} values, the header names {width}")
    try:
        cells = [number(c) for c in row]
    except ValueError as exc:
        raise _error(path, line, f"{exc}") from None
    if cells[0] < 0:
        raise _error(path, line, f"time {cells[0]:g} s is negative")
    q = []
    for j, v in zip(mech.active_joints, cells[1:]):
        f = mech.joint_factor(j)
        lim = mech.limit(j.name)
        if lim is not None and not lim.min - LIMIT_SLACK <= v * f <= lim.max + LIMIT_SLACK:
            raise _error(path, line, f"{j.name} = {format_number(v * f, f)} is outside its limits "
                                     f"[{format_number(lim.min, f)}, {format_number(lim.max, f)}]")
        q.append(v * f)
    return cells[0], np.array(q + cells[1 + len(q):])  # a cell's external axes after the joints, as written


def _error(path: Path, line: int, message: str) -> RsxmlError:
    return RsxmlError(Diagnostic(str(path), line, message))


def random_trajectory(mech: Mechanism, seconds: float, seed: int, velocity: np.ndarray | None = None) -> Trajectory:
    """Smooth random motion within the limits: minimum-jerk moves between random waypoints, each
    move as long as its largest joint step needs at ``velocity`` (rad/s or m/s per joint; default
    the export's velocity limits), so no joint goes faster. Reproducible for ``seed``; kept as its
    waypoints (a mechanism without joints stands still)."""
    checked("seconds", seconds)
    source = f"random (seed {seed})"
    if not mech.dof:
        return Trajectory(source, np.array([0.0, seconds]), np.zeros((2, 0)), smooth=True)
    lower, upper = mech.bounds()
    if not (np.all(np.isfinite(lower)) and np.all(np.isfinite(upper))):
        raise InputError("every active joint needs finite limits for a random trajectory")
    vmax = joint_speed_limits(mech) if velocity is None else np.asarray(velocity, float)
    rng = np.random.default_rng([seed, 0xCAB1E])
    home = np.clip(mech.home_position(), lower, upper)
    knots_t, knots_q = [0.0], [home]
    while knots_t[-1] < seconds:
        step = rng.uniform(-1, 1, len(lower)) * WAYPOINT_SPAN * (upper - lower)
        nxt = np.clip(knots_q[-1] + step, lower, upper)
        # a minimum-jerk move over time T peaks at 1.875 x its mean speed
        duration = max(float(np.max(1.875 * np.abs(nxt - knots_q[-1]) / vmax)), 0.2)
        knots_t.append(knots_t[-1] + duration)
        knots_q.append(nxt)
    return Trajectory(source, np.array(knots_t), np.array(knots_q), smooth=True, until=float(seconds))


def joint_speed_limits(mech: Mechanism) -> np.ndarray:
    """Each active joint's speed limit (SI): the robot data's beside the RSXML, else the default."""
    return axis_limits(mech).velocity


def _moves(knots_t: np.ndarray, knots_q: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Values at ``t`` of minimum-jerk moves between consecutive knots (rest at every knot)."""
    k = np.clip(np.searchsorted(knots_t, t, side="right") - 1, 0, len(knots_t) - 2)
    s = (t - knots_t[k]) / (knots_t[k + 1] - knots_t[k])
    return knots_q[k] + minimum_jerk(s)[:, None] * (knots_q[k + 1] - knots_q[k])


STACKED_KNOTS = 4096  # knots a smooth trajectory has at most to be evaluated with others at once (``Stacked``)


class Stacked:
    """Smooth trajectories evaluated together (a cable run's environments, frame by frame): their
    knots padded into arrays, each row the same arithmetic as its ``Trajectory.at``, bit for bit,
    in a few array operations instead of one Python call each."""

    def __init__(self, trajectories):
        width = max(len(tr.times) for tr in trajectories)
        self.first = np.array([tr.times[0] for tr in trajectories])
        self.last = np.array([tr.times[-1] for tr in trajectories])
        self.count = np.array([len(tr.times) for tr in trajectories])
        self.t = np.full((len(trajectories), width), np.inf)
        self.q = np.empty((len(trajectories), width, trajectories[0].q.shape[1]))
        for k, tr in enumerate(trajectories):
            self.t[k, :len(tr.times)] = tr.times
            self.q[k, :len(tr.times)] = tr.q
            self.q[k, len(tr.times):] = tr.q[-1]

    @classmethod
    def of(cls, trajectories) -> "Stacked | None":
        """The trajectories stacked, or None where one is not smooth, or has one knot or too many."""
        if all(tr.smooth and 1 < len(tr.times) <= STACKED_KNOTS for tr in trajectories):
            return cls(trajectories)
        return None

    def at(self, t: np.ndarray) -> np.ndarray:
        """(trajectories, len(t), dof) every trajectory's joints at times ``t``."""
        tt = np.clip(np.asarray(t, float)[None, :], self.first[:, None], self.last[:, None])
        k = (self.t[:, None, :] <= tt[:, :, None]).sum(axis=2) - 1  # searchsorted(side="right") - 1, per row
        k = np.clip(k, 0, (self.count - 2)[:, None])
        rows = np.arange(len(self.t))[:, None]
        t0, t1 = self.t[rows, k], self.t[rows, k + 1]
        q0, q1 = self.q[rows, k], self.q[rows, k + 1]
        return q0 + minimum_jerk((tt - t0) / (t1 - t0))[..., None] * (q1 - q0)


def minimum_jerk(s: np.ndarray) -> np.ndarray:
    """The share of a minimum-jerk move done at ``s`` (its time share, clipped to [0, 1])."""
    s = np.clip(s, 0.0, 1.0)
    return s ** 3 * (10 - 15 * s + 6 * s * s)


RANDOM_SECONDS = 10.0  # a random run's length unless given


def run_trajectories(mech: Mechanism, files: list[str] | None, random: bool, envs: int, seconds: float | None,
                     seed: int) -> list[Trajectory]:
    """The trajectories of a run: the CSV files read (checked against the limits), or one smooth
    random trajectory per environment, from seeds ``seed``, ``seed + 1``, ..."""
    if random:
        span = seconds or RANDOM_SECONDS
        return [random_trajectory(mech, span, seed + e) for e in range(envs)]
    return [read_trajectory(f, mech) for f in files or []]


def assign(trajectories: list[Trajectory], envs: int) -> list[int]:
    """Which trajectory each environment follows: round-robin over the given ones."""
    if not trajectories:
        raise InputError("at least one trajectory is needed")
    return [e % len(trajectories) for e in range(envs)]
