"""The plots of a cable run: tension, bend radius, clearance and torque over time (per cable, the
median across environments and the band from least to greatest), and the wear map along each cable
(per segment, the Archard wear and the time in contact, at their greatest across environments and
in the environment that wears most)."""

from __future__ import annotations

import numpy as np

from ..rsxml.units import length_text
from ..sim.cable_results import worst_wear
from ..sim.cables import CableRun
from .figures import figure_png

# (series key, title, unit, scale to the unit, file)
OVER_TIME = (("tension", "Tension", "N", 1.0, "tension.png"),
             ("bend", "Least bend radius", "mm", 1000.0, "bend_radius.png"),
             ("gap", "Least clearance", "mm", 1000.0, "clearance.png"),
             ("torque", "Torque about the cable", "N m", 1.0, "torque.png"))
WEAR_FILE = "wear.png"
PLOT_FILES = tuple(p[-1] for p in OVER_TIME) + (WEAR_FILE,)


def cable_plots(run: CableRun) -> dict[str, bytes]:
    """Every plot as PNG bytes, by file name."""
    out = {name: _over_time(run, key, title, unit, scale) for key, title, unit, scale, name in OVER_TIME}
    out[WEAR_FILE] = _wear_map(run)
    return out


def _over_time(run: CableRun, key: str, title: str, unit: str, scale: float) -> bytes:
    t = run.times

    def draw(ax):
        for c in run.cables:
            s = getattr(c, key)
            line, = ax.plot(t, s.median * scale, label=f"{c.name} (median)")
            ax.fill_between(t, s.low * scale, s.high * scale, color=line.get_color(), alpha=0.25, lw=0,
                            label=f"{c.name} (least to greatest)")
            if key == "bend":
                ax.set_yscale("log")
                ax.axhline(c.allowed_bend_radius * scale, color=line.get_color(), ls="--",
                           label=f"{c.name} allowed: {length_text(c.allowed_bend_radius, 1 / scale, unit)}")
        if key == "gap":
            ax.axhline(0.0, color="k", lw=0.8)

    return figure_png(draw, f"{title} over {run.envs} environment(s)", "time (s)", f"{title.lower()} ({unit})")


def _wear_map(run: CableRun) -> bytes:
    """Archard wear (J) along each cable: greatest over the environments that finished, and in the
    environment of the worst segment; the time in contact on a second axis."""

    def draw(ax):
        twin = ax.twinx()
        twin.set_ylabel("time in contact (s), greatest")
        for c in run.cables:
            done = np.nonzero(c.status == "ok")[0]
            if not len(done):
                continue
            wear = c.segment_wear[done]
            line, = ax.plot(c.segments, wear.max(axis=0), marker=".", label=f"{c.name}: greatest")
            worst = worst_wear(c, done)
            if worst is not None:
                e, s, j = worst
                ax.plot(c.segments, c.segment_wear[e], ls="--", color=line.get_color(),
                        label=f"{c.name}: environment {e} (worst: on {c.links[j]})")
            twin.plot(c.segments, c.wear_contact_time[done].max(axis=0), ls=":", color=line.get_color(), alpha=0.7)

    return figure_png(draw, f"Wear along the cable over {run.envs} environment(s)", "along the cable (m)",
                      "normal force x sliding distance (J)")
