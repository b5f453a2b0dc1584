"""A cell's backup read whole, and cells at their edges (issue 60): a backup's SYSPAR/EIO.cfg gives a
task run on the cell its signals, as the backup's own task folder does; a MultiMove backup's
MOC.cfg (tests/data/moc/multimove: ROB_1 on TRACK_1, ROB_2 beside the positioner STN1, each task's
external axes from eax_a, SYS.cfg saying which task moves which) gives the robot the cell names
(``[robot] unit``) its own base frame, carrier and axes; a cell of a robot and no external unit
plans as the robot alone; zoned moves over a cell are one corner path, as over the robot alone.
Expectations are the fixtures' numbers, written out here."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from rswarp.errors import RsxmlError
from rswarp.kinematics.cell import CellKinematics
from rswarp.kinematics.kinematics import Kinematics
from rswarp.motion.plan import program_plan
from rswarp.rsxml.cell import read_cell

from conftest import DATA

ROOT = Path(__file__).resolve().parents[1]
CELLS = DATA / "cell_moc"
ROBOT = ROOT / "examples" / "irb2600_12_165" / "IRB2600_12_165__01.rsxml"
TRACK = ROOT / "examples" / "track" / "IRBT2005_4m.rsxml"
POSITIONER = ROOT / "examples" / "positioner" / "IRBP_A250.rsxml"
MULTIMOVE = DATA / "moc" / "multimove"
POS_TOL = 0.5e-3  # m

SPEED_TASK = """MODULE Speed
  ! I_giSpeed: a group input only the backup's EIO.cfg declares (-Default 3)
  CONST jointtarget jSlow := [[0, 0, 0, 0, 30, 0], [500, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST jointtarget jFast := [[20, 0, 0, 0, 30, 0], [1500, 9E9, 9E9, 9E9, 9E9, 9E9]];
  PROC main()
    IF I_giSpeed = 3 THEN
      MoveAbsJ jFast, v1000, fine, tool0;
    ELSE
      MoveAbsJ jSlow, v1000, fine, tool0;
    ENDIF
  ENDPROC
ENDMODULE
"""


def cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "rswarp.cli", *args], capture_output=True, text=True, cwd=ROOT)


# -- a backup read whole: its EIO.cfg ----------------------------------------------------------------------------

def test_a_cells_backup_gives_the_task_the_signals_its_eio_cfg_declares(tmp_path):
    module = tmp_path / "speed.mod"
    module.write_text(SPEED_TASK)
    cell = read_cell(str(CELLS / "backup_cell.toml"))
    assert Path(cell.eio).resolve() == (DATA / "moc" / "backup" / "SYSPAR" / "EIO.cfg").resolve()
    assert any(d.severity == "note" and d.line == 3 and "EIO.cfg" in d.message for d in cell.diagnostics)
    said: list[str] = []
    _, plan = program_plan(str(CELLS / "backup_cell.toml"), [str(module)], warn=said.append)
    assert not plan.errors and [m.line for m in plan.moves] == [7]  # I_giSpeed at its -Default 3: jFast
    assert plan.ext[-1, 0] == pytest.approx(1.5)  # eax_a 1500 mm: the track's
    notes = [w for w in said if "EIO.cfg" in w and "3 signals read" in w]
    assert len(notes) == 1 and "the cell's backup" in notes[0]
    _, slow = program_plan(str(CELLS / "backup_cell.toml"), [str(module)], io={"I_giSpeed": 1})
    assert [m.line for m in slow.moves] == [9]
    with pytest.raises(RsxmlError, match="'I_giSpeed' is declared nowhere in the task"):
        program_plan(str(ROBOT), [str(module)])  # the robot alone: no backup, no such signal


def test_a_backup_given_as_its_moc_cfg_reads_the_eio_cfg_beside_it(tmp_path):
    backup = tmp_path / "backup"
    shutil.copytree(DATA / "moc" / "backup", backup)
    cell = tmp_path / "cell.toml"
    cell.write_text(f'backup = "backup/SYSPAR/MOC.cfg"\n[robot]\nrsxml = "{ROBOT.as_posix()}"\n[[external]]\n'
                    f'name = "track"\nrsxml = "{TRACK.as_posix()}"\naxes = ["eax_a"]\n')
    assert Path(read_cell(str(cell)).eio).name == "EIO.cfg"
    (backup / "SYSPAR" / "EIO.cfg").unlink()
    assert read_cell(str(cell)).eio is None  # no EIO.cfg: nothing more is read, nothing said


# -- MultiMove: two robots in one MOC.cfg ----------------------------------------------------------------------

def test_a_multimove_backup_gives_rob_2_its_own_base_frame_and_its_tasks_axes():
    cell = read_cell(str(CELLS / "multimove_rob2.toml"))
    expected = np.eye(4)  # ROB_2: [3.2, 1.5, 0] m, q [0, 0, 0, 1] (turned 180 degrees about z)
    expected[:3, :3] = np.diag([-1.0, -1.0, 1.0])
    expected[:3, 3] = (3.2, 1.5, 0.0)
    assert cell.robot.on is None and np.allclose(cell.robot.frame, expected, atol=1e-9)
    lo, hi = cell.external("stn1").mechanism.bounds()  # eax_a, eax_b of T_ROB2: STN1_1, STN1_2
    assert (lo[0], hi[0], lo[1], hi[1]) == pytest.approx((-1.5708, 1.5708, -6.28319, 6.28319))
    text = "\n".join(str(d) for d in cell.diagnostics)
    assert "the cell's robot is ROB_2" in text and "TRACK_1" not in text  # ROB_1's track is not ROB_2's


def test_a_multimove_backup_puts_rob_1_on_its_track_by_its_task_name():
    cell = read_cell(str(CELLS / "multimove_rob1.toml"))  # unit = "T_ROB1": SYS.cfg's task of ROB_1
    assert cell.robot.on == "track"
    # MOC.cfg's base frame is in TRACK_1's own frame: on the track's mount flange (400 mm up) it is 165 mm
    assert np.allclose(cell.robot.frame[:3, 3], (0.0, 0.0, 0.165))
    ck = CellKinematics(cell)
    assert np.allclose(ck.robot_base(ck.split(ck.home()[None]))[0, :3, 3], (0.25, -1.2, 0.565))
    lo, hi = cell.external("track").mechanism.bounds()
    assert (lo[0], hi[0]) == pytest.approx((-0.1, 3.85))  # TRACK_1's eax_a, not STN1_1's (also eax_a)
    assert np.allclose(cell.external("track").frame[:3, 3], (0.25, -1.2, 0.0))
    assert not any(d.severity == "warning" for d in cell.diagnostics)


def test_a_program_over_rob_2_moves_it_from_its_own_base_with_its_positioner():
    module = CELLS / "rob2_station.mod"
    _, plan = program_plan(str(CELLS / "multimove_rob2.toml"), [str(module)])
    assert not plan.errors and [m.line for m in plan.moves] == [9, 10, 11]
    assert np.degrees(plan.ext[-1]) == pytest.approx([30.0, 90.0])  # eax_a, eax_b: STN1's tilt and turn
    kin = Kinematics(read_cell(str(CELLS / "multimove_rob2.toml")).robot.mechanism)
    base = np.eye(4)
    base[:3, :3] = np.diag([-1.0, -1.0, 1.0])
    base[:3, 3] = (3.2, 1.5, 0.0)
    link, offset = kin.flange_frame()
    for move, target in zip(plan.moves[1:], ((2.3, 1.5, 1.0), (2.3, 1.6, 0.8))):
        q = plan.q[move.rows[1] - 1]
        tcp = base @ kin.fk64(q[None])[0, link] @ offset
        assert np.linalg.norm(tcp[:3, 3] - target) < POS_TOL
    _, rob1 = program_plan(str(CELLS / "multimove_rob1.toml"), [str(module)], strict=False)
    assert len(rob1.errors) == 2 and all("out of reach" in d.message for d in rob1.errors)  # far from ROB_1


def test_a_multimove_backup_without_a_named_robot_is_an_error_at_the_backup_line(tmp_path):
    cell = tmp_path / "cell.toml"
    cell.write_text(f'backup = "{MULTIMOVE.as_posix()}"\n[robot]\nrsxml = "{ROBOT.as_posix()}"\n')
    with pytest.raises(RsxmlError) as exc:
        read_cell(str(cell))
    assert str(exc.value) == f"{cell}:1: MOC.cfg: the controller has 2 robots (ROB_1, ROB_2: MultiMove): say which " \
                             "is the cell's, [robot] unit = \"ROB_1\" (or its motion task: T_ROB1, T_ROB2)"
    cell.write_text(f'backup = "{MULTIMOVE.as_posix()}"\n[robot]\nrsxml = "{ROBOT.as_posix()}"\nunit = "ROB_3"\n')
    with pytest.raises(RsxmlError, match=r"cell.toml:4: MOC.cfg: \[robot\] unit = 'ROB_3' is no robot of the "
                                         r"controller \(its robots: ROB_1, ROB_2, and SYS.cfg the motion tasks "
                                         r"T_ROB1, T_ROB2\)"):
        read_cell(str(cell))
    cell.write_text(f'[robot]\nrsxml = "{ROBOT.as_posix()}"\nunit = "ROB_2"\n')
    with pytest.raises(RsxmlError, match=r"cell.toml:3: \[robot\] unit = 'ROB_2' names a robot of the cell's "
                                         r"backup, and the cell file gives no backup"):
        read_cell(str(cell))
    assert cli("check", str(cell)).returncode == 1  # said, never an internal error


def test_without_sys_cfg_a_multimove_robot_takes_the_axes_of_no_other_robots_carrier(tmp_path):
    """No SYS.cfg to group the units: ROB_2's eax_a is STN1_1's, since TRACK_1 carries ROB_1; a
    task's name cannot be known."""
    (tmp_path / "backup" / "SYSPAR").mkdir(parents=True)
    shutil.copy(MULTIMOVE / "SYSPAR" / "MOC.cfg", tmp_path / "backup" / "SYSPAR" / "MOC.cfg")
    text = (CELLS / "multimove_rob2.toml").read_text().replace("../moc/multimove", "backup")
    text = text.replace("../../../examples/irb2600_12_165/IRB2600_12_165__01.rsxml", ROBOT.as_posix())
    text = text.replace("../../../examples/positioner/IRBP_A250.rsxml", POSITIONER.as_posix())
    (tmp_path / "cell.toml").write_text(text)
    cell = read_cell(str(tmp_path / "cell.toml"))
    assert cell.external("stn1").mechanism.bounds()[1][0] == pytest.approx(1.5708)
    assert np.allclose(cell.robot.frame[:3, 3], (3.2, 1.5, 0.0))
    (tmp_path / "cell.toml").write_text(text.replace('unit = "ROB_2"', 'unit = "T_ROB2"'))
    with pytest.raises(RsxmlError, match="a motion task is known by the backup's SYSPAR/SYS.cfg, which it lacks"):
        read_cell(str(tmp_path / "cell.toml"))


def test_an_empty_base_frame_moved_by_is_no_reference():
    """``-base_frame_moved_by ""`` (ROB_2 in the fixture), as the controller writes a reference left
    unset: fixed in the world, not an error."""
    from rswarp.rsxml.moc import read_moc

    moc = read_moc(MULTIMOVE / "SYSPAR" / "MOC.cfg")
    rob2 = next(r for r in moc.robots if r.name == "ROB_2")
    assert rob2.base_frame.moved_by is None


# -- a robot alone in its cell; zoned moves over a cell ---------------------------------------------------------

ZONED = """MODULE Zoned
  PERS wobjdata wBase := [FALSE, TRUE, "", [[{x}, 0, {z}], [1, 0, 0, 0]], [[0, 0, 0], [1, 0, 0, 0]]];
  CONST robtarget p1 := [[900,0,1000],[0,0,1,0],[0,0,0,0],[{a},9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget p2 := [[900,200,900],[0,0,1,0],[0,0,0,0],[{a},9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget p3 := [[901.3,207.1,703.3],[0,0,1,0],[0,0,0,0],[{a},9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget p4 := [[903.7,-211.3,707.9],[0,0,1,0],[-1,0,-1,0],[{a},9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveJ p1, v1000, fine, tool0 \\WObj:=wBase;
    MoveL p2, v500, z20, tool0 \\WObj:=wBase;
    MoveL p3, v500, z20, tool0 \\WObj:=wBase;
    MoveL p4, v500, z20, tool0 \\WObj:=wBase;
    MoveL p1, v500, fine, tool0 \\WObj:=wBase;
  ENDPROC
ENDMODULE
"""


def test_a_cell_of_a_robot_and_no_external_unit_runs_as_the_robot_alone(tmp_path):
    cell = tmp_path / "cell.toml"
    cell.write_text(f'[robot]\nrsxml = "{ROBOT.as_posix()}"\n')
    module = tmp_path / "zoned.mod"
    module.write_text(ZONED.format(x=0, z=0, a="9E9"))
    run = cli("program", str(cell), str(module), "--csv", str(tmp_path / "cell.csv"))
    assert run.returncode == 0, run.stderr
    alone = cli("program", str(ROBOT), str(module), "--csv", str(tmp_path / "alone.csv"))
    assert alone.returncode == 0, alone.stderr
    assert (tmp_path / "cell.csv").read_text() == (tmp_path / "alone.csv").read_text()
    _, a = program_plan(str(ROBOT), [str(module)])
    _, c = program_plan(str(cell), [str(module)])
    assert np.array_equal(a.times, c.times) and np.array_equal(a.q, c.q) and c.ext.shape == (len(c.q), 0)


def test_zoned_moves_over_a_track_are_one_corner_path_as_over_the_robot_alone(tmp_path):
    """The carriage held at 1000 mm and the work object on the robot's base there (400 mm up on
    the carriage): the chain's joints and times are the robot alone's in wobj0, exactly."""
    on_track, alone = tmp_path / "track.mod", tmp_path / "alone.mod"
    on_track.write_text(ZONED.format(x=1000, z=400, a=1000))
    alone.write_text(ZONED.format(x=0, z=0, a="9E9"))
    _, a = program_plan(str(ROBOT), [str(alone)])
    _, c = program_plan(str(ROOT / "examples" / "cells" / "track_cell.toml"), [str(on_track)])
    assert [m.line for m in c.moves] == [8, 9, 10, 11, 12] and not c.errors
    ra, rc = a.moves[1].rows[0], c.moves[1].rows[0]  # after the first move (the carriage runs to 1000 mm)
    assert np.allclose(c.ext[rc:, 0], 1.0)
    assert np.allclose(a.q[ra:], c.q[rc:], atol=1e-9)
    assert np.allclose(np.diff(a.times[ra:]), np.diff(c.times[rc:]), atol=1e-9)
