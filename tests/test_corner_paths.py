"""Corner paths of zoned linear moves as ABB's controller makes them (the planner's Cartesian corner
paths with look-ahead), on the IRB 2600-12/1.65 through ``rswarp.program``: 100 MoveL of 10 mm in
z10 along a straight line and along an arc keep the programmed 400 mm/s; a right angle in z50 is
passed inside its zone at the programmed speed, tangent-continuous; every sample keeps within the
axis limits the plan reports (the bundled pick and place and palletizer among them); a MoveJ still
takes Ruckig's time; a fine point still stops.

The TCP is tGripper's (200 mm along the flange's z, the tool pointing down), by rswarp's forward
kinematics in float64; its speed is the distance between samples over their time (250 a second).

ABB's documented behaviour (RAPID Reference Manual, "Motion and I/O Principles", section 2:
Positioning during Program Execution, whose corner-path part is the Technical reference manual -
RAPID overview's "Corner paths"; and its data type zonedata), as found, quoted where a test leans
on it:

- zonedata: "A fly-by point means that the programmed position is never attained. Instead, the
  direction of motion is changed before the position is reached." "A corner path (parabola) is
  generated as soon as the edge of the zone is reached." "The zone size cannot be larger than half
  the distance to the closest position (forwards or backwards)."
- 2.2.2 Linear interpolation: "During linear interpolation, the TCP travels along a straight line
  between the start and destination points."
- 2.2.3 Circular interpolation: "As long as all motor torques do not exceed the maximum permitted
  values, the tool will move at the programmed velocity along the arc of the circle. If the torque
  of any of the motors is insufficient, the velocity will automatically be reduced at those parts
  of the circular path where the motor performance is insufficient."
- 2.3.2 Linear interpolation of a position in corner paths: "If different speeds have been
  programmed before or after the corner position, the transition will be smooth and take place
  within the corner path without affecting the actual path."
- 2.3.3 (the orientation zone): the reorientation starts before the corner path, so that "it will
  probably not be necessary to reduce the velocity to perform the reorientation".

No ABB text found gives a corner path its own speed: the programmed one holds through it where
the axes allow it (2.2.3, 2.3.2, 2.3.3), so a test asks 0.9 of it.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

import rswarp
from rswarp.examples import IRB2600, IRB2600_CELL, IRB2600_PROGRAM

from conftest import DATA

RAPID = DATA / "rapid"
TOOL_TCP = np.array([0.0, 0.0, 0.2])  # tGripper's TCP on the flange (m), as its tooldata says
SLACK = 1.02  # a sample may exceed a limit by this much (the limits' own rounding, the differences')


@lru_cache(maxsize=None)
def planned(program: str):
    """(mechanism, plan) of a task on the IRB 2600, planned once per test run."""
    return rswarp.program(str(IRB2600), [program])


@lru_cache(maxsize=None)
def kinematics(mech):
    return rswarp.Kinematics(mech)


def tcp(mech, q: np.ndarray) -> np.ndarray:
    """tGripper's TCP (N, 3) in the world (m) at joint rows ``q``."""
    kin = kinematics(mech)
    link, offset = kin.flange_frame()
    flange = kin.fk64(q)[:, link] @ offset
    if mech.base_frame is not None:
        flange = mech.base_frame.matrix() @ flange
    return flange[:, :3, 3] + flange[:, :3, :3] @ TOOL_TCP


def stretch(program: str, first: int, last: int):
    """(times, q, TCP) of the samples from the start of move ``first`` to the end of move ``last``
    (indices into ``plan.moves``: 0 is the MoveJ to the start), and the mechanism and plan."""
    mech, plan = planned(program)
    t0, t1 = plan.moves[first].start, plan.moves[last].end
    rows = (plan.times >= t0 - 1e-9) & (plan.times <= t1 + 1e-9)
    return plan.times[rows], plan.q[rows], tcp(mech, plan.q[rows]), mech, plan


