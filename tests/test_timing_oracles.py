"""Move durations held against two independent time-optimal planners (issue 48), on the IRB
2600-12/1.65 with the axis limits that ``rswarp program``'s JSON reports (``axis_limits``: per axis
velocity, acceleration and jerk, SI; the accelerations and jerks times the ``acceleration_factor``
of the load the moves carry, ``loads``), each move's duration its ``end_s - start_s``.

- Joint moves (``MoveAbsJ``, rest to rest, fine points) against Ruckig: ``ruckig.Ruckig(6)``, an
  ``InputParameter`` from the previous move's joints to this one's, velocities and accelerations
  zero at both ends, ``max_velocity`` / ``max_acceleration`` / ``max_jerk`` the JSON's, the default
  (time) synchronization; its ``Trajectory.duration`` is the time-optimal synchronized
  jerk-limited move, and rswarp's is within 1 % of it. The speeddata lets the axes alone decide
  (v_tcp and v_ori far above what the arm can do).
- Linear moves (``MoveL`` v200 to v7000, 25 mm and 800 mm, the wrist bent 55 deg and 5 deg from
  its singularity) against TOPP-RA: the geometric path is the move's joint values at the
  trajectory's samples (``--csv``), their positions only, as the path is the same whatever the
  timing; the path parameter is the TCP's arc length in metres, the TCP by rswarp's forward
  kinematics times the tooldata's frame; ``toppra.SplineInterpolator`` over it, the arc length
  itself a seventh path coordinate so that the TCP cap v_tcp is a velocity limit like an axis's;
  ``JointVelocityConstraint`` and ``JointAccelerationConstraint`` per axis from the JSON (the arc
  length's acceleration left free), ``TOPPRA(..., parametrizer="ParametrizeConstAccel")`` on
  gridpoints every 0.5 mm of the TCP's path (at least 200 intervals; 1 mm and 0.25 mm give the same
  durations within 0.2 %), ``compute_trajectory(0, 0).duration``. rswarp's is no shorter (bar 1 %,
  the two discretizations of one optimum) and within 10 % of it.
"""

from __future__ import annotations

import re
from functools import lru_cache

import numpy as np
import pytest

import rswarp
from rswarp.examples import IRB2600
from rswarp.kinematics.trajectory import read_trajectory
from rswarp.report.program import run_program

ruckig = pytest.importorskip("ruckig")
toppra = pytest.importorskip("toppra")

TOOL_TCP = np.array([0.0, 0.0, 0.2])  # tGripper's TCP on the flange (m), as its tooldata says
GRID_STEP = 0.0005  # m of the TCP's path between TOPP-RA's gridpoints
SLACK = 0.01  # rswarp may be this much shorter than TOPP-RA: the two discretizations of one optimum

AXIS_RANGE = """MODULE AxisRange
  ! Rest-to-rest joint moves over the IRB 2600's axis ranges, each ended at a fine point; the
  ! speeddata leaves the TCP and its orientation free, so the axes alone decide the time.
  CONST speeddata vAxes:=[20000,20000,5000,1000];
  CONST jointtarget jHome:=[[0,0,0,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST jointtarget jFar:=[[170,-90,70,390,115,-390],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST jointtarget jBack:=[[-175,150,-175,-390,-115,390],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST jointtarget jZero:=[[0,0,0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST jointtarget jWork:=[[90,40,-40,30,60,45],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST jointtarget jNudge:=[[88,41,-38,33,58,50],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveAbsJ jHome\\NoEOffs, vAxes, fine, tool0;
    MoveAbsJ jFar\\NoEOffs, vAxes, fine, tool0;
    MoveAbsJ jBack\\NoEOffs, vAxes, fine, tool0;
    MoveAbsJ jZero\\NoEOffs, vAxes, fine, tool0;
    MoveAbsJ jWork\\NoEOffs, vAxes, fine, tool0;
    MoveAbsJ jNudge\\NoEOffs, vAxes, fine, tool0;
    MoveAbsJ jHome\\NoEOffs, vAxes, fine, tool0;
  ENDPROC
ENDMODULE
"""

