"""A cell file's ``backup``: the backup's SYSPAR/MOC.cfg (tests/data/moc/backup: an IRB 2600 on an
IRBT 2005 track, a two-axis positioner) sets the external axes' bounds, the robot's carrier and
frame and a single-axis unit's frame where the cell file leaves them out, each said in a note at
the ``backup`` line; what disagrees with the cell file is a warning."""

from __future__ import annotations

import numpy as np
import pytest

from rswarp.errors import RsxmlError
from rswarp.report.info import check_any
from rswarp.rsxml.cell import read_cell
from rswarp.transforms import quat_matrix

from conftest import DATA

CELLS = DATA / "cell_moc"


@pytest.fixture(scope="module")
def cell():
    return read_cell(str(CELLS / "backup_cell.toml"))


def test_the_backup_sets_the_bounds_of_every_external_axis(cell):
    track = cell.external("track").mechanism
    lo, hi = track.bounds()
    assert (lo[0], hi[0]) == pytest.approx((-0.1, 3.85))  # MOC's TRACK_1 ARM, not the RSXML's 0 .. 4 m
    stn = cell.external("stn1").mechanism
    lo, hi = stn.bounds()
    assert hi[1] == pytest.approx(6.28319) and lo[1] == pytest.approx(-6.28319)  # STN1_2: +-360 deg, not +-3600


def test_the_backup_puts_the_robot_on_the_track_at_its_base_frame(cell):
    assert cell.robot.on == "track"
    expected = np.eye(4)
    expected[:3, :3] = quat_matrix((0.707107, 0.0, 0.0, 0.707107))
    expected[:3, 3] = (0.0, 0.0, 0.565 - 0.4)  # MOC's frame is in the track's own: on its 400 mm mount flange
    assert np.allclose(cell.robot.frame, expected, atol=1e-6)
    frame = cell.external("track").frame  # TRACK_1's single: base frame [0.25, -1.2, 0]
    assert np.allclose(frame[:3, 3], (0.25, -1.2, 0.0)) and np.allclose(frame[:3, :3], np.eye(3))
    assert np.allclose(cell.external("stn1").frame[:3, 3], (1.8, 2.2, 0.0))  # given in the file: kept


def test_each_setting_is_said_in_a_note_at_the_backup_line(cell):
    notes = [d for d in cell.diagnostics if d.severity == "note"]
    assert all(d.line == 3 for d in notes)
    text = "\n".join(str(d) for d in notes)
    assert "backup_cell.toml:3: note: MOC.cfg: eax_a bounds -100 .. 3850 mm (TRACK_1's joint TRACK_1) replace " \
           "track's J1 limits (0 .. 4000 mm)" in text
    assert "ROB_1's base is moved by TRACK_1: the robot stands on 'track'" in text
    assert "the robot's frame is ROB_1's base frame" in text
    assert "the frame of 'track' is TRACK_1's single TRACK_1's base frame" in text
    report = check_any(str(CELLS / "backup_cell.toml"))
    assert report.ok and not report.warnings  # notes are neither errors nor warnings


def test_what_the_cell_file_gives_stays_and_a_disagreement_is_a_warning():
    cell = read_cell(str(CELLS / "given_cell.toml"))
    assert cell.robot.on == "stn1" and np.allclose(cell.robot.frame[:3, 3], (0.0, 0.0, 0.4))
    assert np.allclose(cell.external("track").frame, np.eye(4))
    warnings = [str(d) for d in cell.diagnostics if d.severity == "warning"]
    assert any("moved by TRACK_1 ('track' in the cell), not 'stn1' as [robot] on says" in w for w in warnings)
    assert any("eax_d drives stn1's J2 in the cell; the controller drives no eax_d" in w for w in warnings)
    assert any("the controller drives eax_c (STN1's joint STN1_2); no unit of the cell does" in w for w in warnings)
    assert cell.external("track").mechanism.bounds()[1][0] == pytest.approx(3.85)  # the bounds still apply


def test_a_missing_backup_and_a_linear_axis_on_a_turning_joint_are_errors_at_the_backup_line():
    with pytest.raises(RsxmlError) as exc:
        read_cell(str(CELLS / "no_backup.toml"))
    assert str(exc.value).startswith(f"{CELLS / 'no_backup.toml'}:2: backup: no such file or folder 'no_such_backup'")
    with pytest.raises(RsxmlError) as exc:
        read_cell(str(CELLS / "linear_on_turning.toml"))
    assert f"{CELLS / 'linear_on_turning.toml'}:2: MOC.cfg: eax_a is linear (TRACK_1), but stn1's J1 turns" \
        in str(exc.value)


def test_a_program_over_the_backups_cell_keeps_the_track_within_the_controllers_bounds(tmp_path):
    from rswarp.motion.plan import program_plan

    module = tmp_path / "far.mod"
    module.write_text("MODULE Far\n  CONST jointtarget jFar := [[0, 0, 0, 0, 30, 0], [3900, 0, 0, 9E9, 9E9, 9E9]];\n"
                      "  PROC main()\n    MoveAbsJ jFar, v1000, fine, tool0;\n  ENDPROC\nENDMODULE\n")
    _, plan = program_plan(str(CELLS / "backup_cell.toml"), [str(module)], strict=False)
    assert len(plan.errors) == 1 and plan.errors[0].line == 4
    assert "puts eax_a at 3900 mm, outside track's limits [-100, 3850] mm" in plan.errors[0].message
