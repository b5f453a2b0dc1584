"""A load lowers the accelerations (issue 48, docs/payload-timing.md): each axis's by
J_arm / (J_arm + J_load) about it at home, the arm's inertias the exports' (``export.physics``);
where loads come from (the tool's tload, GripLoad, ``--payload``) and how the program run reports
them."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from generated import mechanism

from rswarp import examples
from rswarp.cli import main
from rswarp.export.physics import robot_physics
from rswarp.geometry import DEFAULT_DENSITY
from rswarp.geometry.inertia import combined as _combined
from rswarp.motion.payload import NO_MASSES, LoadFactors, load_factors, load_scale
from rswarp.motion.plan import program_plan
from rswarp.rapid import data as rd
from rswarp.rapid.interpret import Interpreter
from rswarp.rapid.task import load_task
from rswarp.report.exports import data_physics
from rswarp.report.program import run_program
from rswarp.rsxml.documents import load_mechanism
from rswarp.rsxml.robot_data import Payload
from rswarp.transforms import matrix_quat

ROBOT = str(examples.IRB2600)
PICK_PLACE = str(examples.IRB2600.parent / "pick_place.mod")
SIDE = 0.1  # m: the test robot's box edge
BOX_Z = 0.3  # m: the box's centre above the joint's axis (x through the origin)
FLANGE_Z = 0.01  # m: the flange above the axis


@pytest.fixture
def box_robot(tmp_path):
    """One joint about x through the origin; its link a 100 mm box 300 mm above the axis; a flange
    10 mm above the axis, its axes the world's."""
    box = trimesh.creation.box((100, 100, 100), trimesh.transformations.translation_matrix((0, 0, 1000 * BOX_Z)))
    box.export(tmp_path / "L1.stl")
    (tmp_path / "box.rsxml").write_text(mechanism(1, part_source="L1.SAT"))
    return load_mechanism(str(tmp_path / "box.rsxml"))[0]


@pytest.fixture(scope="module")
def irb2600():
    return load_mechanism(ROBOT)[0]


def test_the_factor_is_the_arms_inertia_over_it_and_the_loads_computed_by_hand(box_robot):
    factors = LoadFactors(box_robot)
    mass = DEFAULT_DENSITY * SIDE ** 3
    armature = robot_physics(box_robot).joints["J0"].armature
    by_hand = mass * (2 * SIDE ** 2) / 12 + mass * BOX_Z ** 2 + armature  # the box about x, parallel axis
    assert factors.arm == pytest.approx([by_hand], rel=1e-6)
    point = Payload(2.0, (0.0, 0.0, 0.1))  # 100 mm out of the flange: 110 mm from the axis
    assert factors(point) == pytest.approx([by_hand / (by_hand + 2.0 * 0.11 ** 2)], rel=1e-9)
    own = Payload(2.0, (0.0, 0.0, 0.1), (0.3, 0.0, 0.0))  # its own 0.3 kg m² about the flange's x: the axis
    assert factors(own) == pytest.approx([by_hand / (by_hand + 2.0 * 0.11 ** 2 + 0.3)], rel=1e-9)
    turned = Payload(2.0, (0.0, 0.0, 0.1), (0.3, 0.0, 0.0), (0.7071068, 0.0, 0.0, 0.7071068))  # that axis on y
    assert factors(turned) == pytest.approx(factors(point), rel=1e-6)


def test_no_load_is_all_ones_and_builds_nothing(irb2600):
    factors = LoadFactors(irb2600)
    load0 = rd.Load(0.001, (0.0, 0.0, 0.001), (0.0, 0.0, 0.0))  # load0 and tool0's tload: the controller's none
    for loads in ((), (None,), (Payload(0.0),), (load0, None, Payload(0.0, (0.0, 0.0, 0.5)))):
        assert np.array_equal(factors(*loads), np.ones(6))
    assert factors._arm is False  # no mesh read for a task that carries nothing