LINES = """MODULE Lines
  ! Straight lines across the front of the IRB 2600, each from rest to rest: 25 mm and 800 mm with
  ! the gripper pointing down (the wrist bent 55 deg), and with it pointing forward at shoulder
  ! height, where the wrist passes 5 deg from straight (q5 = 0) and axes 4 and 6 turn fast.
  PERS tooldata tGripper:=[TRUE,[[0,0,200],[1,0,0,0]],[5,[0,0,80],[1,0,0,0],0,0,0]];
  CONST robtarget pShortA:=[[900,-12.5,500],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pShortB:=[[900,12.5,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pLongA:=[[900,-400,500],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pLongB:=[[900,400,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pNearA:=[[1230,-12.5,1190],[0.7071068,0,0.7071068,0],[-1,-1,0,1],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pNearB:=[[1230,12.5,1190],[0.7071068,0,0.7071068,0],[0,0,-1,1],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pNearLongA:=[[1230,-400,1190],[0.7071068,0,0.7071068,0],[-1,-1,0,1],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pNearLongB:=[[1230,400,1190],[0.7071068,0,0.7071068,0],[0,0,-1,1],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveJ pShortA, v1000, fine, tGripper;
    MoveL pShortB, v200, fine, tGripper;
    MoveJ pShortA, v1000, fine, tGripper;
    MoveL pShortB, v2000, fine, tGripper;
    MoveJ pShortA, v1000, fine, tGripper;
    MoveL pShortB, v7000, fine, tGripper;
    MoveJ pLongA, v1000, fine, tGripper;
    MoveL pLongB, v500, fine, tGripper;
    MoveJ pLongA, v1000, fine, tGripper;
    MoveL pLongB, v7000, fine, tGripper;
    MoveJ pNearA, v1000, fine, tGripper;
    MoveL pNearB, v200, fine, tGripper;
    MoveJ pNearA, v1000, fine, tGripper;
    MoveL pNearB, v2000, fine, tGripper;
    MoveJ pNearLongA, v1000, fine, tGripper;
    MoveL pNearLongB, v200, fine, tGripper;
    MoveJ pNearLongA, v1000, fine, tGripper;
    MoveL pNearLongB, v2000, fine, tGripper;
  ENDPROC
ENDMODULE
"""

# each MoveL of LINES in order: its length (m), the least |q5| along it (deg, near or far from the singularity)
LINE_CASES = [("short bent v200", 0.025, 50), ("short bent v2000", 0.025, 50), ("short bent v7000", 0.025, 50),
              ("long bent v500", 0.8, 50), ("long bent v7000", 0.8, 50),
              ("short near v200", 0.025, 5), ("short near v2000", 0.025, 5),
              ("long near v200", 0.8, 5), ("long near v2000", 0.8, 5)]


@lru_cache(maxsize=None)
def kin():
    return rswarp.Kinematics(rswarp.load(IRB2600))


def run(folder, name: str, text: str, csv: bool = False):
    """``rswarp program``'s JSON for the module ``text`` on the IRB 2600, and with ``csv`` its
    trajectory as written to ``--csv`` and read back (SI)."""
    path = folder / f"{name}.mod"
    path.write_text(text)
    trajectory = folder / f"{name}.csv"
    out = run_program(str(IRB2600), [str(path)], csv=str(trajectory) if csv else None)
    assert out.code == 0 and not out.errors, out.errors
    return out.doc, (read_trajectory(trajectory, kin().mech) if csv else None)


