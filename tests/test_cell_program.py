"""RAPID programs over a cell (the robot on a track, the robot beside a two-axis positioner): a
robtarget's extax drives the external axes with the robot. Every expectation here is computed by
hand with NumPy/SciPy: the robot's base on the carriage, the positioner's face plate and the work
object on it are built from the cell's numbers (docs/cells.md), the robtargets are read from the
modules' text; only the arm's own forward kinematics in its base frame is rswarp's
(``Kinematics.fk64``). The RAPID modules are under tests/data/cell_programs."""

from __future__ import annotations

import re
import subprocess
import sys
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from rswarp.kinematics.kinematics import Kinematics
from rswarp.kinematics.trajectory import read_trajectory
from rswarp.motion.plan import program_plan
from rswarp.report.program import run_program

from conftest import DATA

ROOT = Path(__file__).resolve().parents[1]
PROGRAMS = DATA / "cell_programs"
TRACK_CELL = ROOT / "examples" / "cells" / "track_cell.toml"
POSITIONER_CELL = ROOT / "examples" / "cells" / "positioner_cell.toml"
ROBOT = ROOT / "examples" / "irb2600_12_165" / "IRB2600_12_165__01.rsxml"

TRACK = PROGRAMS / "track_acceptance.mod"
POSITIONER = PROGRAMS / "positioner_acceptance.mod"
TIMING = PROGRAMS / "track_timing.mod"
STATE = PROGRAMS / "track_state.mod"
UNKNOWN = PROGRAMS / "track_unknown.mod"

GRIPPER_Z = 0.180  # m: tGripper's tframe, straight along the flange's z
TORCH_Z = 0.200  # m: tTorch's tframe
BASE_ON_CARRIAGE = 0.400  # m: the robot's base above the carriage's origin (track_cell.toml's frame)
POS_TOL = 0.5e-3  # m
TURN_TOL = 1e-3  # rad


# -- poses by hand ------------------------------------------------------------------------------
def translation(x: float, y: float, z: float) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = [x, y, z]
    return m


def rotation(axis: str, angle: float) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = Rotation.from_euler(axis, angle).as_matrix()
    return m


def rapid_pose(trans_mm, quat_wxyz) -> np.ndarray:
    """A RAPID pose (mm, quaternion w first) as a 4x4 matrix in metres."""
    w, x, y, z = quat_wxyz
    m = np.eye(4)
    m[:3, :3] = Rotation.from_quat([x, y, z, w]).as_matrix()
    m[:3, 3] = np.asarray(trans_mm, float) / 1000.0
    return m


def turn_between(a: np.ndarray, b: np.ndarray) -> float:
    """The angle (rad) of the rotation from ``a`` to ``b`` (3x3 each)."""
    return float(np.arccos(np.clip((np.trace(a.T @ b) - 1) / 2, -1, 1)))


def track_base(eax_a_m) -> np.ndarray:
    """The robot's base in the world with the carriage at ``eax_a_m`` (m): the track's flange at
    (d, 0, 0.4 m) with the world's axes, the base bolted on it 400 mm up: (N, 4, 4)."""
    d = np.atleast_1d(np.asarray(eax_a_m, float))
    out = np.broadcast_to(np.eye(4), (len(d), 4, 4)).copy()
    out[:, 0, 3] = d
    out[:, 2, 3] = BASE_ON_CARRIAGE
    return out


def positioner_wobj(tilt: float, turn: float) -> np.ndarray:
    """wTable in the world at the positioner's (tilt, turn) (rad): the unit's frame (1100 mm along
    x, turned -90 deg about z) @ the face plate (tilted about the line y = 0, z = 0.9 m along +x, then
    800 mm up, turned about its normal) @ the work object's uframe (100 mm above the plate)."""
    unit = translation(1.1, 0, 0) @ rotation("z", -np.pi / 2)
    about_tilt_axis = translation(0, 0, 0.9) @ rotation("x", tilt) @ translation(0, 0, -0.9)
    plate = about_tilt_axis @ translation(0, 0, 0.8) @ rotation("z", turn)
    return unit @ plate @ translation(0, 0, 0.1)


