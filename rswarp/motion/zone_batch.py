"""A batch's zones blended together: for each move that follows one ending in a zone, both timed
by the batch, ``zones.overlap`` and ``zones.blend`` of the pair at once, the same arithmetic in
the same order. A blend reads only the two moves' own samples (the one before unblended), so the
pairs are independent of each other and of where the trajectory has got to; the planner takes a
pair's answer where its move follows that very move (``zones.Ahead``), else blends it itself."""

from __future__ import annotations

import numpy as np

from .zones import EPS, Ahead, shares


def blends(steps: list, timed: dict, tcp: dict) -> None:
    """Each timed step's ``timed[id(step)]`` given its ``zones.Ahead``: its ramps and, after a
    step timed before it that ends in a zone, their overlap and its joints blended."""
    pairs = []
    for a, b in zip(steps, steps[1:]):
        zone = a.motion.zone
        if isinstance(timed.get(id(a)), tuple) and isinstance(timed.get(id(b)), tuple) and zone is not None \
                and not zone.fine and not b.chained:
            pairs.append((a, b))
    after = _pairs(pairs, timed, tcp) if pairs else {}
    for b in steps:
        if not isinstance(timed.get(id(b)), tuple):
            continue
        t, q, share, (ramp_in, ramp_out) = timed[id(b)]
        t_prev, zone, tau, kept, blended = after.get(id(b), (None,) * 5)
        timed[id(b)] = (t, q, share, Ahead(ramp_in, ramp_out, t_prev, zone, tau, kept, blended))


class _Rows:
    """The samples of the steps in pairs, end to end: times ``t``, shares ``s``, joints ``q``; per
    step where they start (``first``), how many (``count``), its TCP path (``length``, ``turn``,
    the length gone at shares: ``probe_len``, ``probe_s`` padded with their last) and ramps."""

    def __init__(self, steps: list, timed: dict, tcp: dict):
        got = [timed[id(s)] for s in steps]
        self.count = np.array([len(g[0]) for g in got])
        self.first = np.cumsum(self.count) - self.count
        self.t = np.concatenate([g[0] for g in got])
        self.q = np.concatenate([g[1] for g in got])
        self.s = np.concatenate([g[2] for g in got])
        self.ramp_in, self.ramp_out = np.array([g[3] for g in got]).T
        self.q0 = np.array([s.q0 for s in steps])
        paths = [tcp.get(id(s)) for s in steps]
        straight = np.array([p is None for p in paths])
        self.probes = np.array([2 if p is None else len(p.gone) for p in paths])
        self.probe_len = np.empty((len(steps), self.probes.max()))
        self.probe_s = np.empty_like(self.probe_len)
        rows = np.flatnonzero(straight)  # ``zones.straight``: 0 to its length at shares 0 and 1
        self.probe_len[rows, 0], self.probe_len[rows, 1:] = 0.0, np.array([steps[r].length for r in rows])[:, None]
        self.probe_s[rows, 0], self.probe_s[rows, 1:] = 0.0, 1.0
        for n in set(self.probes[~straight].tolist()):  # ``zones.jointed``: its probes
            rows = np.flatnonzero(~straight & (self.probes == n))
            self.probe_len[rows, :n] = np.array([paths[r].gone for r in rows])
            self.probe_len[rows, n:] = self.probe_len[rows, n - 1:n]
            self.probe_s[rows, :n], self.probe_s[rows, n:] = shares(n), 1.0
        self.length = self.probe_len[np.arange(len(steps)), self.probes - 1]  # a Segment's length
        self.turn = np.array([s.turn if p is None else p.turn for s, p in zip(steps, paths)])
        self.last = self.first + self.count - 1
        self.duration = self.t[self.last]

    def share_at(self, r: np.ndarray, gone: np.ndarray) -> np.ndarray:
        """``zones._share_at`` of rows ``r`` at lengths ``gone``."""
        length, shares = self.probe_len[r], self.probe_s[r]
        inside = (gone > 0.0) & ~(gone > length[np.arange(len(r)), self.probes[r] - 1])
        k = np.maximum((length < gone[:, None]).sum(axis=1), 1)  # np.searchsorted(side="left")
        i = np.arange(len(r))
        k = np.minimum(k, self.probes[r] - 1)
        a, b = length[i, k - 1], length[i, k]
        with np.errstate(divide="ignore", invalid="ignore"):
            s = shares[i, k - 1] + (shares[i, k] - shares[i, k - 1]) * (gone - a) / (b - a)
        return np.where(gone <= 0.0, 0.0, np.where(inside, s, np.inf))


def _pairs(pairs: list, timed: dict, tcp: dict) -> dict:
    """{id(later step): (earlier step's times, zone, overlap, samples kept, blended joints)}."""
    rows: dict = {}
    for step in (s for pair in pairs for s in pair):
        rows.setdefault(id(step), (len(rows), step))
    data = _Rows([s for _, s in rows.values()], timed, tcp)
    a = np.array([rows[id(p)][0] for p, _ in pairs])
    b = np.array([rows[id(n)][0] for _, n in pairs])
    zones = [p.motion.zone for p, _ in pairs]
    tau = _overlaps(data, a, b, np.array([z.pzone_tcp for z in zones]), np.array([z.zone_ori for z in zones]))
    kept, blended = _blends(data, a, b, tau)
    out = {}
    for j, (p, n) in enumerate(pairs):
        out[id(n)] = (timed[id(p)][0], zones[j], float(tau[j]), kept.get(j), blended.get(j))
    return out