def speeds(times: np.ndarray, points: np.ndarray) -> np.ndarray:
    """The TCP's speed (m/s) over each interval between samples."""
    return np.linalg.norm(np.diff(points, axis=0), axis=1) / np.diff(times)


def arc_length(points: np.ndarray) -> np.ndarray:
    """The TCP's distance travelled (m) at each sample."""
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])


def wrist_clear(q: np.ndarray) -> None:
    """The wrist stays well away from its singularity (q5 = 0) all along: > 10 deg."""
    assert np.degrees(np.abs(q[:, 4])).min() > 10.0


def middle_speeds(program: str) -> tuple[np.ndarray, float]:
    """The TCP's speeds over the middle 80 % of the path of moves 1 to the last (by distance along
    it: past the first ramp and before the last), and the path's length (m)."""
    times, q, points, _, plan = stretch(program, 1, -1)
    wrist_clear(q)
    assert len(plan.moves) == 101 and all(mv.instruction == "MoveL" for mv in plan.moves[1:])
    s = arc_length(points)
    mid = 0.5 * (s[1:] + s[:-1])
    middle = (mid > 0.1 * s[-1]) & (mid < 0.9 * s[-1])
    return speeds(times, points)[middle], float(s[-1])


def test_a_straight_line_of_100_zoned_moves_keeps_the_programmed_speed():
    """100 collinear MoveL of 10 mm at v400 z10 (``corner_line.mod``, 1 m along y after a MoveJ to
    its start): each zone is cut to 5 mm, half of its move (zonedata: "The zone size cannot be
    larger than half the distance to the closest position"), and the corner path between two
    collinear moves is the line itself. ABB plans the fly-by points as one path: "During linear
    interpolation, the TCP travels along a straight line" at the programmed velocity, and "If
    different speeds have been programmed before or after the corner position, the transition will
    be smooth and take place within the corner path" (RAPID Reference Manual, Motion and I/O
    Principles 2.2.2, 2.3.2): over the middle 80 % of the line (well past the ramps at its ends,
    a few millimetres long) the TCP goes at 400 mm/s within 2 %."""
    middle, length = middle_speeds(str(RAPID / "corner_line.mod"))
    assert length == pytest.approx(1.0, abs=1e-3)  # the samples lie on the line, its whole length
    assert middle.min() >= 0.4 * 0.98 and middle.max() <= 0.4 * 1.02, \
        f"TCP speed over the middle 80 %: {middle.min() * 1e3:.0f} to {middle.max() * 1e3:.0f} mm/s, mean " \
        f"{middle.mean() * 1e3:.0f} mm/s (programmed 400)"


def test_a_straight_line_of_100_zoned_moves_takes_its_length_over_the_speed_and_two_ramps():
    """``corner_line.mod``'s 100 MoveL, from the first one's start to the last one's end (a fine
    point). 1 m at 0.4 m/s is 2.5 s, which the TCP can never beat (v_tcp caps it), plus a ramp in
    and out. A ramp from rest to v at the TCP acceleration a the axes allow, under the jerk j they
    allow, takes v/a + a/j and covers half its time's worth at v, so the two cost v/a + a/j more
    than 2.5 s (a planner without a jerk limit: v/a, 2 % less). a and j are the least of each
    axis's acceleration and jerk (the plan's limits) over its rate along the line (dq/ds) at the
    line's ends. The tool's 3 kg lowers the accelerations by 21 % at most (the JSON's
    acceleration_factor), a few milliseconds on ramps of hundredths of a second: within the 3 %.
    And in any case 2.5 to 2.75 s (10 % over the least)."""
    times, q, points, _, plan = stretch(str(RAPID / "corner_line.mod"), 1, -1)
    s = arc_length(points)
    limits = plan.limits
    ramps = 0.0
    for end in (s < 0.02, s > s[-1] - 0.02):  # the first and the last 20 mm
        rows = np.flatnonzero(end)
        rate = np.abs(q[rows[-1]] - q[rows[0]]) / (s[rows[-1]] - s[rows[0]])  # dq/ds, rad/m
        moving = rate > 1e-6
        a = np.min(limits.acceleration[moving] / rate[moving])
        j = np.min(limits.jerks()[moving] / rate[moving])
        ramps += 0.5 * (0.4 / a + a / j)
    seconds = times[-1] - times[0]
    expected = 1.0 / 0.4 + ramps
    assert 2.5 <= seconds <= 2.75, f"the line takes {seconds:.3f} s"
    assert seconds == pytest.approx(expected, rel=0.03), \
        f"the line takes {seconds:.3f} s, 2.5 s and its ramps {expected:.3f} s"


