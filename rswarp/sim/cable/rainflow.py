"""Rainflow counting (ASTM E1049-85, 5.4.4) of many series at once, streamed: each new value of
every series (a hose segment's curvature, frame by frame) goes in as it comes; reversals are kept
on a stack per series, a range no larger than the one after it is a cycle counted and taken off
(half a cycle where it holds the series' start), and what is left at the end is half cycles.
Memory is the stacks: at most ``depth`` reversals per series (a stack that would pass it counts
its oldest range as half a cycle, which errs long: a real history nests far less deeply)."""

from __future__ import annotations

import numpy as np

DEPTH = 64  # reversals kept per series


class Rainflow:
    """Cycles of ``series`` histories: per series the count of cycles whose range is at least
    ``floor`` and the sum of count x range^``exponent`` over all of them (Miner's sum, before
    dividing by the rating); ``record`` keeps every (series, range, mean, count) for tests."""

    def __init__(self, series: int, exponent: float, floor: float = 0.0, depth: int = DEPTH, record: bool = False):
        self.exponent, self.floor, self.depth = float(exponent), float(floor), int(depth)
        self.stack = np.zeros((series, depth))
        self.n = np.zeros(series, np.int64)
        self.last = np.full(series, np.nan)  # the newest value, not yet known to be a reversal
        self.rising = np.zeros(series, np.int8)  # +1 rising, -1 falling, 0 not yet moved
        self.cycles = np.zeros(series)
        self.damage = np.zeros(series)
        self.record = [] if record else None

    def add(self, values: np.ndarray) -> None:
        """The next value of every series."""
        v = np.asarray(values, np.float64)
        fresh = np.isnan(self.last)
        self._push(fresh, v)  # a series' first value is its first reversal
        step = np.sign(v - self.last)
        turned = ~fresh & (step != 0) & (self.rising != 0) & (step != self.rising)
        self._push(turned, self.last)
        self.rising = np.where(~fresh & (step != 0), step, self.rising).astype(np.int8)
        self.last = np.where(fresh | (step != 0), v, self.last)
        self._count(turned)

    def finish(self) -> tuple[np.ndarray, np.ndarray]:
        """(cycles, Miner's sum) per series, the residue counted as half cycles."""
        moved = ~np.isnan(self.last)
        ends = moved & (self.n > 0) & (self.stack[np.arange(len(self.n)), np.maximum(self.n - 1, 0)] != self.last)
        self._push(ends, self.last)
        self._count(ends)  # the last value is read as a reversal like any other
        for k in range(1, self.depth):
            rows = np.nonzero(self.n > k)[0]
            if not len(rows):
                break
            self._tally(rows, self.stack[rows, k - 1], self.stack[rows, k], 0.5)
        self.n[:] = 0
        return self.cycles, self.damage

    def _push(self, rows: np.ndarray, values: np.ndarray) -> None:
        rows = np.nonzero(rows)[0]
        if not len(rows):
            return
        full = rows[self.n[rows] >= self.depth]
        if len(full):  # the oldest range out as half a cycle, so the stack keeps its bound
            self._tally(full, self.stack[full, 0], self.stack[full, 1], 0.5)
            self.stack[full, :-1] = self.stack[full, 1:]
            self.n[full] -= 1
        self.stack[rows, self.n[rows]] = values[rows] if np.ndim(values) else values
        self.n[rows] += 1

    def _count(self, rows: np.ndarray) -> None:
        """ASTM's rule on the stacks that just took a reversal, until none applies."""
        rows = np.nonzero(rows)[0]
        while len(rows):
            n = self.n[rows]
            rows = rows[n >= 3]
            if not len(rows):
                return
            n = self.n[rows]
            s = self.stack
            x = np.abs(s[rows, n - 1] - s[rows, n - 2])
            y = np.abs(s[rows, n - 2] - s[rows, n - 3])
            rows, n = rows[x >= y], n[x >= y]
            if not len(rows):
                return
            half = n == 3  # Y holds the start (the stack's first entry): half a cycle, the start moved on
            h, f = rows[half], rows[~half]
            self._tally(h, s[h, 0], s[h, 1], 0.5)
            s[h, :-1] = s[h, 1:]
            self.n[h] -= 1
            nf = self.n[f]
            self._tally(f, s[f, nf - 3], s[f, nf - 2], 1.0)
            s[f, nf - 3] = s[f, nf - 1]  # Y's two reversals off, the newest kept
            self.n[f] -= 2

    def _tally(self, rows: np.ndarray, a: np.ndarray, b: np.ndarray, count: float) -> None:
        if not len(rows):
            return
        size = np.abs(b - a)
        self.cycles[rows] += np.where(size >= self.floor, count, 0.0)
        self.damage[rows] += count * size ** self.exponent
        if self.record is not None:
            self.record += [(int(r), float(z), float(m), count) for r, z, m in zip(rows, size, (a + b) / 2)]


def count(history, exponent: float = 1.0) -> list[tuple[float, float]]:
    """(range, count) of one history's cycles, ranges merged, in ascending order (ASTM's table)."""
    flow = Rainflow(1, exponent, record=True)
    for v in history:
        flow.add(np.array([float(v)]))
    flow.finish()
    merged: dict[float, float] = {}
    for _, size, _, n in flow.record:
        merged[round(size, 12)] = merged.get(round(size, 12), 0.0) + n
    return sorted(merged.items())


def miner_passes(damage_sum: np.ndarray, passes: float, rated_cycles: float, rated_range: float,
                 exponent: float) -> np.ndarray:
    """How many passes a location lasts by Miner's rule: ``rated_cycles`` cycles of
    ``rated_range`` to failure, N(r) = rated_cycles (rated_range / r)^exponent for other ranges, so
    each pass's damage is sum(n r^m) / (rated_cycles rated_range^m) / passes."""
    per_pass = np.asarray(damage_sum) / (rated_cycles * rated_range ** exponent) / max(passes, 1e-300)
    with np.errstate(divide="ignore"):
        return np.where(per_pass > 0, 1.0 / per_pass, np.inf)
