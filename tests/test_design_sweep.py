"""The design sweep (``rswarp dresspack``): designs run at once as environments, each exactly as it
runs alone; the ranking; the chosen design written so that ``rswarp cable`` gives its verdict
again; designs that cannot be built refused before any work."""

import csv
import shlex
from pathlib import Path

import numpy as np
import pytest

from rswarp.cli import main
from rswarp.kinematics.trajectory import read_trajectory
from rswarp.report.cables import run_cables
from rswarp.report.dresspack import run_dresspack
from rswarp.rsxml.documents import load_mechanism
from rswarp.sim.cable_solver import CableOptions
from rswarp.sim.cables import design_runs, simulate_cables
from rswarp.sim.designs import DesignSet, parse_vary, sample

RIGS = Path(__file__).parent / "data" / "verdicts"
ROBOT = Path(__file__).parents[1] / "examples" / "irb2600_12_165" / "IRB2600_12_165_DressPack_01.rsxml"


def test_designs_run_at_once_are_each_bit_for_bit_the_design_run_alone():
    """Three lengths and clamp heights of the taut rig, one environment each: every figure of each
    equals that design's own one-environment run (their segment counts differ)."""
    mech, _ = load_mechanism(RIGS / "taut.rsxml")
    variables = parse_vary(["length=1.0:1.3", "Slide.z=-0.05:0.05"], mech.cables[0])
    designs = DesignSet(0, variables, sample(variables, 3, seed=1))
    traj = [read_trajectory(RIGS / "gentle.csv", mech)]
    options = CableOptions(frame_rate=30.0)
    together = design_runs(simulate_cables(mech, traj, 3, 1.0, options, designs=designs))
    segments = set()
    for m, run in zip(designs.mechanisms(mech), together):
        alone = simulate_cables(m, traj, 1, 1.0, options).cables[0]
        mine = run.cables[0]
        segments.add(len(mine.segments))
        assert mine.length == pytest.approx(alone.length, abs=0.0)
        for name in ("min_bend_radius", "peak_tension", "wear", "fatigue_sum", "clamp_force", "final_points"):
            assert np.array_equal(getattr(mine, name), getattr(alone, name), equal_nan=True), name
    assert len(segments) > 1  # the designs really had layouts of their own


def test_the_sweep_writes_the_shortest_passing_design_and_cable_gives_its_verdict_again(tmp_path):
    """Over pull_hold.mod the short hoses are pulled taut; the chosen one is the shortest row that
    passes, and run alone from best.rsxml it passes with the same least bend radius."""
    out = tmp_path / "sweep"
    doc = run_dresspack(str(RIGS / "taut.rsxml"), [str(RIGS / "pull_hold.mod")], str(out), ["length=1.0:1.25"],
                        designs=8, min_bend_radius=150.0).doc
    rows = list(csv.DictReader((out / "designs.csv").open()))
    assert len(rows) == 8
    passing = [r for r in rows if r["verdict"] == "PASS"]
    failing = [r for r in rows if r["verdict"] == "FAIL"]
    assert passing and failing and all("taut" in r["fails"] for r in failing)
    shortest = min(passing, key=lambda r: float(r["hose_m"]))
    assert doc["best"]["design"] == int(shortest["design"])
    assert max(float(r["hose_m"]) for r in failing) < float(shortest["hose_m"])
    assert {"designs.csv", "pareto.png", "best.rsxml", "report.json"} <= {p.name for p in out.iterdir()}
    again = run_cables(str(out / "best.rsxml"), str(tmp_path / "again"), program=[str(RIGS / "pull_hold.mod")],
                       min_bend_radius=150.0).doc
    assert again["verdicts"] == {"Hose": "PASS"}
    assert again["cables"][0]["summary"]["least_bend_radius_m"] == pytest.approx(float(shortest["bend_radius_m"]),
                                                                              abs=1e-4)


@pytest.mark.parametrize("vary, says", [
    ("Nowhere.x=-0.01:0.01", "holds no control point"),
    ("length=1.3:1.2", "an empty range"),
    ("Link3.z=-0.08:-0.06", "inside its link"),
])
def test_designs_that_cannot_be_built_are_one_line_and_exit_1_before_any_work(tmp_path, capsys, vary, says):
    code = main(["dresspack", str(ROBOT), "--program", str(ROBOT.parent / "pick_place.mod"), "--vary", vary,
                 "--designs", "4", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 1 and len(err) == 1 and says in err[0], err
    assert not (tmp_path / "o").exists()


def test_the_sweep_gives_each_columns_unit_and_keeps_the_margin_asked_for(tmp_path):
    """designs.csv holds tilts in degrees, as --vary takes them, each column's unit in its name; a
    --min-margin no design keeps is said, and the design with the most margin is written; the
    command that repeats it names an output folder (rswarp cable needs one)."""
    out = tmp_path / "sweep"
    result = run_dresspack(str(RIGS / "taut.rsxml"), [str(RIGS / "pull_hold.mod")], str(out),
                           ["length=1.15:1.25", "Slide.pitch=-10:10"], designs=4, min_bend_radius=150.0,
                           min_margin=99.0)
    rows = list(csv.DictReader((out / "designs.csv").open()))
    assert {"length_m", "Slide.pitch_deg", "stopped"} <= set(rows[0])
    tilts = [float(r["Slide.pitch_deg"]) for r in rows]
    assert all(-10 <= t <= 10 for t in tilts) and max(abs(t) for t in tilts) > 1  # degrees, not radians
    assert "no design passes with 99 % to every rating" in result.text
    best = max((r for r in rows if r["verdict"] == "PASS"), key=lambda r: float(r["least_margin"]))
    assert result.doc["best"]["design"] == int(best["design"])
    words = shlex.split(result.doc["check"])
    assert words[:3] == ["rswarp", "cable", str(out / "best.rsxml")] and words[words.index("--out") + 1] == \
        f"{out}-best"
