"""Robot data and the timing model: axis speeds from the bundled robot-data file, from a URDF and a
joint_limits.yaml in ROS-Industrial's and MoveIt's layouts; a 170 deg swing of axis 1 timed as
Ruckig times it under the limits used; zones blended (a square of
MoveL in z50 against fine, its corners passed within the zone, a zone larger than half its move
cut to half); ABB's zonedata table; a path shorter than its turn timed by v_ori, and one cut at
its second probe in a fraction of a second; moves timed together as each alone."""

from __future__ import annotations

import shutil
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

from rswarp.cli import main
from rswarp.errors import RsxmlError
from rswarp.examples import IRB2600
from rswarp.kinematics.kinematics import Kinematics
from rswarp.motion.plan import program_plan
from rswarp.rapid.predefined import ZONES
from rswarp.rsxml.documents import load_mechanism
from rswarp.rsxml.robot_data import axis_limits, read_limits

from conftest import DATA

RAPID, LIMITS = DATA / "rapid", DATA / "limits"
ROS_VELOCITY = np.array([3.054, 3.054, 3.054, 6.283, 6.283, 8.727])  # rad/s, ROS-Industrial's URDF


@lru_cache(maxsize=None)
def mech():
    return load_mechanism(IRB2600)[0]


def plain_robot(tmp_path: Path) -> Path:
    """The IRB 2600's RSXML alone in a folder: no robot-data file beside it."""
    target = tmp_path / "robot" / IRB2600.name
    target.parent.mkdir()
    shutil.copy(IRB2600, target)
    return target


def swing(robot, limits=None) -> tuple[float, dict]:
    _, p = program_plan(str(robot), [str(RAPID / "j1_170.mod")], limits=limits)
    return p.moves[1].end - p.moves[1].start, p.limits


def ruckig_time(q0, q1, limits) -> float:
    """Ruckig's synchronized rest-to-rest duration under ``limits`` (the oracle of joint moves)."""
    ruckig = pytest.importorskip("ruckig")
    n = len(q0)
    inp, out = ruckig.InputParameter(n), ruckig.Trajectory(n)
    inp.current_position, inp.target_position = list(q0), list(q1)
    inp.max_velocity, inp.max_acceleration = list(limits.velocity), list(limits.acceleration)
    inp.max_jerk = list(limits.jerks())
    ruckig.Ruckig(n).calculate(inp, out)
    return out.duration


SWING = np.radians([[-85, 0, 0, 0, 30, 0], [85, 0, 0, 0, 30, 0]])  # j1_170.mod's two targets


def test_the_bundled_data_gives_the_datasheet_speeds_and_a_170_degree_swing_ruckigs_time():
    limits = axis_limits(mech())
    assert np.allclose(limits.velocity, ROS_VELOCITY, rtol=1e-3) and not limits.assumed
    seconds, used = swing(IRB2600)
    assert seconds == pytest.approx(ruckig_time(*SWING, used), rel=1e-6)
    # 170 deg at 175 deg/s and the ramps the axis's acceleration and jerk take, never less
    assert 170 / 175 < seconds < 170 / 175 + 2 * 3.054 / used.acceleration[0] + 0.1
    assert seconds == pytest.approx(1.24, abs=0.005)  # docs/program.md's figure
    assert "175-500 deg/s from IRB2600_12_165.robot.toml" in used.summary()


def test_a_plain_rsxml_says_its_speeds_are_assumed_and_limits_files_set_them(tmp_path):
    robot = plain_robot(tmp_path)
    seconds, used = swing(robot)
    assert used.assumed and "assumed 90 deg/s" in used.summary()
    assert seconds == pytest.approx(ruckig_time(*SWING, used), rel=1e-6) and seconds > 170 / 90
    urdf_seconds, used = swing(robot, str(LIMITS / "irb2600_12_165.urdf"))
    assert urdf_seconds == pytest.approx(ruckig_time(*SWING, used), rel=1e-6) and 0.97 <= urdf_seconds <= 1.6
    assert "irb2600_12_165.urdf" in used.summary()
    # the yaml gives axis 1 5 rad/s^2: 0.61 s to reach 3.054 rad/s, and the jerk's ramps on top
    yaml_seconds, used = swing(robot, str(LIMITS / "joint_limits.yaml"))
    assert yaml_seconds == pytest.approx(ruckig_time(*SWING, used), rel=1e-6)
    assert yaml_seconds > np.radians(170) / 3.054 + 3.054 / 5.0
    assert used.acceleration[0] == pytest.approx(5.0) and used.acceleration[3] == pytest.approx(6.283 / 0.25)


