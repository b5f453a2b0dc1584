"""Plot labels carry the measured figure to 0.1 mm: the work-range figures' reach and heights (the
IRB 2600 in metres: 1.6533 m, never 1.7 m), a cable plot's allowed bend radius, and the one
formatter behind them."""

from __future__ import annotations

import re

import numpy as np
import pytest

import rswarp
from rswarp.examples import IRB1300, IRB2600
from rswarp.rsxml.units import length_text


def test_length_text_keeps_a_tenth_of_a_millimetre_in_any_unit():
    assert length_text(1.65332, 1.0, "m") == "1.6533 m"
    assert length_text(1.65332, 0.001, "mm") == "1653.3 mm"
    assert length_text(1.65332, 0.0254, "in") == "65.091 in"  # 0.0254 mm
    assert length_text(-1e-7, 0.001, "mm") == "0.0 mm"  # never "-0.0"


def _labels(monkeypatch, mech, tmp_path) -> tuple[list[str], object]:
    from matplotlib.axes import Axes

    from rswarp.report.figures import work_range_figures

    texts = []
    annotate = Axes.annotate

    def seen(self, text, *a, **k):
        texts.append(text)
        return annotate(self, text, *a, **k)

    monkeypatch.setattr(Axes, "annotate", seen)
    ws = rswarp.workspace(mech, samples=2000, seed=0)
    work_range_figures(ws, mech, tmp_path / "side.png", tmp_path / "top.png")
    assert (tmp_path / "side.png").read_bytes()[:4] == b"\x89PNG"
    return texts, ws


@pytest.mark.parametrize("path, factor", [(IRB2600, 1.0), (IRB1300, 0.001)])
def test_work_range_labels_carry_the_measured_figure(monkeypatch, tmp_path, path, factor):
    mech = rswarp.load(path)
    texts, ws = _labels(monkeypatch, mech, tmp_path)
    unit = "m" if factor == 1.0 else "mm"
    reach = [t for t in texts if t.startswith("reach ")]
    assert len(reach) == 2 and all(t == f"reach {length_text(ws.reach.value, factor, unit)}" for t in reach)
    for t, value in zip(reach + [t for t in texts if t.startswith(("highest", "lowest"))],
                        [ws.reach.value] * 2 + [ws.wrist_high.value, ws.wrist_low.value]):
        shown = float(re.search(r"(-?[\d.]+) m?m$", t).group(1)) * factor
        assert abs(shown - value) <= 0.5e-4 + 1e-12, t  # to 0.1 mm: within half of it


def test_cable_plot_names_the_allowed_bend_radius(monkeypatch):
    """The bend-radius plot's lines say the radii they stand for, in mm to 0.1: the allowed
    (dynamic) one dashed, the static (kink) one dotted."""
    from types import SimpleNamespace

    from matplotlib.axes import Axes

    from rswarp.report import cable_plots

    labels = []
    axhline = Axes.axhline

    def seen(self, *a, **k):
        labels.append(k.get("label"))
        return axhline(self, *a, **k)

    monkeypatch.setattr(Axes, "axhline", seen)
    series = SimpleNamespace(median=np.ones(3), low=np.ones(3), high=np.ones(3))
    cable = SimpleNamespace(name="hose", bend=series, allowed_bend_radius=0.12345, radius=0.006)
    run = SimpleNamespace(times=np.arange(3.0), cables=[cable], envs=1)
    assert cable_plots._over_time(run, "bend", "Least bend radius", "mm", 1000.0)[:4] == b"\x89PNG"
    assert labels == ["hose allowed (dynamic): 123.5 mm", "hose static (kink): 60.0 mm"]  # five diameters
