"""MultiMove from the command line (issue "Real programs in real cells"): a cell file with a
``[[robot]]`` for each robot of a backup (``tests/data/cell_moc/multimove_cell.toml``, over the
two-robot backup ``tests/data/rapid/wild/multimove``: ROB_1 carries, ROB_2 welds), each robot placed
by the backup's MOC.cfg and running its own task, on one clock, checked against the other."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

from rswarp.cli import main
from rswarp.errors import RsxmlError
from rswarp.examples import IRB2600
from rswarp.kinematics.kinematics import Kinematics
from rswarp.report.program import run_program
from rswarp.rsxml.cell import read_cell

from conftest import DATA

CELL = DATA / "cell_moc" / "multimove_cell.toml"
BACKUP = DATA / "rapid" / "wild" / "multimove"
TRACKS = DATA / "moc" / "multimove"  # ROB_1 on TRACK_1, ROB_2 beside the positioner STN1


def test_each_robot_of_the_backup_stands_where_its_moc_puts_it_and_runs_its_own_task():
    cell = read_cell(str(CELL))
    rob1, rob2 = cell.team
    assert (rob1.robot.name, rob1.robot.task, rob2.robot.name, rob2.robot.task) == \
        ("ROB_1", "T_ROB1", "ROB_2", "T_ROB2")  # tasks from SYS.cfg's mechanical unit groups
    assert np.allclose(rob1.robot.frame, np.eye(4))
    turned = np.diag([-1.0, -1.0, 1.0, 1.0])  # MOC.cfg: x 2.6 m, q [0, 0, 0, 1] (180 deg about z)
    turned[0, 3] = 2.6
    assert np.allclose(rob2.robot.frame, turned, atol=1e-9)
    assert cell.robot is rob1.robot  # a command that takes one robot takes the first


def test_the_program_runs_both_tasks_on_one_clock_each_target_where_the_world_has_it(capsys):
    assert main(["program", str(CELL), str(BACKUP), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    rob1, rob2 = doc["robots"]
    assert [r["task"] for r in doc["robots"]] == ["T_ROB1", "T_ROB2"]
    wait = doc["meetings"][0]  # ROB_2 waits at sync1 while ROB_1 goes home
    assert (wait["ident"], wait["kind"]) == ("sync1", "wait")
    assert wait["waited_s"]["ROB_2"] == pytest.approx(rob1["moves"][0]["end_s"], abs=1e-9)
    assert wait["waited_s"]["ROB_2"] > 0.2 and wait["waited_s"]["ROB_1"] == 0.0
    sync = [[m for m in r["moves"] if m["instruction"] == "MoveL"] for r in (rob1, rob2)]
    for a, b in zip(*sync):  # \ID 10, 20, 30: start together, end together
        assert a["start_s"] == pytest.approx(b["start_s"], abs=1e-9)
        assert a["end_s"] == pytest.approx(b["end_s"], abs=1e-9)
    # ROB_1's first synchronized move is slowed to ROB_2's v100 weld, and says so
    assert sync[0][0]["limited_by"]["limit"] == "synchronized" and sync[0][0]["limited_by"]["robots"] == ["ROB_2"]
    assert doc["duration_s"] == pytest.approx(rob1["moves"][-1]["end_s"], abs=1e-6)
    # ROB_2 stands at x 2.6 m turned about z: its TCP reaches the weld's world point (1500, 100, 600) mm
    cell = read_cell(str(CELL)).team[1]
    kin = Kinematics(cell.robot.mechanism)
    q = np.array(sync[1][0]["joints"])
    link, offset = kin.flange_frame()
    tcp = cell.robot.frame @ kin.fk64(q[None])[0, link] @ offset
    assert np.allclose(tcp[:3, 3], [1.5, 0.1, 0.6], atol=1e-4)
    assert doc["clashes"] == []


def test_robots_whose_targets_meet_clash_and_the_report_says_which_links_and_when(tmp_path, capsys):
    backup = tmp_path / "backup"  # ROB_2 welds at x 1.05 m, where ROB_1 carries the part (x 1.0 m)
    shutil.copytree(BACKUP, backup)
    weld = backup / "RAPID" / "T_ROB2" / "PROGMOD" / "MM_Rob2.mod"
    weld.write_bytes(weld.read_bytes().replace(b"[[1500,", b"[[1050,"))
    close = tmp_path / "close.toml"
    close.write_text(CELL.read_text().replace("../rapid/wild/multimove", backup.as_posix())
                     .replace("../../../examples", IRB2600.resolve().parent.parent.as_posix()))
    out = run_program(str(close), [str(backup)])
    assert out.code == 0 and out.doc["clashes"]
    first = out.doc["clashes"][0]
    assert first["first"].startswith("ROB_1.") and first["second"].startswith("ROB_2.")
    assert 0.0 < first["time_s"] < out.doc["duration_s"] and first["span_s"] > 0.0
    assert "robots against each other:" in out.text and f"{first['first']} and {first['second']}" in out.text


def test_task_picks_one_robot_and_options_of_one_robot_need_it(tmp_path, capsys):
    assert main(["program", str(CELL), str(BACKUP), "--task", "ROB_2", "--json"]) == 0
    alone = json.loads(capsys.readouterr().out)
    assert {m["file"].rsplit("/", 1)[-1] for m in alone["moves"]} == {"MM_Rob2.mod"}
    assert main(["program", str(CELL), str(BACKUP), "--csv", str(tmp_path / "t.csv")]) == 1
    err = capsys.readouterr().err
    assert "--csv is one robot's, and the cell has several: give --task NAME" in err
    assert not (tmp_path / "t.csv").exists()
    assert main(["program", str(CELL), str(BACKUP), "--task", "T_ROB3"]) == 1
    assert "--task T_ROB3: no robot of the cell runs it (its robots: ROB_1 (T_ROB1), ROB_2 (T_ROB2))" in \
        capsys.readouterr().err


def test_a_team_needs_the_backups_tasks(capsys):
    module = BACKUP / "RAPID" / "T_ROB1" / "PROGMOD" / "MM_Rob1.mod"
    assert main(["program", str(CELL), str(module)]) == 1
    assert "a cell of 2 robots runs each robot's task of a backup" in capsys.readouterr().err


def test_each_task_has_its_own_external_axes_and_units_go_to_the_robot_that_drives_them(tmp_path):
    cell = tmp_path / "tracks.toml"
    examples = IRB2600.resolve().parent.parent
    cell.write_text(f'backup = "{TRACKS.resolve().as_posix()}"\n'
                    f'[[robot]]\nrsxml = "{IRB2600.resolve().as_posix()}"\nunit = "ROB_1"\non = "track"\n'
                    f'[[robot]]\nrsxml = "{IRB2600.resolve().as_posix()}"\nunit = "ROB_2"\ndrives = ["stn1"]\n'
                    f'[[external]]\nname = "track"\nrsxml = "{(examples / "track/IRBT2005_4m.rsxml").as_posix()}"\n'
                    'axes = ["eax_a"]\n'
                    f'[[external]]\nname = "stn1"\nrsxml = "{(examples / "positioner/IRBP_A250.rsxml").as_posix()}"\n'
                    'frame = [1800, 2200, 0, 0, 0, 0]\naxes = ["eax_a", "eax_b"]\n')
    rob1, rob2 = read_cell(str(cell)).team
    assert [e.name for e in rob1.externals] == ["track"] and [e.name for e in rob2.externals] == ["stn1"]
    assert rob1.mapping["eax_a"] == ("track", rob1.externals[0].joints[0])
    assert rob2.mapping["eax_a"][0] == "stn1" and rob1.robot.on == "track"


@pytest.mark.parametrize("tables, message", [
    ('[[robot]]\nrsxml = "R"\nname = "A"\n[[robot]]\nrsxml = "R"\nname = "a"\n',
     r":6: \[\[robot\]\] 2 name: 'a' is also \[\[robot\]\] 1's: give each robot its own name"),
    ('[[robot]]\nrsxml = "R"\ndrives = ["stn"]\n',
     r":3: \[\[robot\]\] 1 drives 'stn': no \[\[external\]\] of that name"),
    ('[[robot]]\nrsxml = "R"\ntask = 3\n', r":3: \[\[robot\]\] 1 task: give it as text, not 3"),
])
def test_a_team_cell_file_with_a_fault_names_its_line(tmp_path, tables, message):
    cell = tmp_path / "bad.toml"
    cell.write_text(tables.replace('"R"', f'"{IRB2600.resolve().as_posix()}"'))
    with pytest.raises(RsxmlError, match=message):
        read_cell(str(cell))