def test_limits_files_are_matched_by_name_or_order_and_bad_ones_said_at_their_line(tmp_path):
    by_name = read_limits(str(LIMITS / "irb2600_12_165.urdf"), mech())
    assert np.allclose(by_name.velocity, ROS_VELOCITY)
    swapped = (LIMITS / "irb2600_12_165.urdf").read_text().replace('velocity="8.727"', 'velocity="-1"')
    bad = tmp_path / "bad.urdf"
    bad.write_text(swapped)
    with pytest.raises(RsxmlError) as exc:
        read_limits(str(bad), mech())
    assert exc.value.line == 53 and "velocity" in exc.value.message
    five = tmp_path / "five.yaml"
    five.write_text("joint_limits:\n" + "".join(f"  a{k}:\n    has_velocity_limits: true\n    max_velocity: 1.0\n"
                                                 for k in range(5)))
    with pytest.raises(RsxmlError, match="5 axes for 6 active joints"):
        read_limits(str(five), mech())
    assert main(["program", str(IRB2600), str(RAPID / "j1_170.mod"), "--limits", str(five)]) == 1


def test_zones_blend_a_square_faster_than_fine_passing_each_corner_inside_its_zone(tmp_path):
    square = (RAPID / "zone_square.mod").read_text()
    fine = tmp_path / "fine_square.mod"
    fine.write_text(square.replace("z50", "fine"))
    _, zoned = program_plan(str(IRB2600), [str(RAPID / "zone_square.mod")])
    _, stopped = program_plan(str(IRB2600), [str(fine)])
    assert zoned.times[-1] < stopped.times[-1] - 0.1  # three corners not stopped at
    assert (zoned.times[-1], stopped.times[-1]) == pytest.approx((3.79, 4.05), abs=0.005)  # docs/program.md
    kin = Kinematics(mech())
    link, m = kin.flange_frame()
    tcp = (kin.fk64(zoned.q)[:, link] @ m)[:, :3, 3]
    for corner in [(1.0, 0.2, 0.7), (1.4, 0.2, 0.7), (1.4, -0.2, 0.7)]:
        nearest = np.linalg.norm(tcp - corner, axis=1).min()
        assert 0.001 < nearest < 0.050  # inside z50, never touching the point
        assert nearest == pytest.approx(0.017, abs=0.001)  # docs/program.md's 17 mm
    speed = np.linalg.norm(np.diff(tcp, axis=0), axis=1) / np.diff(zoned.times)
    corners = [mv.end for mv in zoned.moves[1:4]]
    at = [int(np.searchsorted(zoned.times, t)) for t in corners]
    assert min(speed[k] for k in at) > 0.495  # v500 kept through each corner (ABB's corner path)
    rate = np.abs(np.diff(zoned.q, axis=0)) / np.diff(zoned.times)[:, None]
    assert (rate <= axis_limits(mech()).velocity * 1.01).all()


def test_zonedata_is_abbs_table():
    """RAPID reference manual, zonedata's predefined data: pzone_tcp, pzone_ori (mm), zone_ori (deg)."""
    table = {"z0": (0.3, 0.3, 0.03), "z1": (1, 1, 0.1), "z5": (5, 8, 0.8), "z10": (10, 15, 1.5),
             "z15": (15, 23, 2.3), "z20": (20, 30, 3.0), "z30": (30, 45, 4.5), "z40": (40, 60, 6.0),
             "z50": (50, 75, 7.5), "z60": (60, 90, 9.0), "z80": (80, 120, 12), "z100": (100, 150, 15),
             "z150": (150, 225, 23), "z200": (200, 300, 30)}
    assert sorted(ZONES) == sorted(int(name[1:]) for name in table)
    for name, (tcp, ori, angle) in table.items():
        pzone_tcp, pzone_ori, _, zone_ori, *_ = ZONES[int(name[1:])]
        assert (pzone_tcp, pzone_ori, zone_ori) == pytest.approx((tcp, ori, angle))


def test_the_exported_irb2600_has_the_datasheet_mass_and_ros_industrials_speeds(tmp_path):
    """ABB's product specification: 272 kg; ROS-Industrial's URDF: the velocity limits."""
    from lxml import etree

    from rswarp.report.exports import run_export

    out = run_export(str(IRB2600), str(tmp_path / "irb.urdf"))
    assert out.doc["total_mass"] == pytest.approx(272.0, rel=0.02)
    assert "IRB2600_12_165.robot.toml" in out.text and "175-500 deg/s" in out.doc["axis_limits"]
    root = etree.parse(str(tmp_path / "irb.urdf")).getroot()
    velocity = [float(j.find("limit").get("velocity")) for j in root.iter("joint") if j.get("type") == "revolute"]
    assert np.allclose(velocity, ROS_VELOCITY, rtol=0.01)
    plain = run_export(str(plain_robot(tmp_path)), str(tmp_path / "plain.urdf"), limits=str(LIMITS / "joint_limits.yaml"))
    assert "joint_limits.yaml" in plain.doc["axis_limits"] and "from IRB2600" not in plain.text


