"""Corner paths as ABB's controller makes them: a chain of linear and circular moves, each ending
in a zone the next one takes at once, is one path in Cartesian space. Within a zone the TCP leaves
the programmed point's corner on a parabola ("a corner path (parabola) is generated as soon as the
edge of the zone is reached", ABB's RAPID reference, zonedata): over the zone, the move before
(from where it enters the zone to its point) and the move after (from its point to where it
leaves the zone) are blended in proportion to the share of the corner, which for two lines is the
parabola whose tangents they are, met at their own speed at both ends. The orientation blends over
``pzone_ori`` (at least ``pzone_tcp``, as the controller makes it) from the move before to the one
after, each turning on as it would, on a quintic share flat to its second derivative at both ends.
The speed changes from one move's to the next's within the corner ("the transition will be
smooth and take place within the corner path"). Each zone is cut to half of either move.

The chain's parameter ``s`` is the moves' own lengths laid end to end (m), each corner centred on
its programmed point; move ``k`` is at ``s - offset[k]`` along its own path, and the path is timed
along its length (``arc``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .paths import angles, path, quaternions, rotations, slerps

PROBE_STEP = 0.002  # m of the chain between probes
FINE_STEP = PROBE_STEP / 4  # in a corner's zones
PROBE_TURN = 0.02  # rad of turn between probes
CORNER_PROBES = 16  # stretches of a corner at least (an even number: its middle is a probe)
FAR_TURN = np.pi / 2  # rad between the two orientations a corner blends: past it, each is held at its end
TOP_CAP = 1e9  # m/s: the cap where neither the TCP's speed nor its turn bounds the path


@dataclass(frozen=True)
class Member:
    """One move of a chain: where its path starts and ends (TCP poses in the work object, 4x4),
    the circle point of a circular move, its speeds (m/s, rad/s) and its zone's two radii (m)."""

    start: np.ndarray
    end: np.ndarray
    circle: np.ndarray | None
    v_tcp: float
    v_ori: float
    pzone: float = 0.0
    ozone: float = 0.0


@dataclass(frozen=True)
class Corners:
    """A chain probed: the parameter ``s`` of each probe (m), the TCP's pose there (P, 4, 4, in the
    work object), its speed caps (m/s and rad/s) there, where each move ends in ``s`` (the middle
    of its corner; the last at the chain's end) and at which probe, and the path's length gone at
    each probe (``arc``, m; ``total`` in all)."""

    s: np.ndarray
    poses: np.ndarray
    v_tcp: np.ndarray
    v_ori: np.ndarray
    ends: np.ndarray
    end_probe: np.ndarray
    arc: np.ndarray
    total: float


def beta(x: np.ndarray) -> np.ndarray:
    """The orientation blend's share at ``x`` of its way (0 to 1): quintic, flat to the second
    derivative at both ends."""
    return x * x * x * (10.0 + x * (-15.0 + 6.0 * x))


def corner_path(members: list[Member]) -> Corners:
    """The chain of ``members`` probed every ``PROBE_STEP`` (and ``PROBE_TURN``), each corner at
    ``CORNER_PROBES`` stretches at least."""
    paths = [path(m.start, m.end, m.circle) for m in members]
    length = np.array([p[1] for p in paths])
    turn = np.array([p[2] for p in paths])
    zp = np.array([min(m.pzone, a / 2, b / 2) for m, a, b in zip(members, length, length[1:])] + [0.0])
    zo = np.array([max(min(m.ozone, a / 2, b / 2), z) for m, a, b, z in zip(members, length, length[1:], zp)] + [0.0])
    offset = np.concatenate([[0.0], np.cumsum(length)[:-1]])
    s, end_probe = _probes(length, turn, zp, zo, offset)
    own = np.clip(np.searchsorted(offset, s, side="right") - 1, 0, len(members) - 1)
    poses = _evaluate(paths, length, own, s - offset[own])
    near, gap = _nearest_corner(offset[1:], s)
    in_pos = np.abs(gap) < zp[near]
    in_ori = np.abs(gap) < zo[near]
    _parabolas(paths, length, poses, np.flatnonzero(in_pos), near, gap, zp)
    _orientations(paths, length, poses, np.flatnonzero(in_ori), near, s, offset, gap, zo)
    v_tcp, v_ori = _speeds(members, own, near, gap, zp, in_pos)
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(poses[:, :3, 3], axis=0), axis=1))])
    return Corners(s, poses, v_tcp, v_ori, np.append(offset[1:], s[-1]), end_probe, arc, float(arc[-1]))


