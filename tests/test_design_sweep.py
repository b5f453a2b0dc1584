"""The design sweep (``rswarp dresspack``): designs run at once as environments, each exactly as it
runs alone; the ranking; the chosen design written so that ``rswarp cable`` gives its verdict
again; designs that cannot be built refused before any work."""

import csv
import shlex
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from rswarp.cli import main
from rswarp.kinematics.trajectory import read_trajectory
from rswarp.report.cables import run_cables
from rswarp.report.dresspack import run_dresspack
from rswarp.rsxml.documents import load_mechanism
from rswarp.sim.cable.solver import CableOptions
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
    doc = run_dresspack(str(RIGS / "taut.rsxml"), [str(RIGS / "pull_hold.mod")], str(out), vary=["length=1.0:1.25"],
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


def _sweep(tmp_path, *options, designs: int = 4) -> list[str]:
    return ["dresspack", str(ROBOT), "--program", str(ROBOT.parent / "pick_place.mod"), "--designs", str(designs),
            "--out", str(tmp_path / "o"), *options]


@pytest.mark.parametrize("toml, says", [
    ('vary = "length=1:2"\n', "'vary' must be a table of NAME = \"MIN:MAX\""),
    ('vary = ["length=1:2"]\n', "not an array"),
    ("[vary]\nlength = [1.0, [2.0]]\n", "'length' must be \"MIN:MAX\" or [MIN, MAX], not an array"),
    ("[vary]\n", "no variables"),
    ("vary = [\n", "not a TOML file of variables"),
    (None, "cannot read the TOML file of variables: No such file or directory"),
    ("folder", "cannot read the TOML file of variables: a folder"),
])
def test_a_toml_file_of_variables_given_wrong_is_one_line_and_exit_1(tmp_path, capsys, toml, says):
    path = tmp_path / "d.toml"
    if toml == "folder":
        path.mkdir()
    elif toml is not None:
        path.write_text(toml)
    code = main(_sweep(tmp_path, "--vary", str(path)))
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 1 and len(err) == 1 and f"{path}: " in err[0] and says in err[0], err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("options, says", [
    (["--vary", "length=1:2000"], "a hose of at most 1000 m, please (1 km"),  # not "into the floor"
    (["--vary", "length=1e9:2e9"], "a hose of at most 1000 m"),  # not "shorter than the path"
    (["--vary", "length=170:200"], "segments of at most 0.04 (maxSegmentLength), and a cable takes at most 4000: "
                                   "keep the length range under about 159.9 m"),
    (["--vary", "length=0.5:0.6"], "every design's hose is shorter than the path through its control points"),
    (["--vary", "Link6.z=0:0.01", "--vary", "3.z=0:0.02"], "already varies control point 3's z"),
    (["--vary", "length=1:1.2", "--rated-cycles", "1e6@nan"], "--rated-cycles '1e6@nan': give N@R"),
    (["--vary", "length=1:1.2", "--tool", f"{ROBOT.parent / 'gripper'}@0,0,0,1e7,0,0"], "angles within"),
])
def test_lengths_and_options_past_their_bounds_name_the_real_cause(tmp_path, capsys, options, says):
    code = main(_sweep(tmp_path, *options))
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 1 and len(err) == 1 and says in err[0], err
    assert not (tmp_path / "o").exists()


def test_an_unknown_option_points_at_the_commands_own_help(tmp_path, capsys):
    assert main(_sweep(tmp_path, "--vary", "length=1:1.2", "--bogus", "3")) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["rswarp dresspack: unrecognized arguments: --bogus 3 (see rswarp dresspack --help)"]


@pytest.mark.parametrize("delay", [0.2, 0.8, 1.5])
def test_ctrl_c_while_the_sweep_starts_is_130_with_no_output(tmp_path, delay):
    """The first seconds load Python's native libraries (Warp, scipy, trimesh's optional ones): a
    KeyboardInterrupt raised inside one aborted the process (exit 134) or printed a traceback."""
    script = Path(sys.executable).parent / "rswarp"  # the command as installed; else the module
    command = [sys.executable, str(script)] if script.is_file() else [sys.executable, "-m", "rswarp.cli"]
    p = subprocess.Popen([*command, *_sweep(tmp_path, "--vary", "length=1:1.2", designs=16)],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    time.sleep(delay)
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=120)
    assert p.returncode == 130, err.decode()[-800:]
    for word in (b"Traceback", b"terminate", b"Exception ignored", b"internal error", b"Segmentation"):
        assert word not in err, err.decode()[-800:]
    assert list(tmp_path.iterdir()) == []


def test_the_sweep_gives_each_columns_unit_and_keeps_the_margin_asked_for(tmp_path):
    """designs.csv holds tilts in degrees, as --vary takes them, each column's unit in its name; a
    --min-margin no design keeps is said, and the design with the most margin is written; the
    command that repeats it names an output folder (rswarp cable needs one)."""
    out = tmp_path / "sweep"
    result = run_dresspack(str(RIGS / "taut.rsxml"), [str(RIGS / "pull_hold.mod")], str(out),
                           vary=["length=1.15:1.25", "Slide.pitch=-10:10"], designs=4, min_bend_radius=150.0,
                           min_margin=99.0, rated_cycles="1e7@300")
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
    assert words[words.index("--rated-cycles") + 1] == "1e7@300" and "passes at" in result.text  # its life, said
