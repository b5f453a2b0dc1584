"""Datasheet work-range figures: the wrist-centre envelope (the flange's, for robots of four axes
or fewer, such as palletizers, whose datasheets measure to the flange) seen from the side (plane of
J1 = 0) and from above, in the file's length unit, with the reach annotated. Every length a label
gives is the measured figure to 0.1 mm (``reach 1.6533 m``, ``reach 1653.3 mm``), never rounded to
the plot's scale. PNG via matplotlib (Agg)."""

from __future__ import annotations

import io

import numpy as np

from ..files import atomic_write
from ..rsxml.model import Mechanism
from ..rsxml.units import length_text
from ..sim.workspace import Workspace


def _png(fig) -> bytes:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=120, bbox_inches="tight")
    return buf.getvalue()


def figure_png(draw, title: str, xlabel: str, ylabel: str) -> bytes:
    """A plot as PNG bytes: ``draw(ax)`` fills one set of axes, which gets the title, labels, a grid
    and a legend."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 4.5))
    ax = fig.add_subplot()
    draw(ax)
    ax.set_title(title)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(True, alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)
    return _png(fig)


def work_range_figures(ws: Workspace, mech: Mechanism, side_path, top_path) -> None:
    """Write the side and top views (each atomically): of the wrist centre, or of the flange where
    there is none (below five axes)."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle

    f = mech.length_factor
    unit = mech.length_unit or "m"
    r, bx, by, bz = ws.view_extent
    wrist = ws.reach is not None
    reach_e, low, high = (ws.reach, ws.wrist_low, ws.wrist_high) if wrist else \
        (ws.flange_reach, ws.flange_low, ws.flange_high)
    reach, point = reach_e.value, "wrist centre" if wrist else "flange"

    def measured(v: float) -> str:
        return length_text(v, f, unit)

    def axes(title, xlabel, ylabel):
        fig = Figure(figsize=(6.4, 6.4))
        ax = fig.add_subplot()
        ax.set_title(title)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.set_aspect("equal")
        ax.grid(True, alpha=0.3)
        return fig, ax

    # side view: x (radial in the plane J1 = 0) against z
    fig, ax = axes(f"{mech.name}: work range of the {point}, side view (J1 = 0)", f"x [{unit}]", f"z [{unit}]")
    ax.imshow((ws.side > 0).T, origin="lower", extent=[(bx - r) / f, (bx + r) / f, (bz - r) / f, (bz + r) / f],
              cmap="Blues", vmin=0, vmax=1.6, interpolation="nearest")
    ax.axvline((bx + reach) / f, color="tab:red", ls="--", lw=1)
    ax.annotate(f"reach {measured(reach)}", xy=((bx + reach) / f, (bz + high.value) / 2 / f),
                xytext=(-8, 0), textcoords="offset points", ha="right", color="tab:red")
    for e, label in ((high, "highest"), (low, "lowest")):
        ax.axhline(e.value / f, color="tab:gray", ls=":", lw=1)
        ax.annotate(f"{label} {measured(e.value)}", xy=((bx - r) / f, e.value / f), xytext=(4, 3),
                    textcoords="offset points", fontsize=8, color="tab:gray")
    ax.plot([bx / f], [bz / f], "k+")
    atomic_write(side_path, _png(fig))

    # top view: x against y, the reach as a circle about the J1 axis
    fig, ax = axes(f"{mech.name}: work range of the {point}, top view", f"x [{unit}]", f"y [{unit}]")
    ax.imshow((ws.top > 0).T, origin="lower", extent=[(bx - r) / f, (bx + r) / f, (by - r) / f, (by + r) / f],
              cmap="Blues", vmin=0, vmax=1.6, interpolation="nearest")
    ax.add_patch(Circle((bx / f, by / f), reach / f, fill=False, color="tab:red", ls="--", lw=1))
    ax.annotate(f"reach {measured(reach)}", xy=((bx + reach * np.cos(0.8)) / f, (by + reach * np.sin(0.8)) / f),
                xytext=(6, 6), textcoords="offset points", color="tab:red")
    ax.plot([bx / f], [by / f], "k+")
    atomic_write(top_path, _png(fig))