def move_limits(doc: dict) -> dict:
    """The per-axis limits the JSON reports for the module's moves, SI: ``axis_limits``, with the
    accelerations and jerks scaled by the ``acceleration_factor`` of the load the moves carry (each
    module here moves with one tool, so all its moves carry one load, or none with tool0)."""
    limits = doc["axis_limits"]
    out = {"velocity": limits["velocity"], "acceleration": limits["acceleration"], "jerk": limits.get("jerk")}
    loads = doc.get("loads") or []
    assert len(loads) <= 1 and all(load["moves"] == len(doc["moves"]) for load in loads), loads
    for load in loads:
        factor = np.asarray(load["acceleration_factor"], float)
        out["acceleration"] = list(factor * out["acceleration"])
        out["jerk"] = None if out["jerk"] is None else list(factor * out["jerk"])
    return out


def ruckig_duration(start, end, limits: dict) -> float:
    """The time-optimal rest-to-rest move from ``start`` to ``end`` (rad), all axes synchronized, under
    the JSON's per-axis velocity, acceleration and jerk limits: Ruckig's."""
    otg, inp, out = ruckig.Ruckig(6), ruckig.InputParameter(6), ruckig.Trajectory(6)
    inp.current_position, inp.target_position = list(start), list(end)
    inp.current_velocity = inp.current_acceleration = inp.target_velocity = inp.target_acceleration = [0.0] * 6
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = limits["velocity"], limits["acceleration"], limits["jerk"]
    assert otg.calculate(inp, out) == ruckig.Result.Working
    return out.duration


def tcp_arc_length(q: np.ndarray) -> np.ndarray:
    """The TCP's distance travelled (m) at each row of ``q``: rswarp's forward kinematics (float64) to
    the flange, then tGripper's TCP on it."""
    link, offset = kin().flange_frame()
    flange = kin().fk64(q)[:, link] @ offset
    tcp = flange[:, :3, 3] + flange[:, :3, :3] @ TOOL_TCP
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(tcp, axis=0), axis=1))])


def toppra_duration(q: np.ndarray, limits: dict, v_tcp: float) -> float:
    """The time-optimal traversal of the joint path through ``q`` (rows in path order) from rest to rest
    under the per-axis velocity and acceleration limits and the TCP capped at ``v_tcp`` (m/s): TOPP-RA's,
    the path parameter the TCP's arc length, which is also a seventh coordinate limited to ``v_tcp``."""
    s = tcp_arc_length(q)
    keep = np.concatenate([[True], np.diff(s) > 1e-9])  # a sample that did not move adds no path
    s, q = s[keep], q[keep]
    path = toppra.SplineInterpolator(s, np.column_stack([q, s]))
    velocity = np.append(limits["velocity"], v_tcp)
    acceleration = np.append(limits["acceleration"], 1e6)  # the arc length's acceleration: free
    constraints = [toppra.constraint.JointVelocityConstraint(np.column_stack([-velocity, velocity])),
                   toppra.constraint.JointAccelerationConstraint(np.column_stack([-acceleration, acceleration]))]
    grid = np.linspace(0.0, s[-1], max(201, int(np.ceil(s[-1] / GRID_STEP)) + 1))
    solver = toppra.algorithm.TOPPRA(constraints, path, gridpoints=grid, parametrizer="ParametrizeConstAccel")
    trajectory = solver.compute_trajectory(0, 0)
    assert trajectory is not None, "TOPP-RA found no parametrization"
    return float(trajectory.duration)


@pytest.fixture(scope="module")
def lines(tmp_path_factory):
    """LINES run once: per MoveL its duration, TOPP-RA's, its length (m) and the least |q5| (deg)."""
    doc, trajectory = run(tmp_path_factory.mktemp("lines"), "lines", LINES, csv=True)
    source, limits, out = LINES.splitlines(), move_limits(doc), {}
    moves = [m for m in doc["moves"] if m["instruction"] == "MoveL"]
    assert len(moves) == len(LINE_CASES)
    for (name, _, _), m in zip(LINE_CASES, moves):
        v_tcp = int(re.search(r", v(\d+),", source[m["line"] - 1]).group(1)) / 1000.0
        rows = (trajectory.times >= m["start_s"] - 1e-5) & (trajectory.times <= m["end_s"] + 1e-5)
        q = trajectory.q[rows]
        out[name] = {"ours": m["end_s"] - m["start_s"], "topp": toppra_duration(q, limits, v_tcp),
                     "length": tcp_arc_length(q)[-1], "q5": np.degrees(np.abs(q[:, 4]).min()), "v_tcp": v_tcp}
    return out


