"""Workspace sweeps: ABB's published reach figures, reproducibility, voxels and the sweep command."""

import json
import re

import numpy as np
import pytest

import rswarp
from rswarp import examples
from rswarp.cli import main
from rswarp.kinematics.kinematics import Kinematics
from rswarp.sim.workspace import radial_distance, sample_chunks, workspace

from conftest import DATA


@pytest.fixture(scope="module")
def irb1300():
    mech = rswarp.load(examples.IRB1300)
    return mech, Kinematics(mech)


@pytest.mark.parametrize("path, reach_mm", [(examples.IRB1300, 901.9), (examples.IRB2600ID, 1999.9)])
def test_reach_matches_abb_figures(path, reach_mm):
    """ABB's reach: the J1 axis to the wrist centre, at its maximum over the limits (within 0.1%)."""
    ws = workspace(rswarp.load(path), samples=4000, seed=0)
    assert ws.reach.value * 1000 == pytest.approx(reach_mm, rel=1e-3)
    assert ws.reach.value >= ws.reach.sampled  # refined beyond the best sample, never below it


def test_reach_is_the_true_maximum_not_the_best_sample(irb1300):
    """Few samples land far from the stretched arm; refinement still finds the analytic maximum
    50 + 425 + sqrt(425^2 + 40^2) mm of the IRB 1300's geometry."""
    mech, kin = irb1300
    ws = workspace(mech, samples=200, seed=5, kinematics=kin)
    analytic = 0.050 + 0.425 + np.hypot(0.425, 0.040)
    assert ws.reach.sampled < analytic - 1e-3
    assert ws.reach.value == pytest.approx(analytic, abs=1e-6)
    q = np.array(ws.reach.q)
    lo, hi = mech.bounds()
    assert np.all(q >= lo) and np.all(q <= hi)
    wrist, _ = kin.wrist_flange(q[None])
    assert radial_distance(wrist.astype(float), np.zeros(3), np.array([0, 0, 1.0]))[0] == pytest.approx(analytic, abs=1e-5)


def test_heights_and_flange_reach(irb1300):
    mech, kin = irb1300
    ws = workspace(mech, samples=3000, seed=1, kinematics=kin)
    # stretched straight up: J2 axis height + upper arm + forearm to the wrist centre
    assert ws.wrist_high.value == pytest.approx(0.544 + 0.425 + np.hypot(0.425, 0.040), abs=1e-6)
    # J5 can turn the 90 mm wrist-to-flange offset straight outwards
    assert ws.flange_reach.value == pytest.approx(0.050 + 0.425 + np.hypot(0.425, 0.040) + 0.090, abs=1e-6)
    assert ws.wrist_low.value < ws.wrist_high.value and ws.flange_low.value < ws.flange_high.value


def test_seed_reproducible_and_thread_independent(irb1300):
    mech, kin = irb1300
    one = Kinematics(mech, threads=1, chunk=1000)
    a = workspace(mech, samples=5000, seed=7, kinematics=kin)
    b = workspace(mech, samples=5000, seed=7, kinematics=one)
    c = workspace(mech, samples=5000, seed=8, kinematics=kin)
    assert a.report() == b.report()
    assert np.array_equal(a.wrist_voxels, b.wrist_voxels) and np.array_equal(a.side, b.side)
    assert a.reach.sampled != c.reach.sampled


@pytest.mark.parametrize("method", ["random", "sobol", "grid"])
def test_sampling_methods_stay_within_limits(method):
    lo, hi = np.array([-1.0, 0.0, 2.0]), np.array([1.0, 0.5, 3.0])
    chunks = list(sample_chunks(lo, hi, 1000, method, seed=3, chunk=300))
    q = np.concatenate(chunks)
    assert q.shape[1] == 3 and np.all(q >= lo) and np.all(q <= hi)
    assert len(q) == (1000 if method != "grid" else 10 ** 3)
    again = np.concatenate(list(sample_chunks(lo, hi, 1000, method, seed=3, chunk=300)))
    assert np.array_equal(q, again)
    with pytest.raises(ValueError, match="unknown sampling method"):
        next(sample_chunks(lo, hi, 10, "halton"))


def test_voxels_hold_every_sampled_position(irb1300):
    mech, kin = irb1300
    ws = workspace(mech, samples=2000, seed=2, resolution=0.05, kinematics=kin)
    q = next(sample_chunks(*mech.bounds(), 2000, "random", 2))
    wrist, flange = kin.wrist_flange(q)
    for grid, pts in ((ws.wrist_voxels, wrist), (ws.flange_voxels, flange)):
        idx = np.floor((pts - np.array(ws.origin)) / ws.resolution).astype(int)
        assert grid[tuple(idx.T)].all()
    assert ws.flange_voxels.sum() <= 2000


def test_sweep_needs_no_wrist_below_five_axes():
    ws = workspace(rswarp.load(DATA / "units_inch.rsxml"), samples=500)
    assert ws.reach is None and ws.wrist_voxels is None
    assert ws.flange_high.value == pytest.approx(12 * 0.0254, abs=1e-6)


def test_sweep_command(tmp_path, capsys):
    out = tmp_path / "ws"
    assert main(["sweep", str(examples.IRB2600ID), "--samples", "3000", "--out", str(out), "--resolution", "50"]) == 0
    text = capsys.readouterr().out
    assert "reach (J1 axis to wrist centre): 1999.9 mm" in text
    assert sorted(p.name for p in out.iterdir()) == [".rswarp.json", "report.json", "side.png", "top.png", "workspace.npz"]
    assert (out / "side.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    report = json.loads((out / "report.json").read_text())
    assert report["voxel_resolution"] == pytest.approx(0.05) and report["samples"] == 3000
    with np.load(out / "workspace.npz") as z:
        assert z["wrist"].dtype == bool and z["wrist"].sum() == report["wrist_voxels_occupied"]
    assert main(["sweep", str(examples.IRB2600ID), "--samples", "500", "--out", str(out), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["reach"]["value"] == pytest.approx(1.9999, rel=1e-3) and doc["files"]["side_view"].endswith("side.png")


def test_sweep_without_a_flange_is_one_line(tmp_path, capsys):
    assert main(["sweep", str(DATA / "units_default.rsxml"), "--samples", "10", "--out", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert re.fullmatch(r".*units_default.rsxml:\d+: 'Pendulum' has no flange \(.*\)\n", err)
