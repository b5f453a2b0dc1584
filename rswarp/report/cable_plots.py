"""The plots of a cable run: tension, bend radius, clearance and torque over time (per cable, the
median across environments and the band from least to greatest), and the wear map along each cable
(per segment, the Archard wear and the time in contact, at their greatest across environments and
in the environment that wears most)."""

from __future__ import annotations

import numpy as np

from ..rsxml.units import length_text
from ..sim.cables import CableRun
from .cable_contact import run_worst
from .figures import figure_png
from .verdicts import Ratings

# (series key, title, unit, scale to the unit, file)
OVER_TIME = (("tension", "Tension", "N", 1.0, "tension.png"),
             ("bend", "Least bend radius", "mm", 1000.0, "bend_radius.png"),
             ("gap", "Least clearance", "mm", 1000.0, "clearance.png"),
             ("torque", "Torque about the cable", "N m", 1.0, "torque.png"))
WEAR_FILE = "wear.png"
PLOT_FILES = tuple(p[-1] for p in OVER_TIME) + (WEAR_FILE,)


def cable_plots(run: CableRun, ratings: Ratings = Ratings()) -> dict[str, bytes]:
    """Every plot as PNG bytes, by file name, each limit of ``ratings`` drawn and in its legend."""
    out = {name: _over_time(run, key, title, unit, scale, ratings) for key, title, unit, scale, name in OVER_TIME}
    out[WEAR_FILE] = _wear_map(run)
    return out


def _over_time(run: CableRun, key: str, title: str, unit: str, scale: float, ratings: Ratings = Ratings()) -> bytes:
    t = run.times

    def draw(ax):
        for c in run.cables:
            s = getattr(c, key)
            line, = ax.plot(t, s.median * scale, label=f"{c.name} (median)")
            ax.fill_between(t, s.low * scale, s.high * scale, color=line.get_color(), alpha=0.25, lw=0,
                            label=f"{c.name} (least to greatest)")
            for value, style, what in _limits(c, key, ratings):
                ax.axhline(value * scale, color=line.get_color(), ls=style,
                           label=f"{c.name} {what}: {_value(value, scale, unit)}")
        if key == "bend":
            _plain_log_axis(ax)
        if key == "gap":
            ax.axhline(0.0, color="k", lw=0.8, label="touching (0 mm)")

    return figure_png(draw, f"{title} over {run.envs} environment(s)", "time (s)", f"{title.lower()} ({unit})")


def _limits(c, key: str, ratings: Ratings) -> list[tuple[float, str, str]]:
    """(value in SI, line style, name) of each limit a plot of ``key`` draws for cable ``c``."""
    if key == "bend":
        return [(c.allowed_bend_radius, "--", "allowed (dynamic)"), (ratings.static(c), ":", "static (kink)")]
    if key == "tension" and getattr(c, "axial_stiffness", 0) > 0:
        return [(ratings.max_strain * c.axial_stiffness, "--", f"taut (strain {100 * ratings.max_strain:g} %)")]
    return []


def _value(value: float, scale: float, unit: str) -> str:
    return length_text(value, 1 / scale, unit) if unit in ("mm", "m") else f"{value * scale:.3g} {unit}"


def _plain_log_axis(ax) -> None:
    """A log axis ticked in plain numbers of its unit (200, 300, 500 mm; never 3x10^2)."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    ax.set_yscale("log")
    low, high = ax.get_ylim()
    decades = np.log10(max(high, 1e-12) / max(low, 1e-12))
    subs = (1.0, 1.5, 2.0, 3.0, 5.0, 7.0) if decades <= 1.2 else (1.0, 2.0, 5.0) if decades <= 3 else (1.0,)
    ax.yaxis.set_major_locator(LogLocator(base=10, subs=subs))
    ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    ax.yaxis.set_minor_formatter(NullFormatter())


def _wear_map(run: CableRun) -> bytes:
    """Archard wear (J) along each cable: greatest over the environments that finished, and in the
    environment of the worst wear, marked, with the worst rub marked too (``cable_contact``); the
    time in contact on a second axis, dotted."""

    def draw(ax):
        twin = ax.twinx()
        twin.set_ylabel("time in contact (s), greatest")
        for c in run.cables:
            done = np.nonzero(c.status == "ok")[0]
            if not len(done):
                continue
            wear = c.segment_wear[done]
            line, = ax.plot(c.segments, wear.max(axis=0), marker=".", label=f"{c.name}: greatest")
            colour = line.get_color()
            worst = run_worst(c, done)
            w, rub = worst["worst_wear"], worst["worst_rub"]
            if w is not None:
                ax.plot(c.segments, c.segment_wear[w["environment"]], ls="--", color=colour,
                        label=f"{c.name}: environment {w['environment']}, the worst wear's")
                ax.plot([w["at_m"]], [w["wear_J"]], marker="o", ms=9, mfc="none", color=colour, ls="none",
                        label=f"{c.name}: worst wear {w['wear_J']:.3g} J on {w['on']} (environment "
                              f"{w['environment']}, {w['at_m']:.3f} m along)")
            if rub is not None and rub["segment"] is not None:
                ax.axvline(rub["at_m"], color=colour, ls="-.", lw=1.0,
                              label=f"{c.name}: worst rub {rub['force_N']:.3g} N on {rub['on']} (environment "
                                 f"{rub['environment']}, {rub['at_m']:.3f} m along)")
            twin.plot(c.segments, c.wear_contact_time[done].max(axis=0), ls=":", color=colour, alpha=0.7)
            ax.plot([], [], ls=":", color=colour, alpha=0.7, label=f"{c.name}: time in contact, greatest (right axis)")

    return figure_png(draw, f"Wear along the cable over {run.envs} environment(s)", "along the cable (m)",
                      "normal force x sliding distance (J)")
