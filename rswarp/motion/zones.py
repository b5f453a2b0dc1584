"""Zones: a move that ends in a zone (``z50``) does not stop at its point. The next move starts
while this one is still on its way, and for that while the robot's joints follow both: the rest
of this move plus the start of the next (superposition, as a controller blends in joint space).
The blend starts where the TCP comes within the zone of the point (``pzone_tcp``, and within
``zone_ori`` of its orientation), the zone cut to half of either move as ABB cuts it, and lasts
no longer than this move's slowing down and the next one's speeding up, so no axis goes faster
than either move lets it. ``fine`` stops; so does a move the next one does not follow at once (a
WaitTime between, an error, the task's last move)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

EPS = 1e-9
SLACK = 0.01  # of the limits, for the samples' own rounding
TRIES = 24  # shorter overlaps tried where a blend's samples pass a limit (down to 2 % of it)
SHORTER = 0.85  # each a little shorter than the one before


@dataclass(frozen=True)
class Ahead:
    """What a batch found of a move before the planner appends it (``zone_batch``): how long it
    speeds up and slows down, and, where it follows a move in a zone, that move's sample times
    (the array itself: the blend holds only after that very move), the zone, their overlap (s),
    the samples of that move kept and this one's joints blended (None where they do not overlap)."""

    ramp_in: float
    ramp_out: float
    t_prev: np.ndarray | None = None
    zone: object = None
    tau: float = 0.0
    kept: int | None = None
    blended: np.ndarray | None = None

    def after(self, prev: Segment, zone) -> bool:
        """Whether this is the blend after ``prev`` ending in ``zone``."""
        return self.t_prev is not None and self.t_prev is prev.t and self.zone is zone


@dataclass(frozen=True)
class Segment:
    """A timed move as the blend sees it: its samples (times from its start, joints, share of
    the way), where it starts, and its TCP path: length (m) and turn (rad), the length gone at
    the shares ``probe_s``."""

    t: np.ndarray
    q: np.ndarray
    s: np.ndarray
    q0: np.ndarray
    length: float
    turn: float
    probe_s: np.ndarray
    probe_len: np.ndarray
    ahead: Ahead | None = None  # what a batch found of it before it was appended

    @property
    def duration(self) -> float:
        return float(self.t[-1])

    def gone(self, s: np.ndarray) -> np.ndarray:
        """The TCP's path length from the start at shares ``s``."""
        return np.interp(s, self.probe_s, self.probe_len)

    def ramp_out(self) -> float:
        """How long it slows down at its end: its last stretch of falling speed."""
        if self.ahead is not None:
            return self.ahead.ramp_out
        return _monotone_tail(self.t, self.s)

    def ramp_in(self) -> float:
        """How long it speeds up at its start."""
        if self.ahead is not None:
            return self.ahead.ramp_in
        t = np.concatenate([[0.0], self.t])
        s = np.concatenate([[0.0], self.s])
        return _monotone_tail(self.duration - t[::-1], 1.0 - s[::-1])  # its start, read backwards


def straight(t, q, s, q0, length: float, turn: float, ahead: Ahead | None = None) -> Segment:
    """A move whose TCP goes its path in proportion to its share (a line, a circle); ``ahead``:
    what a batch found of it, where one did."""
    return Segment(t, q, s, q0, length, turn, shares(2), np.array([0.0, length]), ahead)


def jointed(t, q, s, q0, tcp, ahead: Ahead | None = None) -> Segment:
    """A joint move, its TCP's path measured at evenly shared probes (``tcp``: a ``timing.TcpPath``)."""
    return Segment(t, q, s, q0, float(tcp.gone[-1]), tcp.turn, shares(len(tcp.gone)), tcp.gone, ahead)


@lru_cache(maxsize=8)
def shares(n: int) -> np.ndarray:
    """``np.linspace(0, 1, n)``, made once (read only)."""
    out = np.linspace(0.0, 1.0, n)
    out.flags.writeable = False
    return out