def _overlaps(d: _Rows, a: np.ndarray, b: np.ndarray, pzone: np.ndarray, zone_ori: np.ndarray) -> np.ndarray:
    """``zones.overlap`` of pairs of rows (``a`` before ``b``) with their zones' sizes."""
    z = np.minimum(np.minimum(pzone, d.length[a] / 2), d.length[b] / 2)
    zo = np.minimum(np.minimum(zone_ori, np.where(d.turn[a] > 0, d.turn[a] / 2, np.inf)),
                    np.where(d.turn[b] > 0, d.turn[b] / 2, np.inf))  # ``zones.overlap``'s cut
    with np.errstate(divide="ignore", invalid="ignore"):
        left = np.where(d.turn[a] > 0, 1.0 - (zo + EPS) / d.turn[a], 0.0)
        near = np.where(d.turn[b] > 0, (zo + EPS) / d.turn[b], 1.0)
    s_in = np.maximum(d.share_at(a, d.length[a] - z - EPS), left)
    first = np.minimum(_count(_at(d.s), d.first[a], d.last[a] + 1, s_in, False), d.last[a])  # first inside
    leave = d.duration[a] - np.where(s_in > 0.0, d.t[first], 0.0)
    s_out = np.minimum(d.share_at(b, z + EPS), near)
    count = _count(_at(d.s), d.first[b], d.last[b] + 1, s_out, True) - d.first[b]
    enter = np.where(count > 0, d.t[d.first[b] + np.maximum(count - 1, 0)], 0.0)
    tau = np.minimum(leave, enter)
    return np.where(tau <= 0.0, 0.0, np.maximum(0.0, np.minimum(np.minimum(tau, d.ramp_out[a]), d.ramp_in[b])))


def _blends(d: _Rows, a: np.ndarray, b: np.ndarray, tau: np.ndarray) -> tuple[dict, dict]:
    """``zones.blend`` of the pairs that overlap: {pair: samples of ``a`` kept}, {pair: ``b``'s
    joints blended}."""
    on = np.flatnonzero(tau > 0.0)
    if not len(on):
        return {}, {}
    a, b, tau = a[on], b[on], tau[on]
    start = d.duration[a] - tau
    kept = _count(_at(d.t), d.first[a], d.last[a] + 1, start, True) - d.first[a]
    shared = _count(_at(d.t), d.first[b], d.last[b] + 1, tau, True) - d.first[b]
    pair = np.repeat(np.arange(len(on)), shared)  # b's samples at or before tau, each with its pair
    j = d.first[b][pair] + np.arange(len(pair)) - (np.cumsum(shared) - shared)[pair]
    at = np.minimum(start[pair] + d.t[j], d.duration[a][pair])
    # prev's samples with its start (time 0, q0) in front: e = 0 its start, e = i + 1 its sample i
    base, n = d.first[a][pair], d.count[a][pair]
    e = np.minimum(_count(lambda i: _extended(d.t, base, i), kept[pair], n + 1, at, True), n)
    t0, t1 = _extended(d.t, base, e - 1), _extended(d.t, base, e)
    w = ((at - t0) / np.maximum(t1 - t0, 1e-300))[:, None]
    q0 = np.where((e - 1 == 0)[:, None], d.q0[a][pair], d.q[np.maximum(base + e - 2, 0)])
    q1 = d.q[base + e - 1]
    add = q0 * (1.0 - w) + q1 * w - d.q[d.last[a]][pair]
    moved = d.q.copy()
    moved[j] += add
    kept_out, blended = {}, {}
    for k, p in enumerate(on):
        kept_out[p] = int(kept[k])
        blended[p] = moved[d.first[b[k]]:d.last[b[k]] + 1]
    return kept_out, blended


def _extended(t: np.ndarray, base: np.ndarray, i: np.ndarray) -> np.ndarray:
    """A move's times with its start in front: 0 at i = 0, its sample i - 1 after."""
    return np.where(i == 0, 0.0, t[np.maximum(base + i - 1, 0)])


def _at(values: np.ndarray):
    """``values`` read at indices (those past its end read as its last)."""
    return lambda i: values[np.minimum(i, len(values) - 1)]


def _count(get, lo: np.ndarray, hi: np.ndarray, x: np.ndarray, right: bool) -> np.ndarray:
    """Per row, ``np.searchsorted(values[lo:hi], x, side)`` + lo, each row's values sorted, ``get``
    reading them at indices: a bisection of all rows at once."""
    lo, hi = lo.copy(), hi.copy()
    while True:
        active = lo < hi
        if not active.any():
            return lo
        mid = np.where(active, (lo + hi) // 2, lo)
        v = get(mid)
        go = active & ((v <= x) if right else (v < x))
        lo = np.where(go, mid + 1, lo)
        hi = np.where(active & ~go, mid, hi)
