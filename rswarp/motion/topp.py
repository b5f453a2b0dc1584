"""Path moves timed as TOPP-RA times a path: the fastest speed along it at each probe, from rest
to rest, every axis within its speed and acceleration and the path within its own speed cap
(``kernels.topp``, one path per thread on the CPU, in double precision)."""

from __future__ import annotations

import numpy as np

from ..kernels.topp import topp_kernel
from ..launch import Launcher, init_warp

_LAUNCHER: list = []  # the CPU launcher, made on first use


def launcher() -> Launcher:
    if not _LAUNCHER:
        _LAUNCHER.append(Launcher("cpu"))
    return _LAUNCHER[0]


def path_times(u: np.ndarray, q: np.ndarray, count: np.ndarray, cap: np.ndarray, vel: np.ndarray,
               acc: np.ndarray, head: np.ndarray | None = None,
               tail: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(time, speed du/dt) at each probe (from its path's start) of paths laid end to end: probes
    ``u`` (P,) and joints ``q`` (P, dof), path m the next ``count[m]`` (at least 2, u rising); the
    cap on du/dt at each probe (P,), or one per path (M,); per path its axes' speeds and
    accelerations (M, dof), and the shares of its way in zones: it speeds up to its cap no faster
    than evenly over [0, head] and slows down no faster than evenly over [tail, 1], so a blend
    starts where the zone does (0 and 1: no zone)."""
    head = np.zeros(len(count)) if head is None else head
    tail = np.ones(len(count)) if tail is None else tail
    wp = init_warp()
    count = np.ascontiguousarray(count, np.int32)
    first = (np.cumsum(count) - count).astype(np.int32)
    if len(cap) != len(u):
        cap = np.repeat(np.asarray(cap, np.float64), count)
    u = np.ascontiguousarray(u, np.float64)
    q = np.ascontiguousarray(q, np.float64)
    cap = np.ascontiguousarray(cap, np.float64)
    t = np.empty(len(u))
    x = np.empty(len(u))
    kernel = topp_kernel(q.shape[1])
    run = launcher()
    run.load(kernel)
    probes, written = ([wp.array(a, dtype=wp.float64, device="cpu", copy=False) for a in group]
                       for group in ((u, q, cap), (x, t)))
    run.launch(kernel, len(count), params=probes,
               inputs=[first, count, np.ascontiguousarray(vel, np.float64), np.ascontiguousarray(acc, np.float64),
                       np.ascontiguousarray(head, np.float64), np.ascontiguousarray(tail, np.float64)],
               whole=written)
    return t, np.sqrt(np.maximum(x, 0.0))