def overlap(prev: Segment, nxt: Segment, zone) -> float:
    """How long ``nxt`` runs while ``prev`` is still on its way (s): 0 for a stop point."""
    if zone is None or zone.fine or len(prev.t) == 0 or len(nxt.t) == 0:
        return 0.0
    if nxt.ahead is not None and nxt.ahead.after(prev, zone):
        return nxt.ahead.tau
    z = min(zone.pzone_tcp, prev.length / 2, nxt.length / 2)
    # the orientation's zone cut to half of either move's turn, of a move that turns: one that keeps
    # its orientation bounds nothing (else a MoveJ that turns the tool would stop every such blend)
    zo = min(zone.zone_ori, prev.turn / 2 if prev.turn > 0 else np.inf, nxt.turn / 2 if nxt.turn > 0 else np.inf)
    # prev is inside the zone from the share where both its way and its turn left are within it
    # (both only shrink along the move); nxt is near its start up to where either grows past it
    s_in = max(_share_at(prev, prev.length - z - EPS), 1.0 - (zo + EPS) / prev.turn if prev.turn > 0 else 0.0)
    first = min(int(np.searchsorted(prev.s, s_in, side="left")), len(prev.s) - 1)  # its first sample inside
    leave = prev.duration - (float(prev.t[first]) if s_in > 0.0 else 0.0)
    s_out = min(_share_at(nxt, z + EPS), (zo + EPS) / nxt.turn if nxt.turn > 0 else 1.0)
    count = int(np.searchsorted(nxt.s, s_out, side="right"))
    enter = float(nxt.t[count - 1]) if count else 0.0
    tau = min(leave, enter)
    if tau <= 0.0:
        return 0.0
    return max(0.0, min(tau, prev.ramp_out(), nxt.ramp_in()))


def _share_at(seg: Segment, gone: float) -> float:
    """The least share of ``seg`` at which its TCP has gone ``gone`` (m) along its path."""
    if gone <= 0.0:
        return 0.0
    if gone > seg.probe_len[-1]:
        return np.inf
    k = int(np.searchsorted(seg.probe_len, gone, side="left"))
    a, b = seg.probe_len[k - 1], seg.probe_len[k]
    return float(seg.probe_s[k - 1] + (seg.probe_s[k] - seg.probe_s[k - 1]) * (gone - a) / (b - a))


def blend(prev: Segment, nxt: Segment, tau: float) -> tuple[int, np.ndarray]:
    """(samples of ``prev`` kept, ``nxt``'s joints with the rest of ``prev`` added where they
    overlap) for an overlap of ``tau`` seconds; ``nxt`` then starts ``tau`` before ``prev`` ends."""
    found = nxt.ahead
    if found is not None and found.blended is not None and found.t_prev is prev.t and found.tau == tau:
        return found.kept, found.blended
    start = prev.duration - tau
    kept = int(np.searchsorted(prev.t, start, side="right"))
    # prev's samples from the last at or before ``start`` (its start, q0, at time 0): all ``at`` needs
    t_prev = np.concatenate([[0.0], prev.t]) if kept == 0 else prev.t[kept - 1:]
    q_prev = np.vstack([prev.q0[None], prev.q]) if kept == 0 else prev.q[kept - 1:]
    shared = int(np.searchsorted(nxt.t, tau, side="right"))  # nxt's samples at or before tau
    at = np.minimum(start + nxt.t[:shared], t_prev[-1])
    # at lies in [t[k-1], t[k]]; at >= start >= t_prev[0], so k >= 1 already (np.clip's lower bound)
    k = np.minimum(np.searchsorted(t_prev, at, side="right"), len(t_prev) - 1)
    w = ((at - t_prev[k - 1]) / np.maximum(t_prev[k] - t_prev[k - 1], 1e-300))[:, None]
    q = nxt.q.copy()
    q[:shared] += q_prev[k - 1] * (1.0 - w) + q_prev[k] * w - prev.q[-1]
    return kept, q