def robtargets(module: Path) -> dict[str, tuple[np.ndarray, list[float | None]]]:
    """The module's robtargets read from its text: name -> (pose in its work object, extax in
    RAPID's units with None for 9E9)."""
    num = r"\s*([-+0-9.eE]+)\s*"
    four = ",".join([num] * 4)
    pattern = re.compile(rf"robtarget\s+(\w+)\s*:=\s*\[\s*\[{','.join([num] * 3)}\]\s*,\s*\[{four}\]\s*,"
                         rf"\s*\[{four}\]\s*,\s*\[{','.join([num] * 6)}\]\s*\]")
    out = {}
    for found in pattern.finditer(module.read_text()):
        v = [float(x) for x in found.groups()[1:]]
        extax = [None if abs(e) > 8e9 else e for e in v[11:17]]
        out[found.group(1)] = (rapid_pose(v[0:3], v[3:7]), extax)
    return out


def line_of(module: Path, text: str) -> int:
    """The 1-based line of the module's only line holding ``text``."""
    hits = [k + 1 for k, line in enumerate(module.read_text().splitlines()) if text in line]
    assert len(hits) == 1, (text, hits)
    return hits[0]


@lru_cache(maxsize=None)
def kinematics(mech) -> Kinematics:
    return Kinematics(mech)


def flanges(mech, q: np.ndarray) -> np.ndarray:
    """The flange in the robot's base frame at joints ``q`` (N, 4, 4), the arm's own FK."""
    kin = kinematics(mech)
    link, offset = kin.flange_frame()
    return kin.fk64(np.atleast_2d(q))[:, link] @ offset


def track_tcp_world(mech, plan, rows) -> np.ndarray:
    """tGripper's TCP in the world at trajectory ``rows`` of a track-cell plan (N, 4, 4)."""
    rows = np.atleast_1d(rows)
    return track_base(plan.ext[rows, 0]) @ flanges(mech, plan.q[rows]) @ translation(0, 0, GRIPPER_Z)


def end_row(move) -> int:
    return move.rows[1] - 1


def moves_named(plan, instruction: str, name: str) -> list:
    return [m for m in plan.moves if m.motion.instruction == instruction and m.motion.names == (name,)]


def one_move(plan, instruction: str, name: str):
    found = moves_named(plan, instruction, name)
    assert len(found) == 1, [(m.motion.instruction, m.motion.names) for m in plan.moves]
    return found[0]


# -- the plans, made once --------------------------------------------------------------------
@pytest.fixture(scope="module")
def track():
    """(mechanism, plan, warnings) of track_acceptance.mod on the track cell."""
    warnings: list[str] = []
    mech, plan = program_plan(str(TRACK_CELL), [str(TRACK)], strict=False, warn=warnings.append)
    return mech, plan, warnings


@pytest.fixture(scope="module")
def track_alone():
    """The same program on the robot alone (its RSXML, no track)."""
    warnings: list[str] = []
    mech, plan = program_plan(str(ROBOT), [str(TRACK)], strict=False, warn=warnings.append)
    return mech, plan, warnings


@pytest.fixture(scope="module")
def positioner():
    mech, plan = program_plan(str(POSITIONER_CELL), [str(POSITIONER)], strict=False)
    return mech, plan


@pytest.fixture(scope="module")
def timing():
    """(mechanism, plan, run_program's Output) of track_timing.mod on the track cell."""
    mech, plan = program_plan(str(TRACK_CELL), [str(TIMING)], strict=False)
    out = run_program(str(TRACK_CELL), [str(TIMING)])
    return mech, plan, out


@pytest.fixture(scope="module")
def state():
    mech, plan = program_plan(str(TRACK_CELL), [str(STATE)], strict=False)
    return mech, plan


@pytest.fixture(scope="module")
def track_run(tmp_path_factory):
    """run_program of track_acceptance.mod on the track cell, with its CSV."""
    csv = tmp_path_factory.mktemp("cell_csv") / "t.csv"
    warnings: list[str] = []
    out = run_program(str(TRACK_CELL), [str(TRACK)], csv=str(csv), warn=warnings.append)
    return out, csv


