"""Dress-pack verdicts (issue "Dress-pack verdicts an engineer signs", item 1): each breach of the
hose's ratings a finding record, PASS where none fails. Held against geometry rswarp does not
simulate: clamps pulled farther apart than the hose is long must leave it taut, and needing at
least that shortfall; a hose that must turn back between clamps side by side, D apart, turning one
way only, bends to D/2 or tighter somewhere; a generous hose over a gentle move passes."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from rswarp.examples import IRB2600_DRESSPACK, IRB2600_PROGRAM
from rswarp.findings import Finding
from rswarp.report.cables import run_cables
from rswarp.report.verdicts import Ratings, verdict

from conftest import DATA

RIGS = DATA / "verdicts"


def _run(tmp_path, rig: str, trajectory: str, **options):
    out = run_cables(str(RIGS / rig), str(tmp_path / "run"), envs=1, trajectory=[str(RIGS / trajectory)], **options)
    report = json.loads((tmp_path / "run" / "report.json").read_text())
    return out, report


def test_clamps_pulled_farther_apart_than_the_hose_is_long_leave_it_taut(tmp_path):
    """The slide ends 1100 mm from the base clamp; the hose is 1000 mm: 100 mm short."""
    out, report = _run(tmp_path, "taut.rsxml", "pull.csv")
    taut = [f for f in report["findings"] if f["kind"] == "taut"]
    assert report["verdicts"] == {"Hose": "FAIL"} and len(taut) == 1
    f = taut[0]
    assert f["severity"] == "fail" and f["value"] > f["limit"] == 0.005 and f["unit"] == "1"
    assert f["cable"] == "Hose" and f["env"] == 0 and 0.0 <= f["at_m"] <= 1.0 and f["t_s"] >= 0.5
    assert len(f["joints"]) == 1 and f["joints"][0] > 0.1  # the slide well out when it is taut
    assert int(re.search(r"at least (\d+) mm", f["advice"]).group(1)) >= 100
    assert "verdict: FAIL" in out.text and "fail taut" in out.text


def test_a_generous_hose_over_a_gentle_move_passes(tmp_path):
    out, report = _run(tmp_path, "taut.rsxml", "gentle.csv")
    assert report["verdicts"] == {"Hose": "PASS"}
    assert not [f for f in report["findings"] if f["kind"] in ("taut", "bend", "kink")]
    assert "verdict: PASS" in out.text


def test_a_hose_turning_back_between_clamps_bends_to_half_their_gap(tmp_path):
    _, report = _run(tmp_path, "uturn.rsxml", "gentle.csv")
    bent = [f for f in report["findings"] if f["kind"] in ("bend", "kink")]
    assert bent and min(f["value"] for f in bent) <= 0.060  # the gap is 120 mm
    kink = next(f for f in bent if f["kind"] == "kink")
    assert kink["limit"] == pytest.approx(0.1) and kink["unit"] == "m"  # 5 diameters of a 20 mm hose


def test_the_ratings_are_the_users(tmp_path):
    """A looser strain passes the same pull's stretch as less than it; a static radius set below
    the bend makes the kink a bend (the robot moves then: a failure)."""
    _, report = _run(tmp_path, "taut.rsxml", "pull.csv", max_strain=0.5)
    assert not [f for f in report["findings"] if f["kind"] == "taut"]
    _, report = _run(tmp_path, "uturn.rsxml", "gentle.csv", static_bend_radius=10.0)  # mm, the file's unit
    kinds = {f["kind"] for f in report["findings"]}
    assert "kink" not in kinds and "bend" in kinds


def test_a_program_run_names_the_line_and_the_joints_of_each_finding(tmp_path):
    out = run_cables(str(IRB2600_DRESSPACK), str(tmp_path / "run"), program=[str(IRB2600_PROGRAM)])
    found = out.doc["findings"]
    assert found and all(f["file"] == str(IRB2600_PROGRAM) and f["line"] and len(f["joints"]) == 6 for f in found
                         if f["t_s"] is not None)
    assert {f["routine"] for f in found if f["t_s"] is not None} <= {"main", "Pick", "Place"}


def test_the_verdict_is_fail_only_with_a_failing_finding():
    warn = Finding("rub", "rubs on Link4", "warn", cable="Hose", env=0)
    fail = Finding("taut", "pulled taut", "fail", cable="Hose", env=0)
    assert verdict([]) == "PASS" and verdict([warn]) == "PASS" and verdict([warn, fail]) == "FAIL"
    assert Ratings().max_torsion == pytest.approx(np.pi)


def test_a_hose_is_clear_of_itself_only_beyond_pi_bend_radii_along_it(tmp_path):
    """The U-turn's legs are 100 mm apart but within pi x 200 mm along it: no clearance to itself.
    A 1.5 m hose hung in a long U from clamps 120 mm apart: its legs, over a metre apart along it,
    are 100 mm apart (120 mm less a diameter)."""
    _, report = _run(tmp_path, "uturn.rsxml", "gentle.csv")
    assert "cables" not in report["cables"][0]["environments"][0]["clearance"]
    _, report = _run(tmp_path, "loop.rsxml", "gentle.csv")
    itself = report["cables"][0]["environments"][0]["clearance"]["cables"]["min_clearance_m"]
    assert itself == pytest.approx(0.100, abs=0.005)


def test_a_hose_above_an_open_mesh_is_outside_it(tmp_path):
    """A box without its top (a CAD part that is not closed), its rim 300 mm under the hose's
    clamps: past the rim's edge the nearest face's side says "inside"; the winding number says
    outside. The clearance is the hose's distance to the box (trimesh's, from its final shape)
    less its radius, and nothing pushes it."""
    import trimesh

    box = RIGS / "open_box.stl"  # 400 x 400 x 200 mm, its rim at z = 0
    out = run_cables(str(RIGS / "taut.rsxml"), str(tmp_path / "run"), envs=1, trajectory=[str(RIGS / "still.csv")],
                     environment=[f"{box}@450,0,700"])
    cable = json.loads((tmp_path / "run" / "report.json").read_text())["cables"][0]
    env = cable["environments"][0]
    mesh = trimesh.load(box)
    mesh.apply_translation([450, 0, 700])
    points = np.array(env["final_points"]) * 1000.0  # mm, as the box
    _, distance, _ = trimesh.proximity.closest_point(mesh, points)
    clear = env["clearance"]["open_box"]["min_clearance_m"] * 1000.0
    assert clear > 0 and clear == pytest.approx(distance.min() - 10.0, abs=3.0)
    assert not [f for f in out.doc["findings"] if f["kind"] == "rub"]


def test_a_program_that_pulls_the_hose_taut_is_caught_in_the_move_that_pulls(tmp_path):
    """pull_hold.mod runs the slide out 200 mm by its second MoveAbsJ (line 10, 0.5 s to 2.55 s),
    holds, and comes back: the hose is taut from within that move, and needs 100 mm or more."""
    out = run_cables(str(RIGS / "taut.rsxml"), str(tmp_path / "run"), program=[str(RIGS / "pull_hold.mod")])
    taut = [f for f in out.doc["findings"] if f["kind"] == "taut"]
    assert len(taut) == 1 and taut[0]["line"] == 10 and taut[0]["routine"] == "main"
    assert 0.5 < taut[0]["t_s"] < 2.55
    assert int(re.search(r"at least (\d+) mm", taut[0]["advice"]).group(1)) >= 100


def test_a_clamp_load_past_its_rating_fails(tmp_path):
    """The pull's clamps hold the hose's whole stretch (E A x strain, kilonewtons): rated for
    100 N, both fail; rated for 1 MN, neither."""
    _, report = _run(tmp_path, "taut.rsxml", "pull.csv", max_clamp_load=100.0)
    clamps = [f for f in report["findings"] if f["kind"] == "clamp"]
    assert len(clamps) == 2 and all(f["value"] > 1000 and f["limit"] == 100 and f["unit"] == "N" for f in clamps)
    _, report = _run(tmp_path, "taut.rsxml", "pull.csv", max_clamp_load=1e6)
    assert not [f for f in report["findings"] if f["kind"] == "clamp"]


def test_the_hose_counts_as_moving_until_the_robot_has_been_still_a_second():
    """A bend tighter than the dynamic radius fails while the hose swings: while the robot moves,
    and for a second after it stops (at the trajectory's end too, which a run goes past by a
    second); only then is it at rest, where the same bend is a warning."""
    from rswarp.kinematics.trajectory import Trajectory
    from rswarp.report.verdicts import moments
    from rswarp.sim.cable.solver import CableOptions
    from rswarp.sim.cables import SWING_AFTER, _trajectory_seconds

    times = np.linspace(0.0, 3.0, 31)
    stops = Trajectory("stops", times, np.minimum(times, 1.0)[:, None])  # moves for 1 s, then still
    ends_moving = Trajectory("ends", times, times[:, None])
    at = moments([stops, ends_moving], [0, 1])
    assert [at(0, t).moving for t in (0.5, 1.5, 1.95, 2.2, 3.5)] == [True, True, True, False, False]
    assert [at(1, t).moving for t in (2.9, 3.5, 3.9, 4.2)] == [True, True, True, False]
    assert _trajectory_seconds([stops], CableOptions()) == pytest.approx(3.0 + SWING_AFTER)
