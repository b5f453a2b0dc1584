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
from ..rsxml.model import Mechanism
from ..rsxml.parse import number
from ..rsxml.units import JOINT_VELOCITY, format_number

LIMIT_SLACK = 1e-9  # SI: rounding in a file's units does not put a value outside its limits
WAYPOINT_SPAN = 0.6  # a random move goes at most this share of a joint's range
MAX_ROWS = 10_000_000  # rows of one trajectory file: memory stays bounded


@dataclass(frozen=True)
class Trajectory:
    """Joint values over time: ``times`` (T,) seconds, increasing; ``q`` (T, dof) SI."""

    source: str
    times: np.ndarray
    q: np.ndarray

    @property
    def duration(self) -> float:
        return float(self.times[-1])

    def at(self, t) -> np.ndarray:
        """``(len(t), dof)`` joint values at times ``t``, linearly interpolated; held at the ends."""
        t = np.atleast_1d(np.asarray(t, float))
        return np.stack([np.interp(t, self.times, self.q[:, c]) for c in range(self.q.shape[1])], axis=1)


def read_trajectory(path: str | Path, mech: Mechanism) -> Trajectory:
    """A trajectory CSV for ``mech``; ``RsxmlError`` (``file:line: message``) for a bad header,
    a bad cell, a time that does not increase, or a joint value outside its limits."""
    path = Path(path)
    try:
        text = read_regular(path).decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise RsxmlError(Diagnostic(str(path), 0, f"not UTF-8 text: {exc.reason} at byte {exc.start}")) from None
    except OSError as exc:
        raise InputError(f"{path}: {exc.strerror or exc}") from None
    names = ["time"] + [j.name for j in mech.active_joints]
    rows = csv.reader(io.StringIO(text, newline=""))
    header = next(rows, None)
    if header is None or [h.strip() for h in header] != names:
        raise _error(path, 1, f"the header must be '{','.join(names)}' (the active joints in file order)")
    times, values = [], []
    for row in rows:
        line = rows.line_num
        if not any(cell.strip() for cell in row):
            continue  # blank lines are allowed (a trailing newline, spacing)
        if len(times) >= MAX_ROWS:
            raise _error(path, line, f"more than {MAX_ROWS} rows: split the trajectory")
        t, q = _row(path, line, row, mech, len(names))
        if times and not t > times[-1]:
            raise _error(path, line, f"time {t:g} s does not come after {times[-1]:g} s")
        times.append(t)
        values.append(q)
    if not times:
        raise _error(path, 1, "no rows: a trajectory needs at least one time")
    return Trajectory(str(path), np.array(times), np.array(values))


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
    return cells[0], np.array(q)


def _error(path: Path, line: int, message: str) -> RsxmlError:
    return RsxmlError(Diagnostic(str(path), line, message))


def random_trajectory(mech: Mechanism, seconds: float, seed: int, velocity: np.ndarray | None = None,
                      samples_per_second: int = 100) -> Trajectory:
    """Smooth random motion within the limits: minimum-jerk moves between random waypoints, each
    move as long as its largest joint step needs at ``velocity`` (rad/s or m/s per joint; default
    the export's velocity limits), so no joint goes faster. Reproducible for ``seed``."""
    if not seconds > 0:
        raise InputError("a random trajectory needs a positive duration")
    lower, upper = mech.bounds()
    if not (np.all(np.isfinite(lower)) and np.all(np.isfinite(upper))):
        raise InputError("every active joint needs finite limits for a random trajectory")
    vmax = _velocities(mech) if velocity is None else np.asarray(velocity, float)
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
    times = np.linspace(0.0, seconds, max(2, int(round(seconds * samples_per_second)) + 1))
    return Trajectory(f"random (seed {seed})", times, _moves(np.array(knots_t), np.array(knots_q), times))


def _velocities(mech: Mechanism) -> np.ndarray:
    """Each active joint's default speed limit, the exports' too (SI)."""
    return np.array([JOINT_VELOCITY[j.revolute] for j in mech.active_joints])


def _moves(knots_t: np.ndarray, knots_q: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Values at ``t`` of minimum-jerk moves between consecutive knots (rest at every knot)."""
    k = np.clip(np.searchsorted(knots_t, t, side="right") - 1, 0, len(knots_t) - 2)
    s = (t - knots_t[k]) / (knots_t[k + 1] - knots_t[k])
    return knots_q[k] + minimum_jerk(s)[:, None] * (knots_q[k + 1] - knots_q[k])


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
