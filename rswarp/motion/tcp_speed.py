"""The TCP's speed over a trajectory's samples, in each move's work object (the programmed speed
is relative to it): the flange's poses by its own kernel over all samples in chunks, the tool and
the work object applied, a stationary tool's and a cell's moving work object too
(``motion.speeds`` reads it)."""

from __future__ import annotations

import numpy as np

from .paths import angles
from .tcp import flange_poses, frames

CHUNK = 200_000  # samples per FK launch and per batch of products: memory stays bounded


def tcp_samples(kin, p, table: tuple) -> np.ndarray:
    """(T,) the TCP's speed (m/s) over each sample interval, in the frames ``table``
    (``interval_frames``) gives it. Where both ends of an interval share the work object's frame
    it cancels out of their distance."""
    n = len(p.times)
    pre, post, inverted, ip, ic = table
    tcp = np.zeros(n)
    dt = np.maximum(np.diff(p.times), 1e-12)
    for lo in range(1, n, CHUNK):
        hi = min(lo + CHUNK, n)
        f = flange_poses(kin, p.q[lo - 1:hi])
        ea, eb = ip[lo:hi], ic[lo:hi]
        xa, xb = _tool_point(f[:-1], post, inverted, ea), _tool_point(f[1:], post, inverted, eb)
        moving = np.flatnonzero(ea != eb)
        if len(moving):  # the work object's frame moves (a cell's unit): each end in its own
            xa[moving] = _relative(pre, post, inverted, ea[moving], f[:-1][moving])[:, :3, 3]
            xb[moving] = _relative(pre, post, inverted, eb[moving], f[1:][moving])[:, :3, 3]
        tcp[lo:hi] = np.linalg.norm(xb - xa, axis=1) / dt[lo - 1:hi - 1]
    return tcp


def turn_at(kin, p, table: tuple, rows: np.ndarray) -> np.ndarray:
    """The TCP's turn rate (rad/s) over the sample intervals ``rows`` (rows r-1 to r)."""
    pre, post, inverted, ip, ic = table
    if len(p.times) < 2 or not len(rows):
        return np.zeros(len(rows))
    rows = np.clip(rows, 1, len(p.times) - 1)
    f = flange_poses(kin, np.vstack([p.q[rows - 1], p.q[rows]]))
    a = _relative(pre, post, inverted, ip[rows], f[:len(rows)])
    b = _relative(pre, post, inverted, ic[rows], f[len(rows):])
    return angles(a[:, :3, :3], b[:, :3, :3]) / np.maximum(p.times[rows] - p.times[rows - 1], 1e-12)


def _tool_point(f: np.ndarray, post, inverted, idx: np.ndarray) -> np.ndarray:
    """(N, 3) the TCP of flange poses ``f`` up to the work object's fixed frame: F @ post's origin,
    or F^-1 @ post's for a stationary tool."""
    t = post[idx, :3, 3]
    out = np.einsum("nij,nj->ni", f[:, :3, :3], t) + f[:, :3, 3]
    inv = inverted[idx]
    if inv.any():
        r = f[inv, :3, :3]
        out[inv] = np.einsum("nji,nj->ni", r, t[inv] - f[inv, :3, 3])
    return out


def interval_frames(mech, p, counted: np.ndarray) -> tuple:
    """(pre, post, inverted) a table of frames, the TCP in a work object being pre @ F @ post of
    the flange F (its inverse for a stationary tool), and per interval r the entries for rows r-1
    and r: the move's frames, or, in a cell where its external axes move, the frames of each row."""
    n = len(p.times)
    table, made = [(np.eye(4), np.eye(4), False)], {}
    ip, ic = np.zeros(n, int), np.zeros(n, int)

    def entry(m, ext) -> int:
        fast = (id(m.tool), id(m.wobj), None if ext is None else tuple(ext))  # the data objects, held by moves
        if fast not in made:
            key = (m.tool, m.wobj, fast[2])
            if key not in made:
                made[key] = len(table)
                table.append(_frames_of(mech, p, m, ext))
            made[fast] = made[key]
        return made[fast]

    for k, move in enumerate(p.moves):
        if not counted[k]:
            continue
        a, b = move.rows
        m = move.motion
        ext = None if p.ext is None or not p.ext.shape[1] else p.ext[a - 1:b]
        if ext is not None and np.ptp(ext, axis=0).max() > 0:
            rows = [entry(m, e) for e in ext]
            ip[a:b], ic[a:b] = rows[:-1], rows[1:]
        else:
            ip[a:b] = ic[a:b] = entry(m, None if ext is None else ext[0])
    pre, post, inverted = (np.array(x) for x in zip(*table))
    return pre, post, inverted.astype(bool), ip, ic


def _frames_of(mech, p, m, ext) -> tuple[np.ndarray, np.ndarray, bool]:
    """(pre, post, inverted) of a move's frames (``tcp.Frames.relative`` as two products); the
    flange in the world where the move has no tool and work object a robot can move."""
    base = mech.base_frame.matrix() if mech.base_frame is not None else np.eye(4)
    if m.tool is None or m.wobj is None:
        return base, np.eye(4), False
    try:
        fr = frames(mech, m.tool, m.wobj) if p.framer is None or ext is None else p.framer(m.tool, m.wobj, ext)
    except ValueError:
        return base, np.eye(4), False
    if fr.stationary:
        return np.linalg.inv(fr.wobj), np.linalg.inv(fr.base) @ fr.tool, True
    return np.linalg.inv(fr.wobj) @ fr.base, fr.tool, False


def _relative(pre, post, inverted, idx: np.ndarray, f: np.ndarray) -> np.ndarray:
    """The TCP poses (N, 4, 4) of flange poses ``f`` in the frames of table entries ``idx``."""
    g = f.copy()
    inv = inverted[idx]
    if inv.any():
        rt = np.swapaxes(f[inv, :3, :3], -1, -2)
        g[inv, :3, :3] = rt
        g[inv, :3, 3] = -(rt @ f[inv, :3, 3:4])[..., 0]
    return pre[idx] @ g @ post[idx]
