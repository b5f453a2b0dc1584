"""RAPID programs on a robot (issues "Robot programs" and "RAPID tasks as the controller runs
them"): one module per feature under tests/data/rapid, each move's end held against the robot's
own forward kinematics and against where the RAPID data puts the TCP (computed here with SciPy,
apart from rswarp's pose code); MoveL's line and MoveC's circle; speeds; findings; errors at
their lines; the CSV a cable run reads."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import rswarp
from rswarp.cli import main
from rswarp.errors import InputError, RsxmlError
from rswarp.examples import IRB2600, IRB2600_PROGRAM
from rswarp.kinematics.kinematics import Kinematics
from rswarp.kinematics.trajectory import read_trajectory
from rswarp.motion.plan import program_plan
from rswarp.motion.tcp import frames
from rswarp.report.program import run_program

from conftest import DATA

RAPID = DATA / "rapid"


@lru_cache(maxsize=None)
def kin() -> Kinematics:
    return Kinematics(rswarp.load(IRB2600))


@lru_cache(maxsize=None)
def planned(*names: str, **options):
    return program_plan(str(IRB2600), [str(RAPID / n) for n in names], **options)[1]


def tcp(motion, q: np.ndarray) -> np.ndarray:
    """TCP poses in the move's work object at joints ``q`` (N, 4, 4), by the robot's FK."""
    link, m = kin().flange_frame()
    return frames(kin().mech, motion.tool, motion.wobj).relative(kin().fk64(np.atleast_2d(q))[:, link] @ m)


def rapid_pose(trans_mm, quat_wxyz) -> np.ndarray:
    """A RAPID pose as a 4x4 matrix, by SciPy (x, y, z, w order)."""
    m = np.eye(4)
    w, x, y, z = quat_wxyz
    m[:3, :3] = Rotation.from_quat([x, y, z, w]).as_matrix()
    m[:3, 3] = np.asarray(trans_mm) / 1000.0
    return m


def end(p, k: int) -> np.ndarray:
    return p.q[p.moves[k].rows[1] - 1]


def test_tools_and_work_objects_put_the_tcp_on_the_target():
    """The TCP (flange x tframe) lands on the robtarget in its work object (uframe x oframe), for
    a 150 mm tool in a shifted work object and for tool0 in wobj0."""
    p = planned("tools_wobj.mod")
    for k, mv in enumerate(p.moves):
        assert np.abs(tcp(mv.motion, end(p, k))[0] - rapid_pose([900, 0, 900], [0, 0, 1, 0])).max() < 1e-9
    assert np.abs(end(p, 0) - end(p, 1)).max() > 0.05  # a different TCP point: a different pose


def test_offs_and_reltool_put_the_tcp_where_rapid_says():
    p = planned("offs_reltool.mod")
    base = rapid_pose([900, 0, 900], [0, 0, 1, 0])
    offs = base.copy()
    offs[:3, 3] += [0.0, 0.1, -0.05]
    turn = np.eye(4)
    turn[:3, :3] = Rotation.from_euler("z", 30, degrees=True).as_matrix()
    turn[2, 3] = 0.05  # 50 mm along the tool's own z, then turned about it
    for k, want in enumerate([base, offs, base @ turn]):
        assert np.abs(tcp(p.moves[k].motion, end(p, k))[0] - want).max() < 1e-9


def test_movel_keeps_the_tcp_on_its_line():
    """At every sample of every MoveL, the TCP is within 0.1 mm of the straight line."""
    p = planned("offs_reltool.mod")
    count = 0
    for mv in p.moves:
        if mv.motion.kind != "linear":
            continue
        a, b = mv.rows
        points = tcp(mv.motion, p.q[a - 1:b])[:, :3, 3]
        start, stop = points[0], points[-1]
        d = (stop - start) / np.linalg.norm(stop - start)
        off = (points - start) - np.outer((points - start) @ d, d)
        assert np.linalg.norm(off, axis=1).max() < 1e-4
        count += len(points)
    assert count > 100


def test_movec_follows_the_circle_through_its_point():
    p = planned("movec.mod")
    mv = p.moves[1]
    a, b = mv.rows
    points = tcp(mv.motion, p.q[a - 1:b])[:, :3, 3]
    pts = np.array([points[0], [1.1, 0.0, 0.9], [0.9, 0.2, 0.9]])
    ab, ac = pts[1] - pts[0], pts[2] - pts[0]
    n = np.cross(ab, ac)
    centre = pts[0] + (np.cross(n, ab) * (ac @ ac) + np.cross(ac, n) * (ab @ ab)) / (2 * n @ n)
    radius = np.linalg.norm(pts[0] - centre)
    assert np.abs(np.linalg.norm(points - centre, axis=1) - radius).max() < 1e-4
    assert np.linalg.norm(points - pts[1], axis=1).min() < 2e-3  # it passes the circle point
    assert np.linalg.norm(points[-1] - pts[2]) < 1e-6


def test_speeds_within_the_axes_and_the_speeddata():
    """No axis beyond its default speed (90 deg/s); a MoveL's TCP within its v_tcp up to its zone
    (in the corner its speed changes to the next move's); the task ends at rest."""
    p = planned("zones.mod")
    rate = np.abs(np.diff(p.q, axis=0)) / np.diff(p.times)[:, None]
    assert rate.max() <= np.radians(90) * 1.01
    mv = p.moves[1]
    a, b = mv.rows
    points = tcp(mv.motion, p.q[a - 1:b])[:, :3, 3]
    speed = np.linalg.norm(np.diff(points, axis=0), axis=1) / np.diff(p.times[a - 1:b])
    start = p.moves[0].motion.targets[-1].pose.matrix()[:3, 3]  # where the MoveJ before it blends in, z50
    outside = (np.linalg.norm(points[1:] - mv.motion.targets[-1].pose.matrix()[:3, 3], axis=1) > 0.025) & \
        (np.linalg.norm(points[1:] - start, axis=1) > 0.050)  # zCustom at its end
    assert speed[outside].max() <= 0.050 * 1.01 and speed[outside].max() > 0.045  # vSlow: 50 mm/s, reached
    assert np.abs(p.q[-1] - p.q[-2]).max() < 1e-3  # slowing to a stop


def test_t_sets_the_moves_time_and_velset_stretches_it():
    """``\\T`` replaces the speeddata, shorter or longer than it would take (200 mm at v100 is
    2 s of cruise and the ramps the axes' accelerations take); VelSet 50 doubles it; VelSet's top
    speed still holds the TCP to 100 mm/s."""
    p = planned("time_arg.mod")
    took = [round(mv.end - mv.start, 3) for mv in p.moves]
    assert took[1:3] == [1.0, 10.0] and took[4:6] == [3.0, 2.0] and took[6] == 2.0
    assert 2.0 < took[3] < 2.05
    mv = p.moves[7]
    a, b = mv.rows
    points = tcp(mv.motion, p.q[a - 1:b])[:, :3, 3]
    speed = np.linalg.norm(np.diff(points, axis=0), axis=1) / np.diff(p.times[a - 1:b])
    assert took[7] > 2.0 and speed.max() <= 0.100 * 1.01


def test_a_joint_on_its_quadrants_edge_is_in_either():
    """CRobT at q1 = 0 in a turned work object, moved back to: no motion, no confdata error; a
    target whose solution has q1 = 0 meets cf1 = 0 however its pose rounds."""
    p = planned("quadrant_edge.mod")
    assert not p.errors
    assert np.abs(end(p, 1) - end(p, 0)).max() < 1e-6 and abs(end(p, 2)[0]) < 1e-6


def test_ik_api_takes_a_quadrants_edge_in_either_quadrant():
    k = kin()
    pose = k.flange(np.zeros((1, 6)))[0].astype(np.float64)
    for conf in ([0, 0, 0, 0], [-1, 0, 0, 0]):  # q1 = 0: the edge of cf1 0 and -1
        q, found = k.ik64(pose, conf=conf)
        assert found[0] and abs(q[0, 0]) < 1e-6


def test_zonedata_and_speeddata_are_read_predefined_and_declared():
    moves = [mv.motion for mv in planned("zones.mod").moves]
    z50, custom, fine = (m.zone for m in moves)
    assert (z50.fine, z50.pzone_tcp) == (False, 0.05) and (custom.fine, custom.pzone_tcp) == (False, 0.025)
    assert fine.fine and fine.pzone_tcp == 0.0
    assert moves[1].speed.v_tcp == pytest.approx(0.05) and moves[1].speed.v_ori == pytest.approx(np.radians(30))


def test_loops_and_conditions_run_their_moves():
    """skipped.mod's IF and FOR used to be skipped: now the FOR's MoveL runs three times, SetDO
    runs silently, and nothing is left to warn about."""
    p = planned("skipped.mod")
    assert [(m.motion.instruction, m.line) for m in p.moves] == [("MoveJ", 5)] + [("MoveL", 11)] * 3 + [("WaitTime", 13)]
    assert not p.run.warnings


@pytest.mark.parametrize("name", ["crlf_cp1252.mod", "utf16.mod"])
def test_header_crlf_lower_case_and_encodings(name):
    """The %%% header, CRLF, keywords in lower case, a statement over lines, Windows-1252 and a
    UTF-16 file with its byte-order mark: the same module, lines counted as in the file."""
    p = planned(name)
    assert len(p.moves) == 1 and p.moves[0].line == 10
    assert p.moves[0].motion.targets[0].pose.trans == pytest.approx((0.9, 0.0, 0.9))


@pytest.mark.parametrize("name, line, message", [
    ("unknown_name.mod", 5, "'pMissing' is declared nowhere in the task"),
    ("malformed_record.mod", 2, "'pA' must be a robtarget of 4 parts [trans, rot, robconf, extax], not 3"),
    ("out_of_reach.mod", 4, "MoveJ: 'pFar' is out of reach"),
    ("wrong_confdata.mod", 4, "MoveJ: 'pA' has no solution with confdata [1, 0, 0, 0]"),
    ("syntax_error.mod", 4, "RAPID syntax: unexpected 'v500'"),
])
def test_errors_at_their_lines(name, line, message, capsys):
    with pytest.raises(RsxmlError) as exc:
        program_plan(str(IRB2600), [str(RAPID / name)])
    assert exc.value.line == line and message in exc.value.message
    assert main(["program", str(IRB2600), str(RAPID / name)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert any(e.startswith(f"{RAPID / name}:{line}: ") for e in err) and "Traceback" not in "".join(err)


def test_every_target_the_robot_cannot_take_is_reported_in_one_run(tmp_path, capsys):
    path = tmp_path / "three.mod"
    far = "[[{x},0,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]]"
    path.write_text("MODULE Three\n  PROC main()\n" + "".join(
        f"    MoveJ {far.format(x=x)}, v500, fine, tool0;\n" for x in (900, 3000, 950, 4000, 5000)) +
        "  ENDPROC\nENDMODULE\n")
    out = run_program(str(IRB2600), [str(path)])
    assert out.code == 1 and [e.split(":")[1] for e in out.errors] == ["4", "6", "7"]
    assert [m["line"] for m in out.doc["moves"] if "error" not in m] == [3, 5]
    records = [f for f in out.doc["findings"] if f["severity"] == "fail"]
    assert [(f["kind"], f["line"]) for f in records] == [("unreachable", 4), ("unreachable", 6), ("unreachable", 7)]
    assert main(["program", str(IRB2600), str(path)]) == 1
    assert capsys.readouterr().err.count("is out of reach") == 3


def test_a_missing_routine_names_the_procedures_there():
    with pytest.raises(InputError, match=r"no routine .other. in the task of zones.mod \(procedures without parameters: main\)"):
        program_plan(str(IRB2600), [str(RAPID / "zones.mod")], routine="other")


def test_findings_collisions_floor_singularity_and_a_line_it_cannot_follow():
    """Findings are exit 0 and name their move: the arm folded through the floor into its base;
    a MoveL through the wrist singularity (q5 = 0); a MoveL over axis 1, which no configuration
    can follow. A MoveAbsJ through q5 = 0 is no finding: a joint move passes it freely."""
    floor = run_program(str(IRB2600), [str(RAPID / "floor.mod")])
    found = floor.doc["moves"][0]["findings"]
    assert floor.code == 0 and any(f["kind"] == "floor" and "below the floor" in f["text"] for f in found)
    low = next(f for f in found if f["kind"] == "floor")
    assert low["value"] < low["limit"] == 0.0 and low["unit"] == "m" and low["severity"] == "fail"
    assert low["links"] and low["line"] == floor.doc["moves"][0]["line"] and len(low["joints"]) == 6
    hit = next(f for f in found if f["kind"] == "collision" and f["links"][0] == "Base")
    assert hit["links"][1].startswith("Link") and hit["value"] > 0 and hit["t_s"] >= 0
    assert floor.doc["findings"] == sorted(floor.doc["findings"], key=lambda f: f["t_s"])
    singular = run_program(str(IRB2600), [str(RAPID / "singular.mod")])
    assert not singular.doc["moves"][0]["findings"]  # MoveAbsJ to q5 = 0
    near = [f for f in singular.doc["moves"][1]["findings"] if f["kind"] == "singularity"]
    assert len(near) == 1 and near[0]["value"] < near[0]["limit"] == pytest.approx(np.radians(1.0))
    assert abs(near[0]["joints"][4]) == pytest.approx(near[0]["value"])
    through = run_program(str(IRB2600), [str(RAPID / "through_axis1.mod")])
    assert any(f["kind"] == "path" and "cannot follow its line" in f["text"]
               for f in through.doc["moves"][1]["findings"])
    assert "fail: cannot follow its line" in through.text
    clean = run_program(str(IRB2600), [str(IRB2600_PROGRAM)])
    assert all(not m["findings"] for m in clean.doc["moves"])



def test_no_floor_finds_nothing_below_it(capsys):
    """``--no-floor`` (``TaskOptions.floor`` None): the same move as above has no floor finding."""
    out = run_program(str(IRB2600), [str(RAPID / "floor.mod")], floor=None)
    assert out.code == 0 and not any(f["kind"] == "floor" for m in out.doc["moves"] for f in m["findings"])
    assert main(["program", str(IRB2600), str(RAPID / "floor.mod"), "--no-floor", "--json"]) == 0
    assert '"kind": "floor"' not in capsys.readouterr().out

def test_near_a_singularity_only_the_samples_that_need_it_are_slowed():
    """A 0.5 m MoveL that passes 2 deg from the wrist singularity at its middle: the axes stay
    within their speed, the TCP keeps v_tcp away from the singularity, and the move takes
    seconds, not the minute that slowing the whole move took."""
    p = planned("near_singular.mod")
    mv = p.moves[1]
    a, b = mv.rows
    points = tcp(mv.motion, p.q[a - 1:b])[:, :3, 3]
    speed = np.linalg.norm(np.diff(points, axis=0), axis=1) / np.diff(p.times[a - 1:b])
    rate = np.abs(np.diff(p.q[a - 1:b], axis=0)) / np.diff(p.times[a - 1:b])[:, None]
    assert (rate <= p.limits.velocity * 1.01).all()
    assert speed.max() > 0.19  # v200 where the wrist allows it
    assert mv.end - mv.start < 10.0
    assert mv.end - mv.start == pytest.approx(2.5, abs=0.05)  # docs/program.md's figure


def test_json_and_the_csv_a_cable_run_reads(tmp_path):
    csv = tmp_path / "traj.csv"
    out = run_program(str(IRB2600), [str(IRB2600_PROGRAM)], csv=str(csv))
    doc = out.doc
    assert {"name", "file", "line", "joints", "conf"} <= set(doc["targets"][0])
    assert {"file", "line", "routine", "chain", "instruction", "target", "start_s", "end_s", "findings", "joints",
            "tcp_m"} <= set(doc["moves"][0])
    traj = read_trajectory(csv, rswarp.load(IRB2600))
    p = program_plan(str(IRB2600), [str(IRB2600_PROGRAM)])[1]
    assert traj.duration == pytest.approx(p.times[-1], abs=1e-6)
    assert np.abs(traj.at(p.times) - p.q).max() < 1e-5  # the CSV: times to 1 µs, angles to 1e-6 deg
    pick = next(t for t in doc["targets"] if t["name"] == "pPick")
    assert pick["conf"] == [-1, 0, -1, 0]
    assert doc["cycle_s"] == pytest.approx(doc["duration_s"]) and doc["main_loop"] is None


def test_the_csv_never_replaces_a_file_of_the_users(tmp_path):
    mine = tmp_path / "mine.csv"
    mine.write_text("my data\n")
    assert main(["program", str(IRB2600), str(IRB2600_PROGRAM), "--csv", str(mine)]) == 1
    assert mine.read_text() == "my data\n"


def test_random_programs_keep_the_robot_clear_of_itself_and_the_floor():
    """Every sample of 8 random programs (5 s, 200 samples a second) is checked again, apart from
    the generator: the collision sweep's own kernels (``Checker``, no padding) find no pair
    touching that does not touch at home, and every moving link's mesh vertices, posed by forward
    kinematics here, stay 5 mm above the floor (the generator kept 2 cm at the samples it drew);
    a robot without meshes keeps its joint points above it."""
    from rswarp.examples import IRB2600ID
    from rswarp.geometry.meshes import link_mesh
    from rswarp.sim.bodies import collision_bodies
    from rswarp.sim.collisions import Checker
    from rswarp.sim.random_program import random_programs

    t = np.linspace(0.0, 5.0, 1001)
    mech = rswarp.load(IRB2600)
    programs = random_programs(mech, 8, 5.0, seed=3)
    checker = Checker(mech, collision_bodies(mech))
    at_home = checker.verdicts(mech.home_position()[None])[0][0]
    kin = Kinematics(mech)
    meshes = {k: np.asarray(link_mesh(mech, name).vertices) for k, name in enumerate(mech.link_names)
              if name not in ("Base", "Link1")}  # the base stands on the floor; J1 turns Link1 level
    for p in programs:
        q = p.at(t)
        hit, _ = checker.verdicts(q)
        assert not (hit & ~at_home).any()
        poses = kin.fk64(q)
        low = min(float((poses[:, k, 2, :3] @ v.T + poses[:, k, 2, 3:4]).min()) for k, v in meshes.items())
        assert low > 0.005
    assert np.abs(programs[0].q[1] - programs[1].q[1]).max() > 0  # seeds give different programs
    bare = rswarp.load(IRB2600ID)
    kin = Kinematics(bare)
    for p in random_programs(bare, 4, 5.0, seed=1):
        poses = kin.fk64(p.at(t))
        points = [(bare.link_names.index(j.child), np.r_[j.point1, 1.0]) for j in bare.joints[1:]]
        assert min(float((poses[:, k] @ x)[:, 2].min()) for k, x in points) > 0.005


def test_clocks_read_the_time_of_the_moves_too():
    """clock.mod moves back and forth until ClkRead passes 5 s: the clock runs with the moves (as
    planned), so the loop ends after the pass that crosses 5 s."""
    p = planned("clock.mod")
    first = p.moves[0].end
    ends = [mv.end - first for mv in p.moves[1:]]
    assert ends[-1] >= 5.0 and ends[-3] < 5.0 and len(ends) % 2 == 0


def test_a_t_shorter_than_the_axes_allow_takes_their_time_with_a_warning():
    """``t_too_short.mod``: \\T:=0.1 s over 600 mm is beyond the IRB 2600's axes: the move takes
    what they need (more than 0.3 s), said once at its line; \\T:=5 s is kept to the sample."""
    from rswarp.motion.plan import program_plan

    said = []
    p = program_plan(str(IRB2600), [str(RAPID / "t_too_short.mod")], warn=said.append)[1]
    short, kept = (mv.end - mv.start for mv in p.moves[1:3])
    assert 0.3 < short < 1.0 and kept == pytest.approx(5.0, abs=1e-9)
    line = next(k for k, text in enumerate((RAPID / "t_too_short.mod").read_text().splitlines(), 1) if ":=0.1" in text)
    assert [w for w in said if "\\T:=0.1: its axes need" in w and f"t_too_short.mod:{line}: warning" in w]