# -- 1. the track ------------------------------------------------------------------------------
def test_track_program_takes_every_target_out_of_the_arms_own_reach(track):
    """Targets up to 3.9 m down the line, 2.3 m past where the arm alone could reach, are all taken:
    no errors, no move skipped, and the plan has one external column, eax_a, a linear axis of the
    track's J1."""
    _, plan, _ = track
    assert plan.errors == ()
    assert [m.error for m in plan.moves] == [None] * len(plan.moves)
    assert len(plan.moves) == 7
    assert plan.ext is not None and plan.ext.shape == (len(plan.times), 1)
    assert plan.ext_axes == (("eax_a", "track", "J1", False),)
    assert plan.ext[:, 0].max() == pytest.approx(3.2, abs=1e-9)  # the carriage went 3 m down the line
    assert np.all(np.isfinite(plan.q)) and np.all(np.isfinite(plan.ext))


def test_track_fine_moves_end_on_their_robtargets_with_the_carriage_at_eax_a(track):
    """Each move that ends fine leaves the TCP (carriage @ base 400 mm up @ arm FK @ tframe) on its
    robtarget in the world within 0.5 mm and 1e-3 rad, and the carriage at the target's eax_a
    within 1e-6 m."""
    mech, plan, _ = track
    targets = robtargets(TRACK)
    zoned = line_of(TRACK, "MoveL pPlaceApp, v1000, z50")
    assert [m.motion.line for m in plan.moves if not m.motion.zone.fine] == [zoned]
    checked = 0
    for move in plan.moves:
        if move.motion.line == zoned:
            continue  # ends in a zone: it leaves for the next target before it gets there
        want, extax = targets[move.motion.names[0]]
        row = end_row(move)
        got = track_tcp_world(mech, plan, row)[0]
        assert np.linalg.norm(got[:3, 3] - want[:3, 3]) < POS_TOL, (move.motion.line, got[:3, 3], want[:3, 3])
        assert turn_between(got[:3, :3], want[:3, :3]) < TURN_TOL, move.motion.line
        assert abs(plan.ext[row, 0] - extax[0] / 1000.0) < 1e-6, (move.motion.line, plan.ext[row, 0], extax[0])
        checked += 1
    assert checked == 6


