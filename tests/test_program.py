"""RAPID programs (issue "Robot programs", parts 2 and 3): one module per feature under
tests/data/rapid, each checked against the robot's own forward kinematics; the errors at their
lines; the trajectory's timing, straightness and circle; the batch check's findings; the CSV a
cable run reads."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest

import rswarp
from rswarp.cli import main
from rswarp.errors import RsxmlError
from rswarp.examples import IRB2600, IRB2600_PROGRAM
from rswarp.kinematics.kinematics import Kinematics
from rswarp.kinematics.program import plan, tcp_pose
from rswarp.kinematics.trajectory import read_trajectory
from rswarp.rapid.module import read_module
from rswarp.report.program import run_program

from conftest import DATA

RAPID = DATA / "rapid"


@lru_cache(maxsize=None)
def kin() -> Kinematics:
    return Kinematics(rswarp.load(IRB2600))


@lru_cache(maxsize=None)
def planned(name: str):
    return plan(kin(), read_module(RAPID / name))


def tcp_in_wobj(move, q: np.ndarray) -> np.ndarray:
    link, m = kin().flange_frame()
    return tcp_pose(kin().mech, move, kin().fk64(np.atleast_2d(q))[:, link] @ m)


def moves(p):
    return [s for s in p.module.steps if hasattr(s, "targets")]


def test_tools_and_work_objects_put_the_tcp_on_the_target():
    """The TCP (flange x tframe) lands on the robtarget in its work object (uframe x oframe), for
    a 150 mm tool in a shifted work object and for tool0 in wobj0."""
    p = planned("tools_wobj.mod")
    for move, planned_move in zip(moves(p), p.moves):
        end = p.q[planned_move.rows[1] - 1]
        got = tcp_in_wobj(move, end)[0]
        want = move.targets[0].pose.matrix()
        assert np.abs(got - want).max() < 1e-9
    first, second = (p.q[m.rows[1] - 1] for m in p.moves)
    assert np.abs(first - second).max() > 0.05  # a different TCP point: a different pose


def test_offs_and_reltool():
    """Offs displaces in the work object; RelTool in the tool frame, then turns about its z."""
    m = read_module(RAPID / "offs_reltool.mod")
    base, offs, rel = (s.targets[0].pose for s in m.steps)
    assert np.allclose(np.subtract(offs.trans, base.trans), [0.0, 0.1, -0.05])
    assert np.allclose(offs.quat, base.quat)
    b, r = base.matrix(), rel.matrix()
    assert np.allclose(r[:3, 3], b[:3, 3] + b[:3, 2] * 0.05)  # 50 mm along the tool's z
    turn = b[:3, :3].T @ r[:3, :3]
    assert np.allclose(turn, [[np.cos(np.pi / 6), -np.sin(np.pi / 6), 0], [np.sin(np.pi / 6), np.cos(np.pi / 6), 0],
                              [0, 0, 1]])


def test_movel_keeps_the_tcp_on_its_line():
    """At every sample of every MoveL, the TCP is within 0.1 mm of the straight line."""
    p = planned("offs_reltool.mod")
    count = 0
    for move, pm in zip(moves(p), p.moves):
        if pm.instruction != "MoveL":
            continue
        a, b = pm.rows
        tcp = tcp_in_wobj(move, p.q[a - 1:b])[:, :3, 3]
        start, end = tcp[0], tcp[-1]
        d = (end - start) / np.linalg.norm(end - start)
        off = (tcp - start) - np.outer((tcp - start) @ d, d)
        assert np.linalg.norm(off, axis=1).max() < 1e-4
        count += len(tcp)
    assert count > 100


def test_movec_follows_the_circle_through_its_point():
    p = planned("movec.mod")
    move, pm = moves(p)[1], p.moves[1]
    a, b = pm.rows
    tcp = tcp_in_wobj(move, p.q[a - 1:b])[:, :3, 3]
    pts = np.array([tcp[0], move.targets[0].pose.trans, move.targets[1].pose.trans])
    ab, ac = pts[1] - pts[0], pts[2] - pts[0]
    n = np.cross(ab, ac)
    centre = pts[0] + (np.cross(n, ab) * (ac @ ac) + np.cross(ac, n) * (ab @ ab)) / (2 * n @ n)
    radius = np.linalg.norm(pts[0] - centre)
    assert np.abs(np.linalg.norm(tcp - centre, axis=1) - radius).max() < 1e-4
    assert np.linalg.norm(tcp - pts[1], axis=1).min() < 2e-3  # it passes the circle point
    assert np.linalg.norm(tcp[-1] - pts[2]) < 1e-6


def test_speeds_within_the_axes_and_the_speeddata():
    """No axis beyond its default speed (90 deg/s); a MoveL's TCP within its v_tcp; every move
    starts and ends at rest (zones are not blended)."""
    p = planned("zones.mod")
    rate = np.abs(np.diff(p.q, axis=0)) / np.diff(p.times)[:, None]
    assert rate.max() <= np.radians(90) * 1.01
    move, pm = moves(p)[1], p.moves[1]
    a, b = pm.rows
    tcp = tcp_in_wobj(move, p.q[a - 1:b])[:, :3, 3]
    speed = np.linalg.norm(np.diff(tcp, axis=0), axis=1) / np.diff(p.times[a - 1:b])
    assert speed.max() <= 0.050 * 1.01  # vSlow: 50 mm/s
    for pm in p.moves:
        if pm.rows[1] - pm.rows[0] > 2:
            assert np.abs(p.q[pm.rows[1] - 1] - p.q[pm.rows[1] - 2]).max() < 1e-3  # slowing to a stop


def test_zonedata_is_read_predefined_and_declared():
    m = read_module(RAPID / "zones.mod")
    z50, custom, fine = (s.zone for s in m.steps)
    assert (z50.fine, z50.pzone_tcp) == (False, 0.05)
    assert (custom.fine, custom.pzone_tcp) == (False, 0.025)
    assert fine.fine and fine.pzone_tcp == 0.0
    assert m.steps[1].speed.v_tcp == pytest.approx(0.05) and m.steps[1].speed.v_ori == pytest.approx(np.radians(30))


def test_statements_rswarp_does_not_run_are_skipped_with_a_warning_at_their_line():
    m = read_module(RAPID / "skipped.mod")
    assert [(w.line, w.severity) for w in m.warnings] == [(6, "warning"), (7, "warning"), (10, "warning")]
    assert "SetDO" in m.warnings[0].message and "IF" in m.warnings[1].message and "FOR" in m.warnings[2].message
    assert [type(s).__name__ for s in m.steps] == ["Move", "Wait"]


@pytest.mark.parametrize("name", ["crlf_cp1252.mod", "utf16.mod"])
def test_header_crlf_lower_case_and_encodings(name):
    """The %%% header, CRLF, keywords in lower case, a statement over lines, Windows-1252 and a
    UTF-16 file with its byte-order mark: the same module, lines counted as in the file."""
    m = read_module(RAPID / name)
    assert m.name == "Encoded" and len(m.steps) == 1 and m.steps[0].line == 10
    assert m.steps[0].targets[0].pose.trans == pytest.approx((0.9, 0.0, 0.9))


@pytest.mark.parametrize("name, line, message", [
    ("unknown_name.mod", 5, "unknown name 'pMissing'"),
    ("malformed_record.mod", 2, "robtarget 'pA' is malformed"),
    ("out_of_reach.mod", 4, "robtarget 'pFar' is out of reach"),
    ("wrong_confdata.mod", 4, "robtarget 'pA' has no solution with confdata [1, 0, 0, 0]"),
    ("syntax_error.mod", 4, "RAPID syntax: unexpected 'v500'"),
])
def test_errors_at_their_lines(name, line, message, capsys):
    with pytest.raises(RsxmlError) as exc:
        run_program(str(IRB2600), str(RAPID / name))
    assert exc.value.line == line and message in exc.value.message
    assert main(["program", str(IRB2600), str(RAPID / name)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith(f"{RAPID / name}:{line}: ") and "Traceback" not in "".join(err)


def test_a_missing_routine_names_the_routines_there():
    with pytest.raises(RsxmlError, match="no routine 'other' .* \\(routines: main\\)"):
        read_module(RAPID / "zones.mod", routine="other")


def test_findings_collisions_floor_singularity_and_a_line_it_cannot_follow():
    """Findings are exit 0 and name their move: the arm folded through the floor into its base;
    a wrist straight (q5 = 0); a MoveL over axis 1, which no configuration can follow."""
    floor = run_program(str(IRB2600), str(RAPID / "floor.mod"))
    found = floor.doc["moves"][0]["findings"]
    assert floor.code == 0 and any("below the floor" in f for f in found)
    assert any(f.startswith("Base hits Link") for f in found)
    singular = run_program(str(IRB2600), str(RAPID / "singular.mod"))
    assert any("wrist singularity" in f for f in singular.doc["moves"][1]["findings"])
    through = run_program(str(IRB2600), str(RAPID / "through_axis1.mod"))
    assert any("cannot follow its line" in f for f in through.doc["moves"][1]["findings"])
    clean = run_program(str(IRB2600), str(IRB2600_PROGRAM))
    assert all(not m["findings"] for m in clean.doc["moves"])


def test_json_and_the_csv_a_cable_run_reads(tmp_path):
    csv = tmp_path / "traj.csv"
    out = run_program(str(IRB2600), str(IRB2600_PROGRAM), csv=str(csv))
    doc = out.doc
    assert {"name", "line", "joints", "conf"} <= set(doc["targets"][0])
    assert {"line", "instruction", "target", "start_s", "end_s", "findings"} <= set(doc["moves"][0])
    traj = read_trajectory(csv, rswarp.load(IRB2600))
    p = plan(kin(), read_module(IRB2600_PROGRAM))
    assert traj.duration == pytest.approx(p.times[-1], abs=1e-6)
    assert np.abs(traj.at(p.times) - p.q).max() < 1e-5  # the CSV: times to 1 µs, angles to 1e-6 deg
    pick = next(t for t in doc["targets"] if t["name"] == "pPick")
    assert pick["conf"] == [-1, 0, -1, 0]


def test_the_csv_never_replaces_a_file_of_the_users(tmp_path):
    mine = tmp_path / "mine.csv"
    mine.write_text("my data\n")
    assert main(["program", str(IRB2600), str(IRB2600_PROGRAM), "--csv", str(mine)]) == 1
    assert mine.read_text() == "my data\n"


@pytest.mark.parametrize("text, message", [
    ("MODULE D\n  CONST num x:=" + "[" * 5000 + "1" + "]" * 5000 + ";\nENDMODULE\n", "nested deeper than 64"),
    ("MODULE D\n  CONST num x:=" + "-" * 5000 + "1;\nENDMODULE\n", "nested deeper than 64"),
])
def test_hostile_modules_are_clear_errors_not_crashes(tmp_path, text, message):
    path = tmp_path / "hostile.mod"
    path.write_text(text)
    with pytest.raises(RsxmlError, match=message) as exc:
        read_module(path)
    assert exc.value.line == 2
    path.write_bytes(b"\x00\x01MODULE")
    with pytest.raises(RsxmlError, match="NUL bytes"):
        read_module(path)


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
