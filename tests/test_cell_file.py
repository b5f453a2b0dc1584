"""Cell files and a backup's MOC.cfg (issue 49): a robot on the floor at a frame (mm and degrees,
ABB's Euler ZYX, as a 4x4 in metres), with a tool and environment meshes; a robot on a track's
carriage (eax_a); a two-axis positioner (eax_b, eax_c); a robot whose AllowedTrackModels does
not name its track (a warning); every bad cell file said as ``file:line: message`` at the key
that holds the problem. A RobotWare 6 MOC.cfg of an IRB 2600 on an IRBT 2005 track and a
two-axis positioner: every base frame, logical axis, joint kind and bound it sets, and the notes
that say so; its malformed lines at their lines. The CFG tokenizer it shares with EIO.cfg."""

from __future__ import annotations

import math
import shutil

import numpy as np
import pytest

from rswarp.errors import InputError, RsxmlError
from rswarp.rsxml.cell import frame_matrix, read_cell
from rswarp.rsxml.cfg import parse_cfg
from rswarp.rsxml.moc import read_moc
from rswarp.transforms import quat_matrix

from conftest import DATA

CELLS = DATA / "cells"
MOC = DATA / "moc"
BACKUP_MOC = MOC / "backup" / "SYSPAR" / "MOC.cfg"


def rz(deg: float) -> np.ndarray:
    """The rotation about z by ``deg`` degrees, written out (not through the code under test)."""
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def pose(xyz_m, r) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3], m[:3, 3] = r, xyz_m
    return m


# -- cell files -------------------------------------------------------------------------------------


def test_robot_on_the_floor_with_tool_and_environment():
    cell = read_cell(CELLS / "floor.toml")
    assert cell.robot.rsxml == str(CELLS / "robot.rsxml") and cell.robot.mechanism.type == "Robot"
    assert cell.robot.on is None and cell.carrier is None and cell.robot.line == 3
    np.testing.assert_allclose(cell.robot.frame, pose([1.0, -0.5, 0.5], rz(90)), atol=1e-12)
    assert cell.externals == () and cell.mapping == {} and cell.warnings == ()
    assert cell.tool.path == str(CELLS / "gripper.rsxml") and cell.tool.mechanism.type == "Tool"
    np.testing.assert_allclose(cell.tool.mount, pose([0, 0, 0.01], rz(180)), atol=1e-12)
    assert [(m.name, m.path, m.line) for m in cell.environment] == [
        ("fixture", str(CELLS / "fixture.stl"), 11), ("fixture", str(CELLS / "fixture.stl"), 15)]
    np.testing.assert_allclose(cell.environment[0].pose, pose([1.8, 0, 0], np.eye(3)))
    np.testing.assert_allclose(cell.environment[1].pose, np.eye(4))  # no frame: the world's origin
    with pytest.raises(InputError, match=r"floor.toml: eax_a drives no joint in this cell \(its logical axes: none\)"):
        cell.unit_of("eax_a")


def test_tool_spec_is_what_the_tool_option_takes():
    """``--tool PATH@x,y,z,rx,ry,rz`` in the robot file's length unit (mm here) and degrees."""
    cell = read_cell(CELLS / "floor.toml")
    path, _, numbers = cell.tool.spec(cell.robot.mechanism).rpartition("@")
    assert path == str(CELLS / "gripper.rsxml")
    np.testing.assert_allclose([float(v) for v in numbers.split(",")], [0, 0, 10, 0, 0, 180], atol=1e-9)


def test_robot_on_a_track():
    cell = read_cell(CELLS / "track.toml")
    track = cell.external("track")
    assert cell.robot.on == "track" and cell.carrier is track and cell.warnings == ()
    np.testing.assert_allclose(cell.robot.frame, pose([0, 0, 0.565], rz(90)), atol=1e-12)  # on the carriage
    np.testing.assert_allclose(track.frame, pose([0.25, -1.2, 0], rz(90)), atol=1e-12)  # in the world
    assert track.rsxml == str(CELLS / "track.rsxml") and track.mechanism.type == "ExternalAxis"
    assert (track.axes, track.joints, track.carrier_link, track.line) == (("eax_a",), ("T1",), "Carriage", 8)
    assert cell.mapping == {"eax_a": ("track", "T1")}
    assert cell.unit_of("EAX_A") == ("track", "T1")
    with pytest.raises(InputError, match=r"eax_b drives no joint in this cell \(its logical axes: eax_a\)"):
        cell.unit_of("eax_b")


