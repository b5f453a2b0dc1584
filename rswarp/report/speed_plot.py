"""``rswarp program --speed-plot FILE.png``: the TCP's speed over the run (mm/s against s), each
move's programmed speed as a step line and the moves' boundaries faint, so a programmer sees where
the robot is slower than the program asks (``motion.speeds``). PNG via matplotlib (Agg)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..files import atomic_write
from ..outputs import record
from .figures import figure_png

MOST_POINTS = 20_000  # a longer curve is drawn as its envelope: each bucket's least and greatest speed
MOST_BOUNDARIES = 1_000  # moves whose boundaries are drawn; more would grey the plot over


def write_speed_plot(path: str, p, speeds, title: str) -> None:
    """The plot of plan ``p``'s ``speeds`` (``motion.speeds.Speeds``) written atomically to ``path``,
    noted as rswarp's in its folder's manifest (so the next run may replace it)."""
    png = figure_png(lambda ax: _draw(ax, p, speeds), title, "time [s]", "TCP speed [mm/s]")
    atomic_write(path, png)
    folder = Path(path).parent
    record(folder if str(folder) else Path("."), [Path(path).name])


def _draw(ax, p, speeds) -> None:
    """The measured speed, the programmed steps and the boundaries on one set of axes."""
    x, y = _envelope(speeds.mid[1:], 1000.0 * speeds.tcp[1:], MOST_POINTS)
    ax.plot(x, y, color="tab:blue", lw=1.0, label="TCP speed")
    steps = _steps(p, speeds)
    if steps is not None:
        ax.plot(*steps, color="tab:orange", lw=1.0, ls="--", label="programmed")
    starts = [m.start for m in p.moves if m.end > m.start]
    if 0 < len(starts) <= MOST_BOUNDARIES:
        ax.vlines(starts, 0, 1, transform=ax.get_xaxis_transform(), colors="0.5", lw=0.5, alpha=0.3)
    ax.set_xlim(0.0, max(float(p.times[-1]), 1e-3))
    ax.set_ylim(bottom=0.0)


def _steps(p, speeds) -> tuple[np.ndarray, np.ndarray] | None:
    """Each move's programmed speed (mm/s) from its start to its end, one move's step into the
    next's; a gap for a wait or a move timed by \\T (none programmed)."""
    keep = np.array([m.end > m.start for m in p.moves], bool)
    v = 1000.0 * speeds.programmed[keep]
    if not np.isfinite(v).any():
        return None
    start = np.array([m.start for m in p.moves])[keep]
    end = np.array([m.end for m in p.moves])[keep]
    return np.column_stack([start, end]).ravel(), np.repeat(v, 2)


def _envelope(x: np.ndarray, y: np.ndarray, most: int) -> tuple[np.ndarray, np.ndarray]:
    """At most ``most`` points of a curve: as it is, or each bucket's least and greatest value at
    its ends, so a dip a pixel wide still shows."""
    if len(x) <= most:
        return x, y
    size = int(np.ceil(2 * len(x) / most))
    cut = len(x) // size * size
    yb = y[:cut].reshape(-1, size)
    xb = x[:cut].reshape(-1, size)
    xs = np.column_stack([xb[:, 0], xb[:, -1]]).ravel()
    ys = np.column_stack([yb.min(axis=1), yb.max(axis=1)]).ravel()
    return np.append(xs, x[cut:]), np.append(ys, y[cut:])
