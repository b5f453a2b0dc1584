"""``rswarp place`` (issue "Where the robot should stand"): every pose of a task solved at every
candidate base in one batch, checked against the forward kinematics (a base's chosen configuration
puts the flange on the pose), against poses known reachable (made by FK at a known base) and known
out of reach (the wrist centre past the arm stretched); the best bases run through the program."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from rswarp.cli import main
from rswarp.errors import InputError
from rswarp.examples import IRB2600
from rswarp.kinematics.kinematics import Kinematics
from rswarp.report.placement.candidates import Vary, base_frames, candidates, parse_vary
from rswarp.report.placement.poses import ProgramPoses
from rswarp.report.placement.reach import CONF, FAR, reach, solve
from rswarp.rsxml.documents import load_mechanism

from conftest import DATA

MODULE = DATA / "place" / "pick_table.mod"


@pytest.fixture(scope="module")
def kin():
    return Kinematics(load_mechanism(IRB2600)[0])


def _poses(kin, q, base):
    link, off = kin.flange_frame()
    world = base @ (kin.fk64(q)[:, link] @ off)
    return ProgramPoses(world, kin.confdata(q), np.ones(len(q), bool), world[:, :3, 3], ("p",) * len(q),
                        ("x.mod:1",) * len(q), len(q))


def test_a_grid_crosses_its_variables_ends_included_and_draws_are_seeded():
    got = candidates(parse_vary(["x=-100:100:3", "yaw=0:90:2"]), None, np.array([5.0, 6.0, 7.0, 8.0]))
    assert got.tolist() == [[-100, 6, 7, 0], [-100, 6, 7, 90], [0, 6, 7, 0], [0, 6, 7, 90], [100, 6, 7, 0],
                            [100, 6, 7, 90]]
    drawn = candidates((Vary("y", -1.0, 1.0),), 16, np.zeros(4), seed=3)
    assert np.array_equal(drawn, candidates((Vary("y", -1.0, 1.0),), 16, np.zeros(4), seed=3))
    assert drawn[:, 1].min() >= -1.0 and drawn[:, 1].max() <= 1.0 and len(np.unique(drawn[:, 1])) == 16


@pytest.mark.parametrize("specs, samples, message", [
    (["x=1:0:3"], None, "the range is empty"),
    (["x=0:1:0"], None, "N must be 1 to"),
    (["pitch=0:1:2"], None, "'pitch' is no variable of a base"),
    (["x=0:1"], None, "give --samples N"),
    (["x=0:1:2", "x=0:1:2"], None, "x is varied twice"),
    ([], None, "give at least one --vary"),
])
def test_bad_ranges_are_refused_in_one_line(specs, samples, message):
    with pytest.raises(InputError, match=message):
        candidates(parse_vary(specs), samples, np.zeros(4))


def test_every_pose_made_at_a_base_is_reached_there_with_its_confdata_and_the_flange_lands_on_it(kin):
    rng = np.random.default_rng(7)
    lo, hi = kin.mech.bounds()
    q = rng.uniform(0.8 * lo, 0.8 * hi, (300, 6))
    where = np.array([[400.0, -250.0, 0.0, 35.0]])
    poses = _poses(kin, q, base_frames(where)[0])
    found = reach(kin, base_frames(where), poses)
    assert found.reached.tolist() == [300]
    chosen, ok, _, local = solve(kin, kin._ik_form(), base_frames(where), poses)
    link, off = kin.flange_frame()
    flange = kin.fk64(chosen[0])[:, link] @ off
    assert ok.all() and np.allclose(flange, local[0], atol=1e-7)
    conf = kin.confdata(chosen[0])  # the program's configuration, not another: axes 4 and 6 a whole turn apart at most
    assert np.array_equal(conf[:, [0, 3]], poses.conf[:, [0, 3]])
    assert np.all((conf[:, 1:3] - poses.conf[:, 1:3]) % 4 == 0)


def test_a_base_too_far_misses_every_pose_by_the_distance_past_the_arm_stretched(kin):
    rng = np.random.default_rng(8)
    lo, hi = kin.mech.bounds()
    q = rng.uniform(0.5 * lo, 0.5 * hi, (50, 6))
    poses = _poses(kin, q, np.eye(4))
    far = np.array([[5000.0, 0.0, 0.0, 0.0]])  # 5 m away: the IRB 2600 reaches 1.65 m
    found = reach(kin, base_frames(far), poses)
    assert found.reached.tolist() == [0] and found.ruled_out[:, FAR].sum() == 50
    assert np.all(found.beyond[:, 0] > 1500.0) and np.all(found.beyond[:, 0] < 6000.0)
    turned = reach(kin, base_frames(np.array([[0.0, 0.0, 0.0, 180.0]])), poses)
    assert turned.ruled_out[:, CONF].sum() > 0  # reached, but in another cf1 than the program's


def test_rswarp_place_ranks_by_cycle_time_and_best_toml_reruns_to_the_same_cycle(tmp_path, capsys):
    out = tmp_path / "place"
    args = ["place", str(IRB2600), str(MODULE), "--vary", "x=-300:300:3", "--vary", "y=-300:300:3", "--top", "2",
            "--out", str(out), "--json"]
    assert main(args) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["candidates"] == 9 and doc["poses"] > 3 and doc["best"] is not None
    timed = [t["cycle_s"] for t in doc["timed"]]
    assert doc["best"]["cycle_s"] == min(t for t in timed if t is not None)
    rows = list(csv.DictReader((out / "candidates.csv").open()))
    assert len(rows) == 9 and sum(r["cycle_s"] != "" for r in rows) == 2
    assert all(int(r["feasible"]) <= (int(r["reached"]) == int(r["poses"])) for r in rows)
    assert (out / "map.png").read_bytes()[:4] == b"\x89PNG" and (out / "limiting.csv").is_file()
    assert main(["program", str(out / "best.toml"), str(MODULE), "--json"]) == 0
    again = json.loads(capsys.readouterr().out)
    assert again["cycle_s"] == pytest.approx(doc["best"]["cycle_s"], abs=1e-9)
    assert main(args) == 0  # the same candidates, rows and best on every run
    assert json.loads(capsys.readouterr().out) == doc


def test_a_mesh_in_the_way_rules_bases_out_and_names_itself(tmp_path, capsys):
    out = tmp_path / "place"
    block = DATA / "place" / "block.stl"  # a column 0.3 x 0.3 x 1 m, 0.45 m behind the base at x = -300 mm
    args = ["place", str(IRB2600), str(MODULE), "--vary", "x=-300:300:3", "--env", f"{block}@-0.75,0,0.5",
            "--top", "1", "--out", str(out), "--json"]
    assert main(args) == 0
    doc = json.loads(capsys.readouterr().out)
    assert (doc["reach_every_pose"], doc["feasible"]) == (3, 2)
    rows = list(csv.DictReader((out / "limiting.csv").open()))
    assert rows and all(r["colliding_pair"] == "Base / block" for r in rows)
    bases = list(csv.DictReader((out / "candidates.csv").open()))
    assert [r["feasible"] for r in bases] == ["0", "1", "1"]  # the base at x = -300 mm stands against it


def test_place_refuses_bad_input_before_any_work(tmp_path, capsys):
    out = tmp_path / "never"
    assert main(["place", str(IRB2600), str(MODULE), "--vary", "x=0:1:0", "--out", str(out)]) == 1
    assert "N must be 1 to" in capsys.readouterr().err and not out.exists()
    empty = tmp_path / "still.mod"
    empty.write_text("MODULE still\n  PROC main()\n    WaitTime 1;\n  ENDPROC\nENDMODULE\n")
    assert main(["place", str(IRB2600), str(empty), "--vary", "x=0:1:2", "--out", str(out)]) == 1
    assert "the task moves to no robtarget" in capsys.readouterr().err and not out.exists()


def test_what_reaches_agrees_with_pinocchio_at_every_base_of_a_grid(kin, tmp_path):
    """An independent check from the exported URDF, on a 4 x 4 grid of bases: at every pose ours
    reaches, pinocchio's forward kinematics puts the flange on it from our configuration, within
    pinocchio's joint limits; at every pose ours misses, pinocchio's damped least squares within
    the limits, from 12 seeds, finds no configuration either."""
    pin = pytest.importorskip("pinocchio")
    from rswarp.export.urdf import to_urdf
    from rswarp.motion.plan import program_plan
    from rswarp.report.placement.poses import program_poses

    mech, plan = program_plan(str(IRB2600), [str(MODULE)], strict=False)
    poses = program_poses(plan, mech, np.eye(4))
    bases = base_frames(candidates(parse_vary(["x=-900:600:4", "y=-900:600:4"]), None, np.zeros(4)))
    q, ok, _, local = solve(kin, kin._ik_form(), bases, poses)
    urdf = tmp_path / "irb.urdf"
    to_urdf(mech, urdf)
    model = pin.buildModelFromUrdf(str(urdf))
    data, frame = model.createData(), model.getFrameId(mech.flanges[0].name)
    lo, hi = model.lowerPositionLimit, model.upperPositionLimit
    seeds = np.random.default_rng(11).uniform(lo, hi, (12, model.nq))

    def flange(qq):
        pin.forwardKinematics(model, data, qq)
        pin.updateFramePlacements(model, data)
        return data.oMf[frame]

    def solved(target) -> bool:
        goal = pin.SE3(target[:3, :3], target[:3, 3])
        for qq in seeds:
            for _ in range(80):
                err = pin.log6(flange(qq).actInv(goal)).vector
                if np.linalg.norm(err) < 1e-9:
                    return True
                J = pin.computeFrameJacobian(model, data, qq, frame)
                qq = np.clip(qq + J.T @ np.linalg.solve(J @ J.T + 1e-8 * np.eye(6), err), lo, hi)
        return False

    assert 0 < ok.all(axis=1).sum() < len(bases)  # bases that reach every pose and bases that do not
    for b, p in zip(*np.nonzero(ok)):
        assert np.abs(flange(q[b, p]).homogeneous - local[b, p]).max() < 1e-9
        assert np.all(q[b, p] >= lo - 1e-12) and np.all(q[b, p] <= hi + 1e-12)
    missed = list(zip(*np.nonzero(~ok)))
    assert missed and not any(solved(local[b, p]) for b, p in missed)


def test_manipulability_is_yoshikawas_of_pinocchios_jacobian(kin, tmp_path):
    pin = pytest.importorskip("pinocchio")
    from rswarp.export.urdf import to_urdf
    from rswarp.report.placement.study import manipulability

    urdf = tmp_path / "irb.urdf"
    to_urdf(kin.mech, urdf)
    model = pin.buildModelFromUrdf(str(urdf))
    data, frame = model.createData(), model.getFrameId(kin.mech.flanges[0].name)
    q = np.random.default_rng(5).uniform(*kin.mech.bounds(), (20, 6))
    theirs = []
    for row in q:
        pin.computeJointJacobians(model, data, row)
        pin.updateFramePlacements(model, data)
        J = pin.getFrameJacobian(model, data, frame, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        theirs.append(np.sqrt(max(np.linalg.det(J @ J.T), 0.0)))
    assert np.allclose(manipulability(kin, q), theirs, rtol=1e-5, atol=1e-9)


def test_a_reach_study_reaches_a_plate_before_the_robot_and_not_one_out_of_reach(tmp_path, capsys):
    import trimesh

    plate = tmp_path / "plate.stl"
    trimesh.creation.box((0.4, 0.4, 0.02)).export(plate)
    near, far = tmp_path / "near", tmp_path / "far"
    assert main(["reach", str(IRB2600), f"{plate}@0.9,0,0.4", "--out", str(near), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    rows = list(csv.DictReader((near / "points.csv").open()))
    assert doc["points"] == len(rows) == 12 and doc["spins"] == 4
    top = [r for r in rows if float(r["nz"]) > 0.99]  # the plate's top, approached from above
    assert top and all(int(r["spins_reached"]) == 4 and float(r["manipulability"]) > 0 for r in top)
    coloured = trimesh.load(near / "part.ply")
    assert len(coloured.faces) == 12 and coloured.visual.face_colors.shape == (12, 4)
    assert main(["reach", str(IRB2600), f"{plate}@5,0,0.4", "--out", str(far), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["reached"] == 0
    assert main(["reach", str(IRB2600), f"{plate}@0.9,0,0.4", "--spin", "0", "--out", str(tmp_path / "x")]) == 1
    assert "--spin must be 1 to 360 degrees" in capsys.readouterr().err


def test_a_robot_on_a_track_is_placed_by_the_tracks_frame_each_pose_where_its_carriage_stands(tmp_path, capsys):
    from rswarp import examples

    cell, module = examples.CELLS / "track_cell.toml", examples.CELLS / "track_transfer.mod"
    out = tmp_path / "place"
    assert main(["place", str(cell), str(module), "--vary", "y=-300:300:3", "--top", "1", "--out", str(out),
                 "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    rows = list(csv.DictReader((out / "candidates.csv").open()))
    assert rows[1]["y_mm"] == "0.000" and rows[1]["reached"] == rows[1]["poses"]  # where the track stands now
    best = (out / "best.toml").read_text()
    assert 'on = "track"' in best and "frame = [0, 0, 0, 0, 0, 0]" in best  # the robot stays on its carriage
    assert main(["program", str(out / "best.toml"), str(module), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["cycle_s"] == pytest.approx(doc["best"]["cycle_s"], abs=1e-9)


def test_the_batch_as_tasks_merged_in_any_order_gives_the_local_run_bit_for_bit(kin, monkeypatch):
    """The placement job of the batch engine, cut into one task per chunk of bases, each task's
    tally merged in reverse order (as Ray's tasks may land): the same arrays as one local run."""
    from rswarp.report.placement import reach as reach_module
    from rswarp.report.placement.clear import Clearance
    from rswarp.report.placement.job import PlaceJob
    from rswarp.sim.engine import run_batch

    monkeypatch.setattr(reach_module, "CHUNK", 400)  # 10 bases a chunk: the batch is 5 tasks

    rng = np.random.default_rng(3)
    lo, hi = kin.mech.bounds()
    poses = _poses(kin, rng.uniform(0.6 * lo, 0.6 * hi, (40, 6)), np.eye(4))
    bases = base_frames(candidates(parse_vary(["x=-800:800:9", "yaw=-90:90:5"]), None, np.zeros(4)))
    check = Clearance(kin.mech, (), None, "cpu", str(IRB2600))
    job = PlaceJob(bases, poses, (), None, str(IRB2600))
    here = run_batch(job, kin.mech, tools=(kin, check))
    parts = []
    for k in reversed(range(job.count)):
        part = job.empty()
        job.run((kin, check), part, range(k, k + 1), lambda units: None)
        parts.append(part)
    there = job.empty()
    for part in parts:
        there.merge(part)
    for a, b in ((here.reach.reached, there.reach.reached), (here.reach.singular, there.reach.singular),
                 (here.reach.ruled_out, there.reach.ruled_out), (here.reach.beyond, there.reach.beyond),
                 (here.clear.free, there.clear.free), (here.clear.hits, there.clear.hits)):
        assert np.array_equal(a, b, equal_nan=True)
    assert job.count == 5 and here.reach.reached.max() > 0 and here.clear.free.any()