def test_factors_fall_with_mass_and_the_point_mass_on_axis_6_leaves_it(irb2600):
    factors = load_factors(irb2600)
    assert load_factors(irb2600) is factors  # once per robot
    six, twelve = (factors(Payload(kg, (0.0, 0.0, 0.1))) for kg in (6.0, 12.0))
    assert np.all(twelve[:5] < six[:5]) and np.all(six[:5] < 1.0)
    assert six[5] == twelve[5] == pytest.approx(1.0)  # on axis 6's axis: no lever, no inertia of its own
    spinning = factors(Payload(6.0, (0.0, 0.0, 0.1), (0.0, 0.0, 0.05)))  # 0.05 kg m² about the flange's z
    assert spinning[5] == pytest.approx(factors.arm[5] / (factors.arm[5] + 0.05))
    assert not twelve.flags.writeable


def test_the_arm_is_what_the_exports_simulate(irb2600):
    exported = robot_physics(irb2600, data_physics(ROBOT, irb2600))  # the robot data's 272 kg
    assert load_factors(irb2600).arm == pytest.approx([j.inertia for j in exported.joints.values()])


def test_loads_carried_together_are_one_body(irb2600):
    factors = load_factors(irb2600)
    a, b = Payload(4.0, (0.05, 0.0, 0.1)), Payload(8.0, (0.0, -0.1, 0.2), (0.02, 0.03, 0.01))
    mass, cog, inertia = _combined((a.mass, a.cog, a.inertia_matrix()), (b.mass, b.cog, b.inertia_matrix()))
    moments, axes = np.linalg.eigh(inertia)
    axes[:, 2] *= np.sign(np.linalg.det(axes))  # a rotation
    one = Payload(mass, tuple(cog), tuple(moments), matrix_quat(axes))
    assert factors(a, b) == pytest.approx(factors(one), rel=1e-9)
    tool_load, grip = rd.Load(4.0, (0.05, 0.0, 0.1), (0.0, 0.0, 0.0)), rd.Load(8.0, b.cog, b.inertia)
    assert load_scale(irb2600)(tool_load, grip) == pytest.approx(factors(a, b))
    assert load_scale(irb2600, Payload(8.0, b.cog, b.inertia))(tool_load, None) == pytest.approx(factors(a, b))


def test_two_loads_of_equal_value_weigh_twice(irb2600):
    """A payload equal to the tool's load is a second body of that mass, not the same one: the pair
    is the load of twice the mass at the same centre of gravity."""
    factors = load_factors(irb2600)
    a = Payload(3.0, (0.0, 0.0, 0.08))
    assert factors(a, a) == pytest.approx(factors(Payload(6.0, (0.0, 0.0, 0.08))), rel=1e-9)
    assert np.all(factors(a, a)[:5] < factors(a)[:5])  # axis 6 carries a point mass on its axis: 1 both


def test_a_robot_without_meshes_keeps_its_timing_and_says_why(tmp_path):
    (tmp_path / "bare.rsxml").write_text(mechanism(2))
    factors = LoadFactors(load_mechanism(str(tmp_path / "bare.rsxml"))[0])
    assert np.array_equal(factors(Payload(12.0, (0.0, 0.0, 0.1))), np.ones(2))
    assert factors.warning.endswith(NO_MASSES) and "\n" not in factors.warning


GRIP = """MODULE M
  PERS tooldata tG := [TRUE,[[0,0,200],[0.7071068,0,0.7071068,0]],[3,[0,0,80],[1,0,0,0],0,0,0]];
  PERS tooldata tStand := [FALSE,[[900,0,400],[1,0,0,0]],[2,[0,0,50],[1,0,0,0],0,0,0]];
  PERS wobjdata wHeld := [TRUE,TRUE,"",[[0,0,100],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  PERS loaddata piece1 := [5,[0,0,50],[1,0,0,0],0.1,0,0];
  CONST robtarget p := [[500,0,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveL p, v100, fine, tG;
    GripLoad piece1;
    MoveL p, v100, fine, tG;
    MoveL p, v100, fine, tStand\\WObj:=wHeld;
    GripLoad load0;
    MoveL p, v100, fine, tG;
  ENDPROC
ENDMODULE
"""