def test_a_move_shorter_than_its_turn_is_timed_by_its_reorientation():
    """The TCP moves 0.014 mm while the tool turns (``reorient.mod``): v_ori decides, as on the
    controller (the slower of the TCP's travel at v_tcp and the turn at v_ori). Axis 6 turns the
    tool: 10 deg at v100's 500 deg/s is at least what axis 6 takes to turn 10 deg at its own
    speed and acceleration (its top speed is 500 deg/s too: a triangle, 2 sqrt(d / a)); 90 deg at
    30 deg/s is 3 s of turning plus a ramp the axes' accelerations make short; a move to where the
    TCP is takes none."""
    _, p = program_plan(str(IRB2600), [str(RAPID / "reorient.mod")])
    small, quarter, still = (mv.end - mv.start for mv in p.moves[1:4])
    a6 = p.limits.acceleration[5]
    assert 2 * np.sqrt(np.radians(10) / a6) <= small < 2 * np.sqrt(np.radians(10) / a6) * 1.1
    assert 3.0 < quarter < 3.0 + 2 * np.radians(30) / a6 + 0.01
    assert (small, quarter) == pytest.approx((0.14, 3.02), abs=0.005)  # docs/program.md's figures
    assert still == 0.0
    kin = Kinematics(mech())
    link, m = kin.flange_frame()
    tcp = kin.fk64(p.q)[:, link] @ m
    rows = slice(*p.moves[2].rows)
    turn = np.degrees(np.arccos(np.clip(tcp[rows, 0, 0] * tcp[rows.stop - 1, 0, 0] + tcp[rows, 1, 0] *
                                        tcp[rows.stop - 1, 1, 0], -1, 1)))
    rate = np.abs(np.diff(turn)) / np.diff(p.times[rows])
    assert rate.max() <= 30 * 1.01  # v_ori holds all the way


def test_a_path_cut_at_its_second_probe_speeds_up_and_slows_down_between_them():
    """A MoveL 0.014 mm long turning 179 deg, axis 5 leaving its limit at the second probe
    (``reorient_cut.mod``): the move stops there in a fraction of a second with its finding (two
    probes both at rest once made it 6.4e9 s)."""
    _, p = program_plan(str(IRB2600), [str(RAPID / "reorient_cut.mod")])
    mv = p.moves[1]
    assert 0.0 < mv.end - mv.start < 0.2
    assert [f.kind for f in mv.findings] == ["path"] and "limit" in mv.findings[0].text


def test_a_zone_larger_than_half_its_move_is_cut_to_half(tmp_path):
    """z200 at the corner of two 100 mm MoveL (``zone_half.mod``) blends as z50, half of either
    move, as the controller cuts it; z40 is smaller than half and blends later."""
    text = (RAPID / "zone_half.mod").read_text()
    plans = {}
    for zone in ("z200", "z50", "z40"):
        path = tmp_path / f"{zone}.mod"
        path.write_text(text.replace("z200", zone))
        plans[zone] = program_plan(str(IRB2600), [str(path)])[1]
    assert [mv.end for mv in plans["z200"].moves] == [mv.end for mv in plans["z50"].moves]
    assert np.array_equal(plans["z200"].q, plans["z50"].q)
    assert plans["z200"].moves[1].end < plans["z40"].moves[1].end
    kin = Kinematics(mech())
    link, m = kin.flange_frame()
    p = plans["z200"]
    switch = kin.fk64(p.q[p.moves[1].rows[1] - 1][None])[:, link] @ m  # where the next move takes over
    corner = np.array([1.0, 0.05, 0.7])
    # the middle of a right angle's corner curve: the point and the two moves' z / 2 blended half way
    assert np.linalg.norm(switch[0, :3, 3] - corner) == pytest.approx(0.050 * np.sqrt(2) / 4, abs=2e-4)