def test_two_axis_positioner():
    cell = read_cell(CELLS / "positioner.toml")
    stn = cell.external("stn1")
    assert (stn.axes, stn.joints, stn.carrier_link) == (("eax_b", "eax_c"), ("A1", "A2"), "Plate")
    np.testing.assert_allclose(stn.frame, pose([1.8, 0, 0], rz(180)), atol=1e-12)
    assert cell.mapping == {"eax_b": ("stn1", "A1"), "eax_c": ("stn1", "A2")}
    assert cell.robot.on is None and cell.warnings == ()
    with pytest.raises(KeyError):
        cell.external("track")


def test_track_and_positioner_map_three_axes_in_axis_order():
    cell = read_cell(CELLS / "track_positioner.toml")
    assert cell.mapping == {"eax_a": ("track", "T1"), "eax_b": ("stn1", "A1"), "eax_c": ("stn1", "A2")}
    assert cell.external("stn1").axes == ("eax_b", "eax_c")  # EAX_B written in capitals
    np.testing.assert_allclose(cell.external("stn1").frame, pose([1.8, 2.2, 0], rz(-90)), atol=1e-12)


def test_a_track_the_robot_does_not_allow_is_a_warning():
    cell = read_cell(CELLS / "track_not_allowed.toml")
    assert cell.warnings == (f"{CELLS / 'track_not_allowed.toml'}:4: warning: robot 'IRB2600_12_165__01' allows the "
                             "track models IRBT4004, IRBT2005 (AllowedTrackModels), not 'IRBT6004' of 'track'",)
    assert cell.unit_of("eax_a") == ("track", "T1")  # a warning: the cell is still read


def test_frame_is_abb_euler_zyx_in_mm_and_degrees():
    m = frame_matrix([100, -200, 300, 10, 20, 30])
    np.testing.assert_allclose(m[:3, 3], [0.1, -0.2, 0.3])
    rx, ry = math.radians(10), math.radians(20)
    r_x = np.array([[1, 0, 0], [0, math.cos(rx), -math.sin(rx)], [0, math.sin(rx), math.cos(rx)]])
    r_y = np.array([[math.cos(ry), 0, math.sin(ry)], [0, 1, 0], [-math.sin(ry), 0, math.cos(ry)]])
    np.testing.assert_allclose(m[:3, :3], rz(30) @ r_y @ r_x, atol=1e-12)