def _nearest_corner(points: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per probe, the corner whose programmed point (``points``, in s) is nearest, and how far
    past it the probe is (m of s, negative before it)."""
    j = np.searchsorted(points, s)
    lo, hi = np.clip(j - 1, 0, len(points) - 1), np.clip(j, 0, len(points) - 1)
    near = np.where(np.abs(s - points[lo]) <= np.abs(s - points[hi]), lo, hi)
    return near, s - points[near]


def _probes(length, turn, zp, zo, offset) -> tuple[np.ndarray, np.ndarray]:
    """The probes' ``s`` (each move's part outside the corners, then its corner, evenly within
    each; a corner's zones, where the joints turn from one move's way to the next's, at a quarter
    of the step) and the probe at each move's end (its corner's middle; the chain's end)."""
    pieces = []
    count = len(length)
    for k in range(count):
        lo, hi = offset[k] + (zp[k - 1] if k else 0.0), offset[k] + length[k] - zp[k]
        rate = turn[k] / length[k]
        early = min(lo + (zo[k - 1] - zp[k - 1] if k else 0.0), hi)  # the orientation zones either side
        late = max(hi - (zo[k] - zp[k]), early)
        for a, b, step in ((lo, early, FINE_STEP), (early, late, PROBE_STEP), (late, hi, FINE_STEP)):
            if b - a > 1e-9:
                steps = max(int(np.ceil(max((b - a) / step, rate * (b - a) / PROBE_TURN))), 1)
                pieces.append(a + (b - a) * np.arange(steps) / steps)
        if k < count - 1 and zp[k] > 0:
            steps = max(int(np.ceil(2 * zp[k] / FINE_STEP)), CORNER_PROBES)
            steps += steps % 2
            pieces.append(hi + 2 * zp[k] * np.arange(steps) / steps)
    total = offset[-1] + length[-1]
    s = np.concatenate(pieces + [[total]])
    ends = np.append(offset[1:], total)
    end_probe = np.minimum(np.searchsorted(s, ends - 1e-9), len(s) - 1)
    s[end_probe] = ends  # each move's end a probe, exactly
    return s, end_probe


def _evaluate(paths, length, k: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Poses of moves ``k`` at ``d`` (m) along their own paths (before their start or past their
    end: the path and its turn continued)."""
    out = np.empty((len(k), 4, 4))
    share = d / length[k]
    order = np.argsort(k, kind="stable")
    moves, first = np.unique(k[order], return_index=True)
    for j, rows in zip(moves, np.split(order, first[1:])):
        out[rows] = paths[j][0](share[rows])
    return out


def _parabolas(paths, length, poses, rows, near, gap, zp) -> None:
    """The positions of probes ``rows`` in a corner: the move before from its zone's edge to its
    point and the move after from its point to its zone's edge, blended by the share of the corner."""
    if not len(rows):
        return
    k, z = near[rows], zp[near[rows]]
    x = (gap[rows] + z) / (2 * z)
    before = _evaluate(paths, length, k, length[k] - z + z * x)[:, :3, 3]
    after = _evaluate(paths, length, k + 1, z * x)[:, :3, 3]
    poses[rows, :3, 3] = before + x[:, None] * (after - before)


def _orientations(paths, length, poses, rows, near, s, offset, gap, zo) -> None:
    """The orientations of probes ``rows`` in a corner's orientation zone: the move before's and
    the move after's (each turning on as it would) slerped by ``beta`` of the share of the zone."""
    if not len(rows):
        return
    k, z = near[rows], zo[near[rows]]
    w = beta((gap[rows] + z) / (2 * z))
    d0, d1 = s[rows] - offset[k], s[rows] - offset[k + 1]
    before = _evaluate(paths, length, k, d0)[:, :3, :3]
    after = _evaluate(paths, length, k + 1, d1)[:, :3, :3]
    # a turn continued far past its move could pass the half turn between the two, where the
    # shortest way flips: those corners blend the moves' own orientations, each held at its end
    far = np.unique(k[angles(before, after) > FAR_TURN])
    if len(far):
        held = np.isin(k, far)
        before[held] = _evaluate(paths, length, k[held], np.minimum(d0[held], length[k[held]]))[:, :3, :3]
        after[held] = _evaluate(paths, length, k[held] + 1, np.maximum(d1[held], 0.0))[:, :3, :3]
    poses[rows, :3, :3] = _slerp_rows(before, after, w)


def _slerp_rows(a: np.ndarray, b: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Rotations a share ``w`` of the way from ``a`` to ``b`` (N, 3, 3), row by row."""
    qa, qb = quaternions(a), quaternions(b)
    dot = np.einsum("ij,ij->i", qa, qb)
    qb = np.where((dot < 0)[:, None], -qb, qb)
    half = np.arccos(np.clip(np.abs(dot), 0.0, 1.0))
    return rotations(slerps(qa, qb, w, half))


def _speeds(members, own, near, gap, zp, in_pos) -> tuple[np.ndarray, np.ndarray]:
    """Each probe's TCP speed and turn rate caps: its move's, changing from one move's to the
    next's across a corner."""
    v = np.array([m.v_tcp for m in members])
    o = np.array([m.v_ori for m in members])
    v_tcp, v_ori = v[own].copy(), o[own].copy()
    rows = np.flatnonzero(in_pos)
    if len(rows):
        k = near[rows]
        w = (gap[rows] + zp[k]) / (2 * zp[k])
        v_tcp[rows] = v[k] + w * (v[k + 1] - v[k])
        v_ori[rows] = o[k] + w * (o[k + 1] - o[k])
    return v_tcp, v_ori


def caps(c: Corners) -> np.ndarray:
    """The cap on d(arc)/dt at each probe: the TCP's speed, and its turn's over the turn's rate
    along the path (the faster of the stretches either side)."""
    angle = angles(c.poses[:-1, :3, :3], c.poses[1:, :3, :3])
    with np.errstate(divide="ignore", invalid="ignore"):
        rate = np.where(np.diff(c.arc) > 0, angle / np.diff(c.arc), 0.0)
        turning = np.concatenate([[rate[0]], np.maximum(rate[:-1], rate[1:]), [rate[-1]]])
        out = np.minimum(c.v_tcp, np.where(turning > 1e-9, c.v_ori / turning, np.inf))
    return np.minimum(out, TOP_CAP)