def test_an_arc_of_100_zoned_moves_keeps_the_programmed_speed():
    """100 MoveL along an arc of a horizontal circle of radius 300 mm, 10 mm of arc apart, at v400
    z10 (``corner_arc.mod``): each corner turns 1.9 deg, inside a zone of 5 mm (half the move). The
    centripetal acceleration at 400 mm/s on 300 mm is 0.53 m/s^2, far below what the axes give, so
    ABB keeps the programmed speed: "As long as all motor torques do not exceed the maximum
    permitted values, the tool will move at the programmed velocity along the arc of the circle"
    (RAPID Reference Manual, Motion and I/O Principles 2.2.3, of MoveC; the corner paths of 2.3.2
    are smooth and leave the speed as programmed). Over the middle 80 % of the arc: 400 mm/s
    within 2 %; and the TCP stays on the circle (the polygon of 10 mm chords is 0.04 mm inside it,
    the corner paths within 5 mm zones inside that)."""
    program = str(RAPID / "corner_arc.mod")
    middle, length = middle_speeds(program)
    assert length == pytest.approx(1.0, abs=2e-3)
    _, _, points, _, _ = stretch(program, 1, -1)
    radius = np.linalg.norm(points[:, :2] - [1.05, 0.0], axis=1)
    assert np.abs(radius - 0.3).max() < 0.001 and np.abs(points[:, 2] - 0.6).max() < 0.001
    assert middle.min() >= 0.4 * 0.98 and middle.max() <= 0.4 * 1.02, \
        f"TCP speed over the middle 80 %: {middle.min() * 1e3:.0f} to {middle.max() * 1e3:.0f} mm/s, mean " \
        f"{middle.mean() * 1e3:.0f} mm/s (programmed 400)"


CORNER = np.array([1.3, -0.2, 0.6])  # corner_right.mod's pCorner (m)


def corner_samples():
    """(times, TCP, its distance to pCorner) over ``corner_right.mod``'s two MoveL, the wrist clear."""
    times, q, points, _, _ = stretch(str(RAPID / "corner_right.mod"), 1, 2)
    wrist_clear(q)
    return times, points, np.linalg.norm(points - CORNER, axis=1)


def test_a_right_angle_in_z50_is_passed_inside_its_zone():
    """MoveL 400 mm along x, then 400 mm along y, the corner pCorner a fly-by point in z50, at v500,
    the end fine (``corner_right.mod``). ABB: "A fly-by point means that the programmed position is
    never attained. Instead, the direction of motion is changed before the position is reached."
    and "A corner path (parabola) is generated as soon as the edge of the zone is reached" (RAPID
    Reference Manual, zonedata). So the TCP passes the corner point closer than 50 mm and never
    through it (a parabola at a right angle in z50 passes 18 mm from it), and it leaves the
    straight legs only inside the zone, entering it once and leaving it once."""
    _, points, distance = corner_samples()
    nearest = distance.min()
    assert 0.001 < nearest < 0.050, f"nearest to the corner {nearest * 1e3:.1f} mm"
    inside = np.flatnonzero(distance < 0.050)
    assert np.array_equal(inside, np.arange(inside[0], inside[-1] + 1))  # in once, out once
    leg = np.minimum(np.hypot(points[:, 1] - CORNER[1], points[:, 2] - CORNER[2]),  # off the line along x
                     np.hypot(points[:, 0] - CORNER[0], points[:, 2] - CORNER[2]))  # off the line along y
    off = leg[distance >= 0.0505].max()
    assert off < 1e-4, f"{off * 1e3:.2f} mm off the programmed lines outside the zone"


