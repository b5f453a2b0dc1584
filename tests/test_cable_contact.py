"""A cable's contact in three figures (issue "small truths" part 3): the peak contact force, the
worst rub and the worst wear, each with its environment and time, the same in the text, the
verdict, ``report.json`` and the wear plot; a run without a floor names no floor; progress in the
unit the bar shows (simulated seconds), and no bar but one closing line where stderr is a log."""

from __future__ import annotations

import dataclasses
import io
import re

import numpy as np
import pytest

import rswarp
from rswarp.kinematics.trajectory import Trajectory
from rswarp.report import cable_plots
from rswarp.report.cable_lines import cable_lines
from rswarp.report.cables import cable_report
from rswarp.report.verdicts import cable_findings, verdict_lines
from rswarp.sim.cables import CableOptions, simulate_cables

from conftest import DATA

pytestmark = pytest.mark.filterwarnings("ignore:.*no desiredLength")


@pytest.fixture(scope="module")
def still():
    """The catenary rig's wire held still 0.2 s (and the second after) in two environments, with
    the progress it reported."""
    mech = rswarp.load(DATA / "cables" / "catenary.rsxml")
    seen = []
    still = Trajectory("still", np.array([0.0, 0.2]), np.zeros((2, mech.dof)))
    run = simulate_cables(mech, [still], envs=2, progress=lambda done, total: seen.append((done, total)))
    return mech, run, seen


def _rubbed(run):
    """The run's first cable with contact written in: in environment 0 two segments slide on the
    arm (the harder pressed 50 N, the other wearing most, 3 J), in environment 1 one on the floor at
    80 N; the peak contact forces 50 N and 80 N."""
    c = run.cables[0]
    arm, floor = c.links.index("Arm"), c.links.index("floor")
    wear, peak = np.zeros_like(c.wear), np.zeros_like(c.wear_peak_normal)
    wear[0, 5, arm], peak[0, 5] = 1.0, 50.0
    wear[0, 20, arm], peak[0, 20] = 3.0, 20.0
    wear[1, 10, floor], peak[1, 10] = 0.5, 80.0
    first = np.full_like(c.contact_time, np.nan)
    first[0, arm], first[1, floor] = 0.1, 0.2
    c = dataclasses.replace(c, wear=wear, wear_peak_normal=peak, wear_contact_time=(peak > 0) * 0.25,
                            contact_time=first, contact_at=np.where(np.isfinite(first), 0.5, np.nan),
                            peak_normal=np.array([50.0, 80.0]), peak_normal_time=np.array([0.3, 0.4]),
                            peak_normal_at=np.array([c.segments[5], c.segments[10]]))
    return dataclasses.replace(run, cables=(c,))


def test_the_three_contact_figures_agree_in_the_text_the_verdict_the_report_and_the_plot(still, monkeypatch):
    mech, run, _ = still
    run = _rubbed(run)
    c = run.cables[0]
    text = "\n".join(cable_lines(c, run.weights[0], run.joints, verdict_lines(c, cable_findings(c, run.weights[0]))))
    assert "peak contact force: 80 N, the run's worst (environment 1, t = 0.40 s" in text
    assert f"worst rub: 80 N on floor, the run's worst (environment 1, first touch t = 0.20 s, {c.segments[10]:.3f}" in text
    assert "worst wear: 3 J (normal force x sliding) at one place" in text and "mostly on Arm, the run's worst " \
        "(environment 0" in text
    assert "warn rub: rubs on floor: 80 N" in text  # the verdict's worst rub is the text's
    assert len(re.findall(r"the run's worst", text)) == 3
    summary = cable_report(run)["cables"][0]["summary"]["contact"]
    assert (summary["peak_force"]["environment"], summary["peak_force"]["force_N"]) == (1, 80.0)
    assert (summary["worst_rub"]["environment"], summary["worst_rub"]["on"], summary["worst_rub"]["force_N"]) == \
        (1, "floor", 80.0)
    assert (summary["worst_wear"]["environment"], summary["worst_wear"]["on"], summary["worst_wear"]["wear_J"]) == \
        (0, "Arm", 3.0)
    env0 = cable_report(run)["cables"][0]["environments"][0]["contact"]
    assert env0["worst_rub"]["force_N"] == 50.0 and env0["worst_rub"]["wear_J"] == 4.0  # its harder segment; all wear
    assert env0["worst_wear"]["at_m"] == pytest.approx(c.segments[20])
    labels = _legend(monkeypatch, lambda: cable_plots._wear_map(run))
    assert f"{c.name}: worst wear 3 J on Arm (environment 0, " in " ".join(labels)
    assert f"{c.name}: worst rub 80 N on floor (environment 1, " in " ".join(labels)
    assert f"{c.name}: time in contact, greatest (right axis)" in labels  # the dotted line, in the legend