def within(prev: Segment, nxt: Segment, kept: int, q: np.ndarray, tau: float, speed: np.ndarray,
           accel: np.ndarray, slack: float = SLACK) -> bool:
    """Whether a blend's samples (``blend``'s ``kept`` and ``q`` for an overlap of ``tau``) keep every
    axis within ``speed`` and ``accel`` (a little ``slack`` for sampling) where the two moves run
    together and either side of it: where both speed up or slow down the same axis the same way,
    their accelerations add, and the overlap must then be shorter."""
    shared = int(np.searchsorted(nxt.t, tau, side="right"))
    before = max(kept - 2, 0)
    t_prev = np.concatenate([[0.0], prev.t])[before:kept + 1] if kept else np.zeros(1)
    q_prev = np.vstack([prev.q0[None], prev.q])[before:kept + 1] if kept else prev.q0[None]
    upto = min(shared + 2, len(q))
    t = np.concatenate([t_prev, prev.duration - tau + nxt.t[:upto]])
    rows = np.vstack([q_prev, q[:upto]])
    keep = np.concatenate([[True], np.diff(t) > 1e-9])
    t, rows = t[keep], rows[keep]
    if len(t) < 3:
        return True
    v = np.diff(rows, axis=0) / np.diff(t)[:, None]
    a = np.diff(v, axis=0) / (0.5 * (t[2:] - t[:-2]))[:, None]
    return bool(np.all(np.abs(v) <= speed * (1 + slack)) and np.all(np.abs(a) <= accel * (1 + slack)))


def _monotone_tail(t: np.ndarray, s: np.ndarray) -> float:
    """The time of the last slowing down: from where the speed (ds/dt) last leaves its top
    (a cruise's end) and falls without rising again to the end."""
    if len(t) < 3:
        return float(t[-1] - t[0]) if len(t) else 0.0
    v = np.diff(s) / np.maximum(np.diff(t), 1e-12)
    rising = np.nonzero(v[1:] > v[:-1] * (1 + 1e-9) + 1e-12)[0]
    first = int(rising[-1]) + 1 if len(rising) else 0  # speed falls (or holds) from sample first on
    held = np.nonzero(v[first:] >= v[first] * (1 - 1e-3))[0]
    return float(t[-1] - t[first + int(held[-1])])


def ramps(t: np.ndarray, s: np.ndarray, first: np.ndarray, count: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(ramp_in, ramp_out) of moves whose samples (times ``t`` from their start, shares ``s``) lie
    end to end, move m's ``count[m]`` of them from ``first[m]``: ``Segment.ramp_in`` and
    ``ramp_out`` of each, the same arithmetic."""
    if not len(t):
        return np.zeros(len(count)), np.zeros(len(count))
    out = _tails(t, s, first, count)
    # each move read backwards from its end, with its start (0, 0) last: what ``ramp_in`` reads
    row = np.repeat(np.arange(len(count)), count + 1)
    back_first = first + np.arange(len(count))
    i = np.arange(len(row)) - back_first[row]  # 0 .. count within the move
    src = first[row] + count[row] - 1 - i  # sample read at i (its start where i == count)
    start = i == count[row]
    duration = np.where(count > 0, t[np.maximum(first + count - 1, 0)], 0.0)
    t_back = duration[row] - np.where(start, 0.0, t[np.minimum(src, len(t) - 1)])
    s_back = 1.0 - np.where(start, 0.0, s[np.minimum(src, len(s) - 1)])
    return _tails(t_back, s_back, back_first, count + 1), out


def _tails(t: np.ndarray, s: np.ndarray, first: np.ndarray, count: np.ndarray) -> np.ndarray:
    """``_monotone_tail`` of each move laid end to end in ``t`` and ``s``."""
    out = np.zeros(len(count))
    short = count < 3
    for m in np.flatnonzero(short & (count > 0)):
        out[m] = t[first[m] + count[m] - 1] - t[first[m]]
    rows = np.flatnonzero(~short)
    if not len(rows):
        return out
    f, n = first[rows], count[rows]
    row = np.repeat(np.arange(len(rows)), n - 1)  # speeds between neighbouring samples
    starts = np.cumsum(n - 1) - (n - 1)
    local = np.arange(len(row)) - starts[row]
    pair = local + f[row]
    v = (s[pair + 1] - s[pair]) / np.maximum(t[pair + 1] - t[pair], 1e-12)
    rising = np.zeros(len(v), bool)  # v[j + 1] rises above v[j], at j + 1
    rising[1:] = v[1:] > v[:-1] * (1 + 1e-9) + 1e-12
    rising[starts] = False
    top = np.maximum.reduceat(np.where(rising, local, 0), starts)  # the last rise (0: none)
    held = (local >= top[row]) & (v >= v[starts + top][row] * (1 - 1e-3))
    last = np.maximum.reduceat(np.where(held, local, -1), starts)
    out[rows] = t[f + n - 1] - t[f + last]
    return out