def test_gripload_is_carried_into_each_move_in_the_flanges_frame_and_load0_clears_it(tmp_path):
    (tmp_path / "grip.mod").write_text(GRIP)
    moves = Interpreter(load_task([tmp_path / "grip.mod"])).run("main").motions
    assert [m.load is None for m in moves] == [True, False, False, True]
    held = moves[1].load
    assert (held.mass, held.inertia, held.source) == (5.0, (0.1, 0.0, 0.0), "GripLoad piece1 at grip.mod:9")
    # in the tool's frame, turned 90 degrees about y and 200 mm out: 50 mm on its z is 50 mm on the flange's x
    assert held.cog == pytest.approx((0.05, 0.0, 0.2))
    assert held.aom == pytest.approx((0.7071068, 0.0, 0.7071068, 0.0))
    assert moves[2].load.cog == pytest.approx((0.0, 0.0, 0.15))  # a stationary tool: in the held work object
    assert moves[2].tool.robhold is False


def test_a_real_backups_gripload_reads(data):
    task = load_task([data / "rapid" / "real" / "backup" / "RAPID" / "TASK1"])
    run = Interpreter(task).run("main")
    assert any(m.load is not None and m.load.source.startswith("GripLoad loadPart at") for m in run.motions)
    assert not any("GripLoad" in w.message for w in run.warnings)


def test_program_reports_the_loads_and_their_factors(irb2600):
    out = run_program(ROBOT, [PICK_PLACE], payload="6@0,0,0.1")
    (load,) = out.doc["loads"]
    assert load["mass"] == pytest.approx(9.0) and load["moves"] == 8  # tGripper's 3 kg and the payload's 6
    assert load["cog"] == pytest.approx([0.0, 0.0, (3 * 0.08 + 6 * 0.1) / 9])
    assert "tload" in load["source"] and "--payload 6@0,0,0.1" in load["source"]
    expected = load_factors(irb2600)(rd.Load(3.0, (0.0, 0.0, 0.08), (0.0, 0.0, 0.0)), Payload(6.0, (0.0, 0.0, 0.1)))
    assert load["acceleration_factor"] == pytest.approx(list(expected))
    assert "loads: 9 kg (" in out.text and f"accelerations x{min(expected):.2f}-1.00" in out.text


@pytest.mark.parametrize("spec", ["abc", "-3", "6@0,0", "nowhere.mod:tool1", "12@0,0,100"])
def test_bad_payloads_are_one_line_errors(spec, capsys):
    assert main(["program", ROBOT, PICK_PLACE, "--payload", spec]) == 1
    err = capsys.readouterr().err.strip()
    assert err and "\n" not in err and "Traceback" not in err and ("payload" in err or "nowhere.mod" in err)


def test_a_centre_of_gravity_in_the_wrong_unit_is_said_in_the_files(capsys):
    """The IRB 2600's file is in metres: 100 (a programmer's mm) is 100 m from the flange."""
    assert main(["program", ROBOT, PICK_PLACE, "--payload", "12@0,0,100"]) == 1
    assert "100 m from the flange: the robot file's length unit is m" in capsys.readouterr().err


def test_a_load_over_the_rated_payload_is_timed_and_warned(capsys):
    assert main(["program", ROBOT, PICK_PLACE, "--payload", "30"]) == 0
    err = capsys.readouterr().err
    assert "a load of 33 kg" in err and "over the robot's rated 12 kg (IRB2600_12_165.robot.toml)" in err


def test_a_heavier_load_makes_the_program_slower():
    payloads = (None, "6@0,0,0.1", "12@0,0,0.1")
    times = [float(program_plan(ROBOT, [PICK_PLACE], payload=kg)[1].times[-1]) for kg in payloads]
    assert times[0] < times[1] < times[2]