def _legend(monkeypatch, draw_plot) -> list[str]:
    """The legend labels of the plot ``draw_plot`` draws."""
    from matplotlib.figure import Figure

    labels = []

    def figure(draw, *a):
        ax = Figure().add_subplot()
        draw(ax)
        labels.extend(ax.get_legend_handles_labels()[1])
        return b""

    monkeypatch.setattr(cable_plots, "figure_png", figure)
    draw_plot()
    return labels


def test_the_bend_plot_ticks_plain_millimetres_and_names_both_radii(still, monkeypatch):
    """Ticks read 200, 300 (never 3x10^2); the allowed (dynamic) and static (kink) radii are both
    drawn and both in the legend; the clearance plot's zero line is named too."""
    from matplotlib.figure import Figure

    mech, run, _ = still
    axes = []

    def figure(draw, *a):
        ax = Figure().add_subplot()
        draw(ax)
        axes.append(ax)
        return b""

    monkeypatch.setattr(cable_plots, "figure_png", figure)
    c = run.cables[0]
    cable_plots._over_time(run, "bend", "Least bend radius", "mm", 1000.0)
    ax = axes[-1]
    ax.figure.canvas.draw()
    ticks = [t.get_text() for t in ax.get_yticklabels() if t.get_text()]
    assert ticks and all(re.fullmatch(r"[\d.]+", t) for t in ticks), ticks
    labels = ax.get_legend_handles_labels()[1]
    assert any("allowed (dynamic)" in s for s in labels) and \
        any(f"static (kink): {c.radius * 10 * 1000:.1f} mm" in s for s in labels), labels
    cable_plots._over_time(run, "gap", "Least clearance", "mm", 1000.0)
    assert "touching (0 mm)" in axes[-1].get_legend_handles_labels()[1]


def test_a_run_without_a_floor_reports_no_floor(still):
    mech, _, _ = still
    held = Trajectory("still", np.array([0.0, 0.1]), np.zeros((2, mech.dof)))
    run = simulate_cables(mech, [held], envs=1, seconds=0.1, options=CableOptions(floor=None))
    doc = cable_report(run)["cables"][0]
    assert "floor" not in doc["slots"] and "floor" not in doc["environments"][0]["clearance"]
    assert "floor" not in "\n".join(cable_lines(run.cables[0], run.weights[0]))


def test_a_cable_run_counts_its_progress_in_simulated_seconds(still):
    """One count, in the bar's unit: the run's seconds (0.2 s and the second after), never past."""
    _, run, seen = still
    done = [d for d, _ in seen]
    assert all(t == pytest.approx(float(run.times[-1])) for _, t in seen)
    assert done == sorted(done) and done[0] == 0.0 and done[-1] == pytest.approx(float(run.times[-1]))


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_a_bar_s_percentage_is_its_count_and_a_log_gets_one_line(monkeypatch, capsys):
    """On a terminal each drawn state's percentage is its count over its total; where stderr is
    not a terminal there is no bar, only the closing line."""
    import sys

    from rswarp.cli import SIMULATED, _Progress

    term = _Terminal()
    monkeypatch.setattr(sys, "stderr", term)
    bar = _Progress("cable", SIMULATED, "2 environments")
    for k in range(61):
        bar(k / 60 * 1.2, 1.2)
    states = re.findall(r"(\d+)%\|[^|]*\| ([\d.]+)/([\d.]+) s simulated", term.getvalue())
    assert states and states[-1] == ("100", "1.2", "1.2") and "simulated in" not in term.getvalue()
    for pct, n, total in states:
        assert abs(int(pct) - 100 * float(n) / float(total)) <= 5  # the count is shown to 0.1 s
    monkeypatch.undo()
    capsys.readouterr()
    log = _Progress("cable video", "frame")
    for k in range(265):
        log(k, 264)
    err = capsys.readouterr().err
    assert re.fullmatch(r"cable video: 264 frames in \d+\.\d s\n", err), err