def test_a_right_angle_in_z50_keeps_the_programmed_speed_through_its_corner_path():
    """``corner_right.mod``'s corner at v500 in z50. No ABB text found gives a corner path a speed of
    its own: the programmed speed holds where the axes allow it ("If different speeds have been
    programmed before or after the corner position, the transition will be smooth and take place
    within the corner path without affecting the actual path", RAPID Reference Manual, Motion and
    I/O Principles 2.3.2; of the orientation zone, "it will probably not be necessary to reduce the
    velocity", 2.3.3; on a circle, "the tool will move at the programmed velocity" unless a motor's
    torque is short, 2.2.3). A 90 deg parabola in z50 bends at 35 mm at the least: 7 m/s^2 at
    500 mm/s, within what the axes give, so the least TCP speed inside the zone is at least 0.9 of
    500 mm/s."""
    times, points, distance = corner_samples()
    both_inside = (distance[1:] < 0.050) & (distance[:-1] < 0.050)
    least = speeds(times, points)[both_inside].min()
    assert least >= 0.9 * 0.5, f"least TCP speed in the zone {least * 1e3:.0f} mm/s (programmed 500)"


def test_a_right_angle_in_z50_is_tangent_continuous():
    """``corner_right.mod``'s corner: the corner path is a smooth curve ("the direction of motion is
    changed before the position is reached", zonedata; a parabola), so the TCP's velocity never
    jumps from one sample to the next. The sampled acceleration (second differences of the TCP's
    position) from 10 mm before the zone to 10 mm after it stays within v^2 / (0.1 zone) =
    50 m/s^2, the programmed 500 mm/s on a curve of radius a tenth of the zone (5 mm): a kink at
    500 mm/s sampled at 250 a second makes at least 88 m/s^2 (its 0.71 m/s of velocity change split
    over two samples), and a corner path such as ABB's (7 m/s^2 at its apex) never comes near."""
    times, points, distance = corner_samples()
    velocity = np.diff(points, axis=0) / np.diff(times)[:, None]
    acceleration = np.linalg.norm(np.diff(velocity, axis=0), axis=1) / (0.5 * (times[2:] - times[:-2]))
    worst = acceleration[distance[1:-1] < 0.060].max()
    assert worst <= 0.5 ** 2 / (0.1 * 0.050), f"TCP acceleration through the corner up to {worst:.1f} m/s^2"


LIMITED = {"pick_place": IRB2600_PROGRAM, "palletizer cell": IRB2600_CELL,
           "corner_line": RAPID / "corner_line.mod", "corner_arc": RAPID / "corner_arc.mod",
           "corner_right": RAPID / "corner_right.mod", "corner_fast": RAPID / "corner_fast.mod"}