@pytest.mark.parametrize("task", ["zone_square.mod", "time_arg.mod", "real/palletizer.mod", "real/welding.mod"])
def test_moves_timed_together_are_timed_as_each_alone(task, monkeypatch):
    """The batch (``timing_batch``, ``zone_batch``) times, samples and blends every move to the bit
    as the one-move functions do (``timing.path_move``, ``joint_move``, ``zones.overlap``, ``blend``),
    which time a move past the batch's samples."""
    from rswarp.motion import timing_batch

    together = program_plan(str(IRB2600), [str(RAPID / task)], strict=False)[1]
    monkeypatch.setattr(timing_batch, "BATCH_SAMPLES", 0)
    alone = program_plan(str(IRB2600), [str(RAPID / task)], strict=False)[1]
    assert np.array_equal(together.times, alone.times) and np.array_equal(together.q, alone.q)
    assert [(mv.start, mv.end, mv.rows) for mv in together.moves] == [(mv.start, mv.end, mv.rows) for mv in alone.moves]


def test_a_joint_moves_zone_keeps_its_geometry(tmp_path):
    """Two MoveJ at a corner (``joint_zone.mod``): the first slows down over its zone, so it hands
    over to the second where the TCP comes within the zone of the corner (z50: 40 to 50 mm from
    it, z10: 8 to 10 mm), the bigger zone sooner, and neither touches the corner; fine stops there."""
    kin = Kinematics(mech())
    link, m = kin.flange_frame()
    corner = np.array([1.0, 0.1, 0.7])
    ends = {}
    for zone, (lo, hi) in {"z50": (0.040, 0.0501), "z10": (0.008, 0.0101), "fine": (0.0, 1e-9)}.items():
        path = tmp_path / f"{zone}.mod"
        path.write_text((RAPID / "joint_zone.mod").read_text().replace("pB, v1000, z50", f"pB, v1000, {zone}"))
        p = program_plan(str(IRB2600), [str(path)])[1]
        mv = p.moves[1]
        switch = (kin.fk64(p.q[mv.rows[1] - 1][None])[:, link] @ m)[0, :3, 3]
        assert lo <= np.linalg.norm(switch - corner) <= hi, zone
        ends[zone] = mv.end
    assert ends["z50"] < ends["z10"] < ends["fine"]


@pytest.mark.parametrize("task", ["zone_slow_next.mod", "zone_square.mod", "joint_zone.mod", "pick_place"])
def test_a_zone_never_makes_a_task_slower_than_fine(task, tmp_path):
    """Every zone of a task swapped for fine: the task takes longer (a slow move after a fast one
    in a zone once took 0.7 s more than after a stop)."""
    import re

    from rswarp.examples import IRB2600_PROGRAM

    source = IRB2600_PROGRAM if task == "pick_place" else RAPID / task
    fine = tmp_path / "fine.mod"
    fine.write_text(re.sub(r"\bz\d+\b", "fine", source.read_text()))
    zoned = program_plan(str(IRB2600), [str(source)])[1]
    stopped = program_plan(str(IRB2600), [str(fine)])[1]
    assert zoned.times[-1] < stopped.times[-1]


def test_a_moves_own_limits_in_the_json_recompute_its_time(tmp_path):
    """A MoveAbsJ with a 12 kg tool under AccSet 50, 100: its record gives the limits it was timed
    under (the robot's lowered by the load and halved), and it takes Ruckig's time under them."""
    from rswarp.report.program import run_program

    module = tmp_path / "loaded.mod"
    module.write_text("""MODULE Loaded
  PERS tooldata tHeavy:=[TRUE,[[0,0,200],[1,0,0,0]],[12,[0,0,100],[1,0,0,0],0,0,0]];
  CONST jointtarget jA:=[[0,0,0,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST jointtarget jB:=[[90,20,-10,45,60,90],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    AccSet 50, 100;
    MoveAbsJ jA, vmax, fine, tHeavy;
    MoveAbsJ jB, vmax, fine, tHeavy;
  ENDPROC
ENDMODULE
""")
    doc = run_program(str(IRB2600), [str(module)]).doc
    move = doc["moves"][1]
    own = {k: np.array(v) for k, v in move["limits"].items()}
    assert np.all(own["acceleration"] < 0.5 * np.array(doc["axis_limits"]["acceleration"]) + 1e-12)
    used = type("Limits", (), {"velocity": own["velocity"], "acceleration": own["acceleration"],
                               "jerks": lambda self: own["jerk"]})()
    q0, q1 = np.radians([0, 0, 0, 0, 30, 0]), np.radians([90, 20, -10, 45, 60, 90])
    assert move["end_s"] - move["start_s"] == pytest.approx(ruckig_time(q0, q1, used), rel=1e-6)
