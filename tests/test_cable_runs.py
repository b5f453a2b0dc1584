"""Cable runs (issues "Cable dynamics in parallel environments", "Cables as Cosserat rods"): contact
with link meshes and the floor, the IRB 2600ID's hose over wrist sweeps, blow-ups that stop
one environment only, results identical on one core or many, and the ``rswarp cable`` command."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

import rswarp
from rswarp.cli import main
from rswarp.errors import RsxmlError
from rswarp.kinematics.trajectory import Trajectory
from rswarp.sim.cables import CableOptions, simulate_cables

from conftest import DATA

ID = DATA.parent.parent / "examples" / "irb2600id" / "IRB2600ID_8_200__03.rsxml"


def held(q, seconds: float, name: str = "held") -> Trajectory:
    return Trajectory(name, np.array([0.0, seconds]), np.array([q, q], float))


def test_hose_rests_on_a_moving_link_mesh():
    """A lift raises a block under the hanging wire: the wire's middle ends on the block's top
    (z = 0.9 m plus the 2 mm radius, within 0.5 mm; near the edges its stiffness lifts it a few
    millimetres), the contact is reported on the lift's link at the time and place it happened,
    and the wire beside it, unraised, hangs free."""
    mech = rswarp.load(DATA / "cables" / "draped.rsxml")
    lift = Trajectory("lift", np.array([0.0, 2.0, 6.0]), np.array([[0.0], [0.4], [0.4]]))
    run = simulate_cables(mech, [lift, held([0.0], 6.0)], envs=2, options=CableOptions(damping=3.0))
    c = run.cables[0]
    assert list(c.status) == ["ok", "ok"]
    lifted, still = c.final_points
    middle, over = np.abs(lifted[:, 0] - 0.5) < 0.05, np.abs(lifted[:, 0] - 0.5) < 0.1
    assert middle.sum() >= 3 and np.abs(lifted[middle, 2] - 0.902).max() < 5e-4
    assert lifted[over, 2].min() > 0.9015 and lifted[over, 2].max() < 0.91
    j = c.links.index("Lift")
    assert abs(c.clearance[0, j]) < 1e-3 and 0.5 < c.contact_time[0, j] < 2.0
    assert abs(c.contact_at[0, j] - 0.6) < 0.1  # the middle of the 1.2 m wire touches first
    assert c.peak_normal[0] > 0 and c.peak_normal_at[0] == pytest.approx(0.6, abs=0.15)
    assert np.isnan(c.contact_time[1]).all() and c.clearance[1, j] > 0.15 and still[:, 2].min() < 0.75


def test_floor_holds_the_hose_up(tmp_path):
    """Lowered so that the catenary would pass 94 mm below the floor, the wire lies on it: no point
    below its radius, contact with the floor reported. A cable routed through the floor from the
    start is an error at its line."""
    mech = rswarp.load(DATA / "cables" / "floor.rsxml")
    down = Trajectory("down", np.array([0.0, 2.0, 5.0]), np.array([[0.0], [0.3], [0.3]]))
    hang = simulate_cables(mech, [down], envs=1, options=CableOptions(damping=3.0)).cables[0]
    assert hang.final_points[0][:, 2].min() == pytest.approx(0.002, abs=5e-4)
    assert hang.clearance[0, -2] == pytest.approx(0.0, abs=5e-4) and np.isfinite(hang.contact_time[0, -2])
    assert hang.links[-2] == "floor" and list(hang.status) == ["ok"]
    with pytest.raises(RsxmlError, match=r"floor.rsxml:11: cable 'Hang' starts 0.107 m into the floor"):
        simulate_cables(mech, [down], envs=1, options=CableOptions(floor=0.3))


def wrist_sweeps(seconds: float = 3.0) -> list[Trajectory]:
    """J4, J5 and J6 each swept from 0 to +90 degrees and back, the others at zero."""
    t = np.linspace(0.0, seconds, 61)
    swing = np.radians(90.0) * np.sin(np.pi * t / seconds) ** 2
    out = []
    for j in (3, 4, 5):
        q = np.zeros((len(t), 6))
        q[:, j] = swing
        out.append(Trajectory(f"J{j + 1}", t, q))
    return out


def test_irb2600id_hose_over_wrist_sweeps():
    """The spec's hose, clamped on Link4 and Link5 (666.5 mm, straight at zero). J4 turns both
    clamps together and J6 neither: the hose stays straight (a bend radius of metres). J5 at 90
    degrees turns the clamps a right angle apart, so the hose bends at least as tight as its
    length over pi / 2 somewhere: too tight for ten diameters (0.5 m). No contact (no meshes ship;
    the wrist is far above the floor), no environment stops. The spec's file gives no desiredLength
    (the example's is 700 mm): without it the hose is the path through its clamps."""
    mech = rswarp.load(ID)
    mech = dataclasses.replace(mech, cables=(dataclasses.replace(mech.cables[0], desired_length=None),))
    run = simulate_cables(mech, wrist_sweeps(), envs=3)
    hose = run.cables[0]
    assert list(hose.status) == ["ok"] * 3 and hose.length == pytest.approx(0.6665, abs=1e-6)
    assert hose.min_bend_radius[0] > 5.0 and hose.min_bend_radius[2] > 5.0
    assert 0.02 < hose.min_bend_radius[1] < 0.6665 / (np.pi / 2)
    assert list(hose.too_tight) == [False, True, False]
    assert not hose.touching.any() and hose.clearance[:, hose.links.index("floor")].min() > 1.0
    assert hose.max_twist[0] < 0.01 and hose.max_twist[2] < 0.01
    assert any("no mesh" in w for w in run.warnings)


def test_identical_on_one_core_or_many():
    """Environments are independent threads: one core or two give the same bits."""
    mech = rswarp.load(ID)
    runs = [simulate_cables(mech, wrist_sweeps(1.0), envs=6, options=CableOptions(threads=n)) for n in (1, 2)]
    a, b = (r.cables[0] for r in runs)
    assert np.array_equal(a.final_points, b.final_points)
    assert np.array_equal(a.min_bend_radius, b.min_bend_radius) and np.array_equal(a.peak_tension, b.peak_tension)


def test_a_blow_up_stops_that_environment_only():
    """J1 jumping half a turn in a millisecond flings the arm's hose (past 100 m/s, or through
    itself): that environment stops with a message naming the time and the cause; the other runs
    on."""
    mech = rswarp.load(DATA / "cables" / "catenary.rsxml")
    jump = Trajectory("jump", np.array([0.0, 0.5, 0.501, 2.0]), np.array([[0.0], [0.0], [np.pi], [np.pi]]))
    c = simulate_cables(mech, [jump, held([0.0], 2.0)], envs=2).cables[1]
    assert c.status[0].startswith("stopped at t = 0.5")
    assert "100 m/s" in c.status[0] or "the trajectory drives it through" in c.status[0]
    assert c.status[1] == "ok" and np.isfinite(c.final_points[1]).all()


def test_cable_command_writes_its_report(tmp_path, capsys):
    """``rswarp cable --json``: per environment and cable, the answers and final_points (N x 3,
    metres) in report.json and on stdout; the plots are PNGs; --usd writes a time-sampled stage."""
    csv = tmp_path / "j5.csv"
    csv.write_text("time,J1,J2,J3,J4,J5,J6\n0,0,0,0,0,0,0\n1,0,0,0,0,60,0\n")
    out = tmp_path / "run"
    code = main(["cable", str(ID), "--envs", "2", "--trajectory", str(csv), "--out", str(out), "--usd", "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 0 and doc == json.loads((out / "report.json").read_text())
    env = doc["cables"][0]["environments"][1]
    points = np.array(env["final_points"])
    assert points.shape == (15, 3) and env["status"] == "ok" and env["trajectory"] == str(csv)
    assert points[0] == pytest.approx([0.5385, 0.0, 1.495], abs=5e-4)  # the clamp, as stiff as the hose
    for name in ("tension.png", "bend_radius.png", "clearance.png"):
        assert (out / name).read_bytes()[:4] == b"\x89PNG"
    from pxr import Usd, UsdGeom

    stage = Usd.Stage.Open(str(out / "playback.usdc"))
    curve = UsdGeom.BasisCurves(stage.GetPrimAtPath("/IRB2600ID_8_200__03/cable_Hose"))
    # the 1 s trajectory and the second a run goes on with the robot still (the hose swings on)
    assert stage.GetTimeCodesPerSecond() == 60 and len(curve.GetPointsAttr().GetTimeSamples()) == 120


def test_cable_command_refuses_bad_input(tmp_path, capsys):
    """A trajectory beyond a limit: its file:line, exit 1, nothing written; a file without cables:
    one line saying so."""
    csv = tmp_path / "far.csv"
    csv.write_text("time,J1,J2,J3,J4,J5,J6\n0,0,0,0,0,0,0\n1,0,0,0,0,130,0\n")
    out = tmp_path / "run"
    assert main(["cable", str(ID), "--trajectory", str(csv), "--out", str(out)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"{csv}:3:") and not out.exists()
    assert main(["cable", str(DATA / "cables" / "../transforms.rsxml"), "--random", "--out", str(out)]) == 1
    assert "no Cable" in capsys.readouterr().err and not out.exists()
    assert main(["cable", str(ID), "--random", "--floor", "nan", "--out", str(out)]) == 1
    assert "--floor: must be a finite number" in capsys.readouterr().err and not out.exists()


def test_a_playback_stage_first_leaves_exports_whole(tmp_path):
    """Writing a playback stage before any export (a fresh process) still registers Newton's
    schemas with USD first: the export that follows authors its Newton joint attributes."""
    import subprocess
    import sys

    script = (f"import rswarp, numpy as np\n"
              f"from rswarp.export.playback import PlaybackCable, write_playback\n"
              f"write_playback({str(tmp_path / 'p.usdc')!r}, 'p', [], [PlaybackCable('c', np.zeros((2, 3, 3)), 0.01, "
              f"(0, 0, 0))], 60.0)\n"
              f"rswarp.export.export(rswarp.load({str(ID)!r}), {str(tmp_path / 'r.usda')!r})\n")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "NewtonJointAPI" in (tmp_path / "r.usda").read_text()


@pytest.mark.parametrize("args, says", [
    (["--poisson", "0.7"], "argument --poisson: must be at most 0.5"),
    (["--poisson", "-0.1"], "argument --poisson: must be a finite number >= 0"),
    (["--friction", "-1"], "argument --friction: must be a finite number >= 0"),
    (["--density", "0"], "argument --density: must be a finite number > 0"),
])
def test_bad_rod_parameters_are_one_line(tmp_path, capsys, args, says):
    """A Poisson ratio outside [0, 0.5], negative friction, a density not above zero: one line,
    exit 1, nothing written. (E and radius are the file's: ``tests/test_bad.py``.)"""
    out = tmp_path / "run"
    assert main(["cable", str(DATA / "cables" / "catenary.rsxml"), "--random", "--out", str(out), *args]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and says in err[0] and not out.exists()