BAD = {  # file: its whole first line of error, after the path
    "bad_type.toml": "3: [robot] rsxml: 'track.rsxml' is a mechanism of type ExternalAxis, not Robot",
    "bad_external_type.toml": "7: [[external]] 'track' rsxml: 'robot.rsxml' is a mechanism of type Robot, not "
                              "ExternalAxis",
    "bad_tool_type.toml": "6: [tool] path: 'robot.rsxml' is a mechanism of type Robot, not Tool",
    "bad_unknown_key.toml": "4: unknown key 'fram' in [robot]; did you mean 'frame'?",
    "bad_unknown_table.toml": "5: unknown key 'externals' in the cell file; did you mean 'external'?",
    "bad_frame.toml": "5: [robot] frame: give 6 numbers, x, y, z in mm, then rx, ry, rz in degrees (ABB's Euler "
                      "ZYX), not 7 values (a quaternion is not taken: give rx, ry, rz)",
    "bad_frame_value.toml": "9: [[external]] 'track' frame: value 3 ('100') is not a finite number",
    "bad_axes_count.toml": "8: [[external]] 'stn1' axes: 1 logical axis for its 2 active joints (A1, A2): give one "
                           "per joint, in joint order",
    "bad_axis_twice.toml": "14: [[external]] 'stn1' axes: eax_a already drives joint T1 of 'track' (line 9)",
    "bad_axis_name.toml": "8: [[external]] 'track' axes: 'eax_g' is not a logical axis: eax_a .. eax_f",
    "bad_on.toml": "4: [robot] on = 'trak' names no [[external]]; did you mean 'track'?",
    "bad_missing_file.toml": f"7: [[external]] 'stn1' rsxml: no such file 'positioner_two_axes.rsxml' (looked for "
                             f"{CELLS / 'positioner_two_axes.rsxml'})",
    "bad_toml.toml": "4: TOML: Expected '=' after a key in a key/value pair",
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_cell_file_is_said_at_its_line(name):
    with pytest.raises(RsxmlError) as err:
        read_cell(CELLS / name)
    assert str(err.value) == f"{CELLS / name}:{BAD[name]}"
    assert err.value.line == int(BAD[name].split(":")[0])


def test_a_cell_without_a_robot_is_said_for_the_whole_file():
    with pytest.raises(RsxmlError) as err:
        read_cell(CELLS / "bad_no_robot.toml")
    assert str(err.value) == f"{CELLS / 'bad_no_robot.toml'}: no [robot] table: a cell places one robot (rsxml = its " \
                             "RSXML file)"


def write_cell(tmp_path, text: str, data: bytes | None = None):
    """A cell file beside copies of the test RSXML files."""
    for f in ("robot.rsxml", "track.rsxml", "positioner.rsxml", "gripper.rsxml", "gripper.stl", "fixture.stl"):
        shutil.copy(CELLS / f, tmp_path / f)
    path = tmp_path / "cell.toml"
    path.write_bytes(data if data is not None else text.encode())
    return path


@pytest.mark.parametrize("text, line, message", [
    ('[robot]\nrsxml = "robot.rsxml"\n\n[[external]]\nname = "a"\nrsxml = "track.rsxml"\naxes = ["eax_a"]\n\n'
     '[[external]]\nname = "b"\nrsxml = "track.rsxml"\naxis = ["eax_b"]\n', 12,
     "unknown key 'axis' in [[external]] 2; did you mean 'axes'?"),
    ('[robot]\nrsxml = "robot.rsxml"\n[[external]]\nname = "a"\nrsxml = "track.rsxml"\naxes = ["eax_a"]\n'
     '[[external]]\nname = "a"\nrsxml = "track.rsxml"\naxes = ["eax_b"]\n', 8, "two external units are named 'a'"),
    ('[robot]\nrsxml = "robot.rsxml"\n[[external]]\nrsxml = "track.rsxml"\n', 3, "[[external]] 1: give it a name (text)"),
    ('[robot]\nrsxml = "robot.rsxml"\n[[external]]\nname = "t"\nrsxml = "track.rsxml"\n', 3,
     "[[external]] 't' axes: give the logical axes (eax_a .. eax_f) of its 1 active joint (T1), in joint order, as "
     "a list of text"),
    ('[robot]\nrsxml = "robot.rsxml"\non = "track"\n', 3, "[robot] on = 'track' names no [[external]] (the cell has "
                                                          "no [[external]])"),
    ('[robot]\nrsxml = "robot.rsxml"\nframe = [0, 0, 0, 0, 0, nan]\n', 3, "[robot] frame: value 6 (nan) is not a "
                                                                          "finite number"),
    ('[robot]\nrsxml = "robot.rsxml"\nframe = [0, 0, 0, 0, true, 0]\n', 3, "[robot] frame: value 5 (True) is not a "
                                                                           "finite number"),
    ('[robot]\nrsxml = "robot.rsxml"\nframe = [2e6, 0, 0, 0, 0, 0]\n', 3, "[robot] frame: a position within 1e+06 "
                                                                          "mm and angles within 5.72958e+06 degrees, "
                                                                          "please"),
    ('[robot]\nrsxml = "robot.rsxml"\nframe = "0, 0, 0"\n', 3, "[robot] frame: give 6 numbers, x, y, z in mm, then "
                                                              "rx, ry, rz in degrees (ABB's Euler ZYX), not '0, 0, 0'"),
    ('robot = { rsxml = "robot.rsxml", fame = [] }\n', 1, "unknown key 'fame' in [robot]; did you mean 'frame'?"),
    ('[robot]\nrsxml = "robot.rsxml"\n[[environment]]\nmesh = "fixture.stl"\nname = "x"\n', 5,
     "unknown key 'name' in [[environment]] 1 (known: mesh, frame, on)"),
    ('[robot]\nrsxml = "robot.rsxml"\n[robot.base]\nx = 1\n', 3, "unknown key 'base' in [robot] (known: rsxml, on, "
                                                                  "frame, unit, name, task, drives)"),
    ('[robot]\nrsxml = "robot.rsxml"\n[external]\nname = "t"\n', 3, "external must be an array of tables: "
                                                                    "[[external]], once for each"),
    ('[robot]\nrsxml = 3\n', 2, "[robot] rsxml: give an RSXML Mechanism of type Robot, as a path relative to the cell "
                                "file"),
    ('[robot]\nrsxml = "robot.rsxml"\n[tool]\npath = "gripper.stl"\n[[environment]]\nmesh = "floor.stl"\n', 6,
     "[[environment]] 1 mesh: no such file 'floor.stl'"),
])
def test_more_bad_cells_at_their_lines(tmp_path, text, line, message):
    path = write_cell(tmp_path, text)
    with pytest.raises(RsxmlError) as err:
        read_cell(path)
    assert str(err.value).startswith(f"{path}:{line}: {message}")


def test_utf8_with_bom_is_read_other_encodings_are_not(tmp_path):
    text = '# Zelle für Roboter\n[robot]\nrsxml = "robot.rsxml"\n'
    cell = read_cell(write_cell(tmp_path, "", b"\xef\xbb\xbf" + text.encode()))
    assert cell.robot.mechanism.type == "Robot" and cell.robot.line == 2
    path = write_cell(tmp_path, "", text.encode("cp1252"))
    with pytest.raises(RsxmlError, match=r"cell.toml: not UTF-8 text \(byte 9\)"):
        read_cell(path)
    with pytest.raises(RsxmlError, match=r": cannot read file: a folder: only regular files are read"):
        read_cell(tmp_path)


def test_mesh_tool_and_windows_paths(tmp_path):
    (tmp_path / "meshes").mkdir()
    shutil.copy(CELLS / "fixture.stl", tmp_path / "meshes" / "fixture.stl")
    path = write_cell(tmp_path, '[robot]\nrsxml = "robot.rsxml"\n[tool]\npath = "gripper.stl"\n'
                                '[[environment]]\nmesh = "meshes\\\\fixture.stl"\nframe = [0, 0, -10, 0, 0, 0]\n')
    cell = read_cell(path)
    assert cell.tool.mechanism is None and cell.tool.path == str(tmp_path / "gripper.stl")
    assert cell.environment[0].path == str(tmp_path / "meshes" / "fixture.stl")
    np.testing.assert_allclose(cell.environment[0].pose[:3, 3], [0, 0, -0.01])


# -- MOC.cfg ----------------------------------------------------------------------------------------


def test_moc_units_robot_and_singles():
    moc = read_moc(BACKUP_MOC)
    assert [u.name for u in moc.units] == ["ROB_1", "TRACK_1", "STN1"]
    rob, track, stn = moc.units
    assert rob.robot.name == "ROB_1" and rob.robot.robot_type == "ROB1_2600_1.65_12" and rob.singles == ()
    assert rob.robot.joints == tuple(f"rob1_{k}" for k in range(1, 7)) and rob.line == 27
    frame = rob.robot.base_frame
    assert frame.position == (0.0, 0.0, 0.565) and frame.moved_by == "TRACK_1"
    np.testing.assert_allclose(frame.quaternion, [math.sqrt(0.5), 0, 0, math.sqrt(0.5)], atol=1e-6)
    np.testing.assert_allclose(frame.matrix(), pose([0, 0, 0.565], rz(90)), atol=1e-6)
    assert track.robot is None and [s.name for s in track.singles] == ["TRACK_1"]
    single = track.singles[0]
    assert (single.single_type, single.joint, single.base_frame.position) == ("TRACK", "TRACK_1", (0.25, -1.2, 0.0))
    assert single.base_frame.quaternion == (1.0, 0.0, 0.0, 0.0) and single.base_frame.moved_by is None
    assert [s.name for s in stn.singles] == ["STN1_1", "STN1_2"]
    assert stn.singles[0].base_frame.position == (1.8, 2.2, 0.6) and stn.singles[0].base_frame.quaternion == (0.5,) * 4
    np.testing.assert_allclose(stn.singles[0].base_frame.matrix()[:3, :3], quat_matrix([1, 1, 1, 1]))
    assert stn.singles[1].base_frame.position == (1.8, 2.2, 0.85)
    assert moc.robots == (rob.robot,) and moc.unit("stn1") is stn


ROBOT_BOUNDS = [(-3.14159, 3.14159), (-1.65806, 2.70526), (-3.14159, 1.309), (-6.98132, 6.98132),
                (-2.0944, 2.0944), (-6.98132, 6.98132)]


def test_moc_joints_axes_kinds_and_bounds():
    moc = read_moc(BACKUP_MOC)
    rob, track, stn = moc.units
    for k, j in enumerate(rob.joints):
        assert (j.name, j.logical_axis, j.axis, j.unit, j.rotating) == (f"rob1_{k + 1}", k + 1, f"rax_{k + 1}",
                                                                         "ROB_1", True)
        assert (j.lower, j.upper) == ROBOT_BOUNDS[k] and j.arm == j.transmission == j.name
    eax = moc.external_axes
    assert list(eax) == ["eax_a", "eax_b", "eax_c"]
    expected = {"eax_a": ("TRACK_1", 7, "TRACK_1", False, -0.1, 3.85),
                "eax_b": ("STN1_1", 8, "STN1", True, -1.5708, 1.5708),
                "eax_c": ("STN1_2", 9, "STN1", True, -6.28319, 6.28319)}
    for axis, j in eax.items():
        assert (j.name, j.logical_axis, j.unit, j.rotating, j.lower, j.upper) == expected[axis]
    assert track.joints == (eax["eax_a"],) and stn.joints == (eax["eax_b"], eax["eax_c"])
    assert len(moc.joints) == 9 and moc.joints[6].line == 94


def test_moc_notes_say_what_it_set():
    notes = read_moc(BACKUP_MOC).notes
    assert notes[0] == ("ROB_1's base frame [0, 0, 0.565] m, q [0.707107, 0, 0, 0.707107], moved by TRACK_1 "
                        "(robot type ROB1_2600_1.65_12)")
    assert notes[1] == "rax_1: ROB_1 axis 1 (rob1_1), rotating, -3.14159 .. 3.14159 rad (-180 .. 180 deg)"
    assert notes[2] == "rax_2: ROB_1 axis 2 (rob1_2), rotating, -1.65806 .. 2.70526 rad (-95 .. 155 deg)"
    assert notes[7:] == (
        "TRACK_1's single TRACK_1: base frame [0.25, -1.2, 0] m, q [1, 0, 0, 0], fixed in the world",
        "eax_a: TRACK_1's joint TRACK_1, linear, -0.1 .. 3.85 m",
        "STN1's single STN1_1: base frame [1.8, 2.2, 0.6] m, q [0.5, 0.5, 0.5, 0.5], fixed in the world",
        "STN1's single STN1_2: base frame [1.8, 2.2, 0.85] m, q [1, 0, 0, 0], fixed in the world",
        "eax_b: STN1's joint STN1_1, rotating, -1.5708 .. 1.5708 rad (-90 .. 90 deg)",
        "eax_c: STN1's joint STN1_2, rotating, -6.28319 .. 6.28319 rad (-360 .. 360 deg)",
    )


def test_moc_with_crlf_and_bom_reads_the_same(tmp_path):
    path = tmp_path / "MOC.cfg"
    path.write_bytes(b"\xef\xbb\xbf" + BACKUP_MOC.read_bytes().replace(b"\n", b"\r\n"))
    assert read_moc(path).notes == read_moc(BACKUP_MOC).notes
    assert read_moc(path).units[0].line == 27


BAD_MOC = {
    "bad_header.cfg": "1: not a MOC.cfg: its first line is 'EIO:CFG_1.0:6:0::', not the header "
                      "MOC:CFG_1.0:<version>:<revision>::",
    "bad_number.cfg": "19: ARM 'TRACK_1': -upper_joint_bound: a bad number '3,85'",
    "bad_quote.cfg": "5: '\"ROB_1': an unclosed quote",
    "bad_text.cfg": "5: 'activate_at_start_up' in MECHANICAL_UNIT is no attribute: give -key value",
    "bad_moved_by.cfg": "10: ROBOT 'ROB_1': -base_frame_moved_by 'TRACK_2' names no MECHANICAL_UNIT",
    "bad_logical_axis.cfg": "14: JOINT 'TRACK_1': -logical_axis must be a whole number 1..12 (7..12: eax_a..eax_f), "
                            "not 13",
    "bad_reference.cfg": "13: JOINT 'TRACK_1': -use_arm 'TRACK_1' names no ARM instance",
    "bad_quaternion.cfg": "9: ROBOT 'ROB_1': the base frame's quaternion [1, 0, 0, 0.707107] (u0..u3; u0 is 1 where "
                          "omitted) has length 1.22474, not 1",
    "bad_twice.cfg": "7: ARM 'TRACK_1' is defined twice (first at line 5)",
    "bad_outside.cfg": "2: '-name \"ROB_1\" -use_robot \"ROB_1\"' stands before any section (NAME:)",
}


@pytest.mark.parametrize("name", sorted(BAD_MOC))
def test_bad_moc_is_said_at_its_line(name):
    with pytest.raises(RsxmlError) as err:
        read_moc(MOC / name)
    assert str(err.value) == f"{MOC / name}:{BAD_MOC[name]}"


def test_moc_that_cannot_be_read(tmp_path):
    with pytest.raises(RsxmlError, match=r"MOC.cfg: cannot read: "):
        read_moc(tmp_path / "MOC.cfg")
    (tmp_path / "MOC.cfg").write_bytes(b"MOC:CFG_1.0:6:0::\n\x00\x01")
    with pytest.raises(RsxmlError, match=r"MOC.cfg: not a CFG text file \(it holds NUL bytes\)"):
        read_moc(tmp_path / "MOC.cfg")


# -- the CFG tokenizer ------------------------------------------------------------------------------


def test_cfg_flags_negative_numbers_quotes_and_continuations():
    text = ('X:CFG_1.0:6:0::\n#\nARM:\n\n      -name "a" -flag  -lower -0.5 -upper 2\\\n      -text "say \\"hi\\""\n'
            '\n      -name "b" -rotating_move\n#\nSYSSIG_OUT:\n\n      -Status "MotorOn" -Signal "do1"\n'
            '      -Status "Auto" -Signal "do2"\n')
    a, b, s1, s2 = parse_cfg(text, "X.cfg", domain="X")
    assert a.section == "ARM" and a.name == "a" and a.line == 5
    assert dict(a.attrs) == {"name": "a", "flag": True, "lower": "-0.5", "upper": "2", "text": 'say \\"hi\\"'}
    assert a.line_of("text") == 6 and a.line_of("absent") == 5 and a.text("flag") is None and a.flag("flag")
    assert dict(b.attrs) == {"name": "b", "rotating_move": True}
    assert (s1.section, s1.text("signal"), s1.line, s2.text("signal"), s2.line) == ("SYSSIG_OUT", "do1", 12, "do2", 13)


def test_cfg_lenient_skips_what_strict_refuses():
    text = 'EIO_SIGNAL:\n  -Name "d1" -SignalType "DI" junk -Default 1\n  -Name "d2" -SignalType "DO\n'
    lenient = parse_cfg(text, "EIO.cfg", strict=False)
    assert [(i.name, i.text("default")) for i in lenient] == [("d1", "1"), ("d2", None)]
    with pytest.raises(RsxmlError, match=r"^EIO.cfg:2: 'junk' in EIO_SIGNAL is no attribute"):
        parse_cfg(text, "EIO.cfg")


def test_check_and_info_take_a_cell_file(capsys):
    """``rswarp check`` and ``rswarp info`` on a cell file: its verdict, its problems at their line
    (exit 1), and what stands where in the file's units (``--json``: SI)."""
    import json

    from rswarp.cli import main

    assert main(["check", str(CELLS / "track_positioner.toml")]) == 0
    assert "OK (Cell; 0 errors, 0 warnings)" in capsys.readouterr().out
    assert main(["check", str(CELLS / "bad_on.toml")]) == 1
    captured = capsys.readouterr()
    assert "FAILED (Cell; 1 error" in captured.out and f"{CELLS / 'bad_on.toml'}:4: " in captured.err
    assert main(["info", str(CELLS / "track_positioner.toml")]) == 0
    out = capsys.readouterr().out
    assert "on track's Carriage, frame [0, 0, 565, 0, 0, 90]" in out and "eax_b -> A1 (-90 .. 90 deg), eax_c -> A2 (-360 .. 360 deg)" in out
    assert main(["info", "--json", str(CELLS / "track_positioner.toml")]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["kind"] == "Cell" and doc["externals"][0]["axes"] == {"eax_a": "T1"}
    assert doc["robot"]["frame"][2][3] == pytest.approx(0.565)


@pytest.mark.parametrize("name", ["track_cell.toml", "positioner_cell.toml"])
def test_the_bundled_cells_check_clean(name, capsys):
    """The example cells (``examples/cells``): the IRB 2600 on the track, 400 mm up on its carriage,
    and beside the positioner; each checks with no error and no warning."""
    from rswarp import examples
    from rswarp.cli import main

    assert main(["check", str(examples.CELLS / name)]) == 0
    assert "OK (Cell; 0 errors, 0 warnings)" in capsys.readouterr().out
    cell = read_cell(str(examples.CELLS / name))
    assert cell.robot.mechanism.name == "IRB2600_12_165__01" and len(cell.externals) == 1


def test_every_problem_of_a_cell_file_is_said_at_its_line(tmp_path):
    """Five problems in five tables: all five, in line order, each at its line (a unit left out for
    its own problem does not make the robot's `on` a sixth)."""
    robot = DATA / "cells" / "robot.rsxml"
    path = tmp_path / "cell.toml"
    path.write_text(f'[robot]\nrsxml = "{robot}"\non = "track"\nfram = [0, 0, 0, 0, 0, 0]\n\n'
                    '[[external]]\nname = "track"\nrsxml = "nothere.rsxml"\naxes = ["eax_a"]\n\n'
                    f'[[external]]\nname = "stn"\nrsxml = "{DATA / "cells" / "positioner.rsxml"}"\n'
                    'axes = ["eax_g", "eax_b"]\n\n[tool]\npath = "gone.stl"\n\n'
                    '[[environment]]\nmesh = "gone2.stl"\non = "track"\n')
    with pytest.raises(RsxmlError) as err:
        read_cell(str(path))
    found = [(d.line, d.message.split(":")[0]) for d in err.value.diagnostics]
    assert found == [(4, "unknown key 'fram' in [robot]; did you mean 'frame'?"),
                     (8, "[[external]] 'track' rsxml"), (14, "[[external]] 'stn' axes"), (17, "[tool] path"),
                     (20, "[[environment]] 1 mesh")]