def test_track_movel_keeps_its_line_while_the_carriage_runs_1500_mm(track):
    """MoveL pPickApp -> pCarry (fine at both ends, eax_a 200 -> 1700): at every sample row the TCP
    in the world is within 0.5 mm of the straight line between the two robtargets, while the
    carriage really runs along under it (1.5 m, steadily forwards)."""
    mech, plan, _ = track
    targets = robtargets(TRACK)
    move = one_move(plan, "MoveL", "pCarry")
    start, goal = targets["pPickApp"][0][:3, 3], targets["pCarry"][0][:3, 3]
    assert abs(targets["pCarry"][1][0] - targets["pPickApp"][1][0]) >= 1000
    rows = np.arange(*move.rows)
    assert len(rows) > 50
    tcp = track_tcp_world(mech, plan, rows)[:, :3, 3]
    axis = (goal - start) / np.linalg.norm(goal - start)
    off = tcp - start
    distance = np.linalg.norm(off - (off @ axis)[:, None] * axis, axis=1)
    assert distance.max() < POS_TOL, distance.max()
    along = off @ axis
    assert along.min() > -POS_TOL and along.max() < np.linalg.norm(goal - start) + POS_TOL
    carriage = plan.ext[rows, 0]
    assert carriage[-1] - carriage[0] > 1.45
    assert np.all(np.diff(carriage) >= -1e-9)  # forwards only
    middle = carriage[len(carriage) // 2]
    assert 0.3 < middle < 1.6  # it moves during the line, not before or after it
    # the arm's own joints move too: it is not the carriage alone carrying a still arm
    assert np.abs(plan.q[rows[-1]] - plan.q[rows[0]]).max() > 0.05


def test_track_movel_tcp_speed_stays_within_v_tcp(track):
    """Along the same MoveL (v1000), the TCP's speed in the world, by finite differences over the
    plan's times, never goes over 1000 mm/s by more than 1 %, and it does get near it."""
    mech, plan, _ = track
    move = one_move(plan, "MoveL", "pCarry")
    rows = np.arange(move.rows[0] - 1, move.rows[1])  # from the row before: where the move starts
    tcp = track_tcp_world(mech, plan, rows)[:, :3, 3]
    dt = np.diff(plan.times[rows])
    assert np.all(dt > 0)
    speed = np.linalg.norm(np.diff(tcp, axis=0), axis=1) / dt
    assert speed.max() <= 1.0 * 1.01, speed.max()
    assert speed.max() > 0.9, speed.max()


def test_the_same_program_on_the_robot_alone_is_out_of_reach_and_ignores_eax_a(track_alone):
    """Without the track the far targets are out of reach (errors at their lines), the near ones
    are taken, and the eax_a values are said to be ignored."""
    _, plan, warnings = track_alone
    assert len(plan.errors) >= 1
    assert all("out of reach" in e.message for e in plan.errors), plan.errors
    lines = {e.line for e in plan.errors}
    assert line_of(TRACK, "MoveL pCarry,") in lines
    assert line_of(TRACK, "MoveL pPlace,") in lines
    assert line_of(TRACK, "MoveL pPick,") not in lines  # 0.9 m out: the arm reaches it alone
    assert plan.ext is None or plan.ext.shape[1] == 0
    said = " ".join(warnings)
    assert "eax_a" in said and "ignore" in said, warnings
    assert any(t.ignored and "eax_a" in t.ignored for t in plan.targets), [t.ignored for t in plan.targets]


# -- 2. the positioner -------------------------------------------------------------------------
def test_positioner_movel_keeps_the_seam_in_the_turning_work_object(positioner):
    """MoveL pSeamStart -> pSeamEnd in wTable (coordinated with STN1): eax_a holds 20 deg while
    eax_b turns 0 -> 90 deg; at every row the TCP, taken into the work object's frame where the
    face plate is at that row, stays on the seam's line (|y|, |z| < 0.5 mm), going -150 -> 150 mm."""
    mech, plan = positioner
    assert plan.errors == ()
    assert [a[0] for a in plan.ext_axes] == ["eax_a", "eax_b"]
    move = one_move(plan, "MoveL", "pSeamEnd")
    rows = np.arange(move.rows[0] - 1, move.rows[1])
    assert len(rows) > 50
    tilt, turn = plan.ext[rows, 0], plan.ext[rows, 1]
    assert np.abs(tilt - np.radians(20)).max() < 1e-9
    assert turn[0] == pytest.approx(0.0, abs=1e-9) and turn[-1] == pytest.approx(np.pi / 2, abs=1e-9)
    assert np.all(np.diff(turn) >= -1e-12)
    assert 0.2 < turn[len(turn) // 2] < 1.4  # it turns during the seam
    world = flanges(mech, plan.q[rows]) @ translation(0, 0, TORCH_Z)  # the robot stands at the origin
    inwobj = np.array([np.linalg.inv(positioner_wobj(a, b)) @ t for a, b, t in zip(tilt, turn, world)])
    p = inwobj[:, :3, 3]
    assert np.abs(p[:, 1]).max() < POS_TOL, np.abs(p[:, 1]).max()
    assert np.abs(p[:, 2]).max() < POS_TOL, np.abs(p[:, 2]).max()
    assert p[0, 0] == pytest.approx(-0.150, abs=POS_TOL) and p[-1, 0] == pytest.approx(0.150, abs=POS_TOL)
    # in the world the TCP does not go straight: the plate turns the seam under it
    w = world[:, :3, 3]
    chord = (w[-1] - w[0]) / np.linalg.norm(w[-1] - w[0])
    bow = np.linalg.norm((w - w[0]) - ((w - w[0]) @ chord)[:, None] * chord, axis=1)
    assert bow.max() > 0.02


def test_positioner_fine_moves_end_on_their_targets_in_the_work_object(positioner):
    """Each robtarget move ends fine with the TCP on its target in wTable (0.5 mm, 1e-3 rad), the
    plate where the target's eax_a and eax_b put it."""
    mech, plan = positioner
    targets = robtargets(POSITIONER)
    checked = 0
    for move in plan.moves:
        if move.motion.kind == "absolute":
            continue
        name = move.motion.names[0]
        if name.startswith("Offs("):
            want, extax = targets["pSeamEnd"]
            want = translation(0, 0, 0.080) @ want
        else:
            want, extax = targets[name]
        row = end_row(move)
        a, b = plan.ext[row]
        assert a == pytest.approx(np.radians(extax[0]), abs=1e-9) and b == pytest.approx(np.radians(extax[1]), abs=1e-9)
        got = np.linalg.inv(positioner_wobj(a, b)) @ flanges(mech, plan.q[row])[0] @ translation(0, 0, TORCH_Z)
        assert np.linalg.norm(got[:3, 3] - want[:3, 3]) < POS_TOL, (name, got[:3, 3], want[:3, 3])
        assert turn_between(got[:3, :3], want[:3, :3]) < TURN_TOL, name
        checked += 1
    assert checked == 4


# -- 3. timing ---------------------------------------------------------------------------------
def ruckig_duration(distance: float, v: float, a: float, j: float) -> float:
    import ruckig

    inp = ruckig.InputParameter(1)
    inp.current_position, inp.current_velocity, inp.current_acceleration = [0.0], [0.0], [0.0]
    inp.target_position, inp.target_velocity, inp.target_acceleration = [distance], [0.0], [0.0]
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = [v], [a], [j]
    otg, traj = ruckig.Ruckig(1), ruckig.Trajectory(1)
    otg.calculate(inp, traj)
    return float(traj.duration)


def test_track_alone_move_takes_ruckigs_time_for_the_tracks_limits(timing):
    """MoveAbsJ jAt0 -> jAt2000 (the arm's joints the same, eax_a 0 -> 2000 mm, v5000 so the TCP's
    speed does not cap it): the carriage goes 2 m and the move lasts what Ruckig gives for 2 m at
    the track's velocity, acceleration and jerk (the eax_a row of the axis limits), within 1 %;
    the arm's joints do not move."""
    _, plan, out = timing
    assert plan.errors == () and out.code == 0
    rows = [r for r in out.doc["axis_limits"]["axes"] if r["axis"].startswith("eax_a")]
    assert len(rows) == 1, [r["axis"] for r in out.doc["axis_limits"]["axes"]]
    lim = rows[0]
    assert lim["velocity"] > 0 and lim["acceleration"] > 0 and lim["jerk"] > 0
    move = one_move(plan, "MoveAbsJ", "jAt2000")
    first, last = move.rows
    assert plan.ext[first - 1, 0] == pytest.approx(0.0, abs=1e-9)
    assert plan.ext[last - 1, 0] == pytest.approx(2.0, abs=1e-9)
    assert np.abs(plan.q[first - 1:last] - plan.q[first - 1]).max() < 1e-9
    want = ruckig_duration(2.0, lim["velocity"], lim["acceleration"], lim["jerk"])
    got = move.end - move.start
    assert got == pytest.approx(want, rel=0.01), (got, want)
    assert plan.times[last - 1] - plan.times[first - 1] == pytest.approx(want, rel=0.01)
    said = next(m for m in out.doc["moves"] if m["line"] == move.motion.line)
    assert said["end_s"] - said["start_s"] == pytest.approx(want, rel=0.01)
    # the carriage's top speed in the samples is the track's, not more
    v = np.abs(np.diff(plan.ext[first - 1:last, 0])) / np.diff(plan.times[first - 1:last])
    assert v.max() <= lim["velocity"] * 1.01 and v.max() > 0.95 * lim["velocity"]


def test_movej_moves_the_arm_and_the_carriage_together(timing):
    """MoveJ pDown from the arm at jAt2000's joints and eax_a 2000 to eax_a 2600: the robot's joints
    and the carriage start and arrive together (at the move's end row both are at their targets,
    the TCP on pDown; halfway and near the end neither has arrived, both having left)."""
    mech, plan, _ = timing
    move = one_move(plan, "MoveJ", "pDown")
    first, last = move.rows
    rows = np.arange(first - 1, last)
    q, e = plan.q[rows], plan.ext[rows, 0]
    pose, extax = robtargets(TIMING)["pDown"]
    assert e[0] == pytest.approx(2.0, abs=1e-9) and e[-1] == pytest.approx(extax[0] / 1000, abs=1e-6)
    tcp = track_tcp_world(mech, plan, rows[-1])[0]
    assert np.linalg.norm(tcp[:3, 3] - pose[:3, 3]) < POS_TOL
    arm_way = np.abs(q[-1] - q[0])
    assert arm_way.max() > 0.1  # the arm has a real way to go too
    moving = arm_way > 1e-3
    for share in (0.5, 0.9):
        k = int(round(share * (len(rows) - 1)))
        arm_done = np.abs(q[k] - q[0])[moving] / arm_way[moving]
        track_done = abs(e[k] - e[0]) / abs(e[-1] - e[0])
        assert np.all((arm_done > 0.01) & (arm_done < 0.995)), (share, arm_done)
        assert 0.01 < track_done < 0.995, (share, track_done)
    # neither arrives early and waits: ten samples before the end each still has some way to go
    assert np.abs(q[-10] - q[-1])[moving].min() > 1e-6 and abs(e[-10] - e[-1]) > 1e-6
    assert move.end - move.start > 0


# -- 4. CJointT, CRobT, CalcJointT, CalcRobT -----------------------------------------------------
def test_crobt_and_cjointt_carry_the_carriage(state):
    """After MoveJ pHere (eax_a 1500): MoveL Offs(CRobT(), 0, 100, 0) keeps the carriage at 1.5 m
    and puts the TCP 100 mm along y in the world; MoveAbsJ CJointT() returns to pHere with the
    carriage at 1.5 m and the arm's joints those it had there."""
    mech, plan = state
    assert plan.errors == () and [m.error for m in plan.moves] == [None] * len(plan.moves)
    here, extax = robtargets(STATE)["pHere"]
    assert extax[0] == 1500
    first = one_move(plan, "MoveJ", "pHere")
    offs = one_move(plan, "MoveL", "Offs(pNow,0,100,0)")
    back = one_move(plan, "MoveAbsJ", "jNow")
    assert plan.ext[end_row(first), 0] == pytest.approx(1.5, abs=1e-6)
    assert np.abs(plan.ext[offs.rows[0]:offs.rows[1], 0] - 1.5).max() < 1e-6
    got = track_tcp_world(mech, plan, end_row(offs))[0]
    assert np.linalg.norm(got[:3, 3] - (here[:3, 3] + [0, 0.1, 0])) < POS_TOL, got[:3, 3]
    assert plan.ext[end_row(back), 0] == pytest.approx(1.5, abs=1e-6)
    assert np.abs(plan.q[end_row(back)] - plan.q[end_row(first)]).max() < 1e-6
    got = track_tcp_world(mech, plan, end_row(back))[0]
    assert np.linalg.norm(got[:3, 3] - here[:3, 3]) < POS_TOL


def test_calcjointt_and_calcrobt_solve_from_where_the_target_puts_the_carriage(state):
    """CalcJointT(pFar) with pFar's eax_a 3000: MoveAbsJ to it moves the carriage to 3 m and the TCP
    onto pFar (0.5 mm, 1e-3 rad), though the carriage stood at 1.5 m when it was computed;
    CalcRobT(jNow) is pHere with eax_a 1500 (MoveL to it: the TCP on pHere, the carriage at 1.5 m)."""
    mech, plan = state
    targets = robtargets(STATE)
    far, extax = targets["pFar"]
    assert extax[0] == 3000
    to_far = one_move(plan, "MoveAbsJ", "jFar")
    assert plan.ext[to_far.rows[0] - 1, 0] == pytest.approx(1.5, abs=1e-6)
    row = end_row(to_far)
    assert plan.ext[row, 0] == pytest.approx(3.0, abs=1e-6)
    got = track_tcp_world(mech, plan, row)[0]
    assert np.linalg.norm(got[:3, 3] - far[:3, 3]) < POS_TOL, (got[:3, 3], far[:3, 3])
    assert turn_between(got[:3, :3], far[:3, :3]) < TURN_TOL
    back = one_move(plan, "MoveL", "pBack")
    row = end_row(back)
    assert plan.ext[row, 0] == pytest.approx(1.5, abs=1e-6)
    got = track_tcp_world(mech, plan, row)[0]
    here = targets["pHere"][0]
    assert np.linalg.norm(got[:3, 3] - here[:3, 3]) < POS_TOL, (got[:3, 3], here[:3, 3])
    assert turn_between(got[:3, :3], here[:3, :3]) < TURN_TOL


# -- 5. JSON and CSV ---------------------------------------------------------------------------
def test_json_moves_carry_the_external_axes(track, track_run):
    """run_program's document: external_axes is {"eax_a": "linear"}, each move's external_axes is
    eax_a at its end row in metres (the fine ones: the robtarget's eax_a), the limits have a row for
    eax_a on the track's J1, and the world TCP it gives for a fine move is the robtarget's."""
    _, plan, _ = track
    out, _ = track_run
    doc = out.doc
    assert out.code == 0 and doc["errors"] == []
    assert doc["external_axes"] == {"eax_a": "linear"}
    assert any(r["axis"] == "eax_a (track J1)" for r in doc["axis_limits"]["axes"])
    targets = robtargets(TRACK)
    assert len(doc["moves"]) == len(plan.moves)
    for said, move in zip(doc["moves"], plan.moves):
        assert set(said["external_axes"]) == {"eax_a"}
        assert said["external_axes"]["eax_a"] == pytest.approx(plan.ext[end_row(move), 0], abs=1e-9)
    carry = next(m for m in doc["moves"] if m["target"] == "pCarry" or m["line"] == line_of(TRACK, "MoveL pCarry,"))
    assert carry["external_axes"]["eax_a"] == pytest.approx(1.7, abs=1e-6)
    assert np.linalg.norm(np.array(carry["tcp_world_m"]) - targets["pCarry"][0][:3, 3]) < POS_TOL
    assert np.linalg.norm(np.array(carry["tcp_m"]) - targets["pCarry"][0][:3, 3]) < POS_TOL  # wobj0: the world


def test_csv_has_eax_a_in_mm_and_reads_back(track, track_run):
    """The CSV's header ends with eax_a, its values are millimetres (200 .. 3200), and
    read_trajectory reads it back with ext_axes ("eax_a",) and ext / 1000 equal to the plan's."""
    mech, plan, _ = track
    _, csv = track_run
    lines = Path(csv).read_text().splitlines()
    header = lines[0].split(",")
    assert header[0] == "time" and header[-1] == "eax_a" and len(header) == 1 + 6 + 1
    values = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    assert len(values) == len(plan.times)
    assert values[:, -1].min() == pytest.approx(0.0, abs=1e-3)  # the carriage at home first
    assert values[:, -1].max() == pytest.approx(3200.0, abs=1e-3)
    traj = read_trajectory(str(csv), mech)
    assert tuple(traj.ext_axes) == ("eax_a",)
    assert traj.ext.shape == (len(plan.times), 1)
    assert np.abs(traj.ext[:, 0] / 1000.0 - plan.ext[:, 0]).max() < 1e-5


# -- 6. axes and units the cell does not have --------------------------------------------------
def test_an_axis_the_cell_lacks_is_ignored_and_a_unit_it_lacks_is_an_error():
    """On the track cell, pWithC's eax_c is ignored with a warning (its move runs, the carriage to
    its eax_a); a work object coordinated with STN9 is an error at its move's line naming STN9."""
    warnings: list[str] = []
    _, plan = program_plan(str(TRACK_CELL), [str(UNKNOWN)], strict=False, warn=warnings.append)
    with_c = one_move(plan, "MoveJ", "pWithC")
    assert with_c.error is None
    assert plan.ext[end_row(with_c), 0] == pytest.approx(0.7, abs=1e-6)
    c_line = line_of(UNKNOWN, "MoveJ pWithC")
    assert any("eax_c" in w for w in warnings), warnings
    stn9_line = line_of(UNKNOWN, "MoveL pOnStn9")
    assert [e.line for e in plan.errors] == [stn9_line], plan.errors
    assert c_line not in {e.line for e in plan.errors}
    assert "STN9" in plan.errors[0].message and Path(plan.errors[0].file).name == UNKNOWN.name
    assert one_move(plan, "MoveL", "pOnStn9").error is not None


# -- 7. the command line -----------------------------------------------------------------------
def cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "rswarp.cli", "program", *args], cwd=ROOT, capture_output=True,
                          text=True, timeout=300)


def test_cli_program_on_the_track_cell_and_on_the_robot_alone():
    """`rswarp program track_cell.toml MODULE` exits 0 with an "extax [mm, deg]" column giving
    eax_a per move; the robot alone exits 1 with `file:line:` errors "out of reach" on stderr."""
    done = cli(str(TRACK_CELL), str(TRACK))
    assert done.returncode == 0, done.stderr
    assert "extax [mm, deg]" in done.stdout
    assert re.search(r"eax_a 1700(\.0)?\b", done.stdout), done.stdout
    alone = cli(str(ROBOT), str(TRACK))
    assert alone.returncode == 1, alone.stdout
    carry = line_of(TRACK, "MoveL pCarry,")
    assert re.search(rf"track_acceptance\.mod:{carry}:.*out of reach", alone.stderr), alone.stderr
    assert "extax [mm, deg]" not in alone.stdout