def test_joint_moves_over_the_axis_ranges_take_ruckigs_time(tmp_path):
    """Seven MoveAbsJ from rest to rest (fine), six of them moving: swings over nearly every axis's
    whole range, a return to zero, and a nudge of a few degrees where jerk shapes the whole move.
    Each takes Ruckig's time-optimal synchronized time under the JSON's limits, within 1 %."""
    doc, _ = run(tmp_path, "axis_range", AXIS_RANGE)
    limits = move_limits(doc)
    assert limits["jerk"] is not None and len(limits["jerk"]) == 6, "the JSON's axis_limits report no jerk"
    moves = doc["moves"]
    assert len(moves) == 7 and all(m["kind"] == "absolute" for m in moves)
    for before, m in zip(moves, moves[1:]):
        ours, oracle = m["end_s"] - m["start_s"], ruckig_duration(before["joints"], m["joints"], limits)
        assert ours == pytest.approx(oracle, rel=0.01), f"line {m['line']}: {ours:.4f} s, Ruckig {oracle:.4f} s"


@pytest.mark.parametrize("name", [case[0] for case in LINE_CASES])
def test_a_line_takes_no_less_than_topp_ras_time_and_at_most_a_tenth_more(lines, name):
    """A MoveL's duration against TOPP-RA's time-optimal one along the same path under the same limits
    (v_tcp from its speeddata): no shorter (bar 1 %), within 10 %."""
    length, near = next((length, q5) for case, length, q5 in LINE_CASES if case == name)
    line = lines[name]
    assert line["length"] == pytest.approx(length, abs=1e-4)  # the samples lie on the line, its whole length
    assert (line["q5"] < near + 1) if near < 10 else (line["q5"] > near)  # near to or far from q5 = 0
    ratio = line["ours"] / line["topp"]
    assert 1 - SLACK <= ratio <= 1.10, f"{name}: {line['ours']:.4f} s, TOPP-RA {line['topp']:.4f} s ({ratio - 1:+.1%})"


def test_a_v200_and_a_v2000_short_line_differ_as_the_limits_say(lines):
    """25 mm at v200 and at v2000 (the wrist bent): at v200 the TCP cap decides most of the move, at
    v2000 the axes' accelerations do (TOPP-RA's v2000 and v7000 times are one), so the two differ
    by what the limits say, not by a fixed ramp: each within 10 % of TOPP-RA (no shorter, bar 1 %),
    the slower one slower, and their difference TOPP-RA's within what those 10 % allow (a fixed
    0.25 s ramp on each would make it about 0.24 s, five times TOPP-RA's)."""
    slow, fast, top = lines["short bent v200"], lines["short bent v2000"], lines["short bent v7000"]
    assert fast["topp"] == pytest.approx(top["topp"], rel=1e-3)  # at v2000 the cap does not bind
    assert slow["topp"] > 1.2 * fast["topp"]  # at v200 it does
    for line in (slow, fast):
        assert 1 - SLACK <= line["ours"] / line["topp"] <= 1.10, (line["ours"], line["topp"])
    assert slow["ours"] > fast["ours"]
    difference, oracle = slow["ours"] - fast["ours"], slow["topp"] - fast["topp"]
    assert difference == pytest.approx(oracle, abs=0.1 * (slow["topp"] + fast["topp"])), (difference, oracle)
    assert slow["ours"] / fast["ours"] == pytest.approx(slow["topp"] / fast["topp"], rel=0.1)