@pytest.mark.parametrize("task", list(LIMITED))
def test_every_sample_keeps_within_the_axis_limits_the_plan_reports(task):
    """Every sample of the trajectory (what ``--csv`` writes) within the limits the plan reports:
    each axis's speed by first differences of ``plan.q`` over ``plan.times``, its acceleration by
    second differences (over the mean of the two intervals: for any motion whose acceleration
    stays within A, the change of two successive mean speeds over that is within A too, whatever
    the spacing), against ``plan.limits`` times 1.02. Those are the limits before the loads scale
    them, and loads only lower them, so the bound is never tighter than what the planner used.
    ABB: "Acceleration is automatically optimised to the max performance of the robot" (RAPID
    Reference Manual, Motion and I/O Principles 2.2.1): at most, never beyond. The bundled pick and
    place (``pick_place.mod``) and palletizer (the cell folder), the line, arc and corner modules
    and an 800 mm MoveL at v7000 (``corner_fast.mod``), where the axes alone decide."""
    _, plan = planned(str(LIMITED[task]))
    times, q, limits = plan.times, plan.q, plan.limits
    dt = np.diff(times)
    assert dt.min() > 0
    rate = np.diff(q, axis=0) / dt[:, None]
    change = np.diff(rate, axis=0) / (0.5 * (dt[1:] + dt[:-1]))[:, None]

    def where(k: int) -> str:
        at = [f"{mv.instruction} at {Path(mv.motion.file).name}:{mv.line}" for mv in plan.moves
              if mv.start - 1e-9 <= times[k] <= mv.end + 1e-9]
        return f"t {times[k]:.3f} s, {' / '.join(at) or 'at rest'}"

    fast = np.abs(rate) / limits.velocity
    k, axis = np.unravel_index(np.argmax(fast), fast.shape)
    assert fast.max() <= SLACK, f"axis {axis + 1} at {fast.max():.2f} of its speed, {where(k)}"
    hard = np.abs(change) / limits.acceleration
    k, axis = np.unravel_index(np.argmax(hard), hard.shape)
    assert hard.max() <= SLACK, f"axis {axis + 1} at {hard.max():.2f} of its acceleration, {where(k + 1)}"


def test_a_joint_move_to_a_stop_point_still_takes_ruckigs_time():
    """The MoveJ at vmax from home to ``corner_fast.mod``'s start, fine, carrying the 3 kg gripper:
    its duration is Ruckig's time-optimal synchronized rest-to-rest time under the limits the JSON
    reports for it (the load's share taken), within 1 % (as ``tests/test_timing_oracles.py`` holds
    over the joint ranges). Corner paths change linear moves, not joint moves."""
    ruckig = pytest.importorskip("ruckig")
    from rswarp.report.program import run_program

    out = run_program(str(IRB2600), [str(RAPID / "corner_fast.mod")])
    assert out.code == 0 and not out.errors, out.errors
    move = out.doc["moves"][0]
    assert move["instruction"] == "MoveJ"
    _, plan = planned(str(RAPID / "corner_fast.mod"))
    own = move["limits"]
    otg, inp, trajectory = ruckig.Ruckig(6), ruckig.InputParameter(6), ruckig.Trajectory(6)
    inp.current_position, inp.target_position = list(plan.q[0]), list(move["joints"])
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = own["velocity"], own["acceleration"], own["jerk"]
    assert otg.calculate(inp, trajectory) == ruckig.Result.Working
    seconds = move["end_s"] - move["start_s"]
    assert seconds == pytest.approx(trajectory.duration, rel=0.01), (seconds, trajectory.duration)


def test_a_fine_point_between_two_lines_stops_there(tmp_path):
    """``corner_right.mod`` with its corner a stop point (z50 swapped for fine): "A stop point means
    that the robot and external axes must reach the specified position (stand still) before
    program execution continues with the next instruction" (RAPID Reference Manual, zonedata). The
    TCP reaches the corner, and at the sample where the first line ends its speed is below
    5 mm/s, from either side: the velocity there of the parabola through it and the next two
    samples on that side (exact for a constant acceleration, so a stop sampled at 250 a second
    reads 0, where the mean speed of its first interval would read a dt / 2)."""
    module = tmp_path / "corner_fine.mod"
    module.write_text((RAPID / "corner_right.mod").read_text().replace("pCorner, v500, z50", "pCorner, v500, fine"))
    times, q, points, _, plan = stretch(str(module), 1, 2)
    wrist_clear(q)
    k = int(np.argmin(np.abs(times - plan.moves[1].end)))  # the sample where the first line ends
    assert np.linalg.norm(points[k] - CORNER) < 1e-4
    for side in (slice(k, k + 3), slice(k - 2, k + 1)):
        fit = np.polyfit(times[side] - times[k], points[side], 2)  # (3, 3): t^2, t, 1 per axis
        speed = np.linalg.norm(fit[1])
        when = "after" if side.start == k else "before"
        assert speed < 0.005, f"TCP speed at the stop point {speed * 1e3:.1f} mm/s ({when})"
