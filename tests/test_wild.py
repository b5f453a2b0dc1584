"""RAPID as it is written in the wild (docs/program.md, shared/docs/RAPID-IN-THE-WILD.md): tasks under
tests/data/rapid/wild shaped like the programs that stopped rswarp, written here in their manner.

- live reads (SocketReceive, TPReadNum, UINumEntry, ReadNum, ReadAnyBin) store an unknown value; the
  run stops where the motion needs it, with every move before it planned and timed, and says which
  read and which ``--input`` gives it; given values are taken in order and the run goes on;
- every word of ABB's RAPID manual is known: what cannot change the motion runs silently, data by
  name (GetDataVal, SetDataVal, SetAllDataVal, SetDataSearch/GetNextSym, GetSysData/SetSysData) and
  the vector and string functions are computed; an option's procedure is one warning;
- limits as the controller applies them: Grasshopper's 200 000 mm/s at 7000 mm/s, eax_a 0 on a robot
  without a track ignored (one warning), MultiMove run as this task's robot, a positioner's work
  object still an error;
- names as the controller binds them: a name read and declared nowhere is a load error, a missing
  tool points at CalibData.mod, names used as signals are signals, a backup's EIO.cfg declares them,
  ISO 8859-1 letters in names (Windows-1252 and UTF-8 files)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

from rswarp.errors import RsxmlError
from rswarp.examples import IRB2600
from rswarp.motion.plan import program_plan
from rswarp.rapid.interpret import Interpreter
from rswarp.rapid.task import load_task
from rswarp.rapid.values import Arr, Rec
from rswarp.report.program import run_program

from conftest import DATA

WILD = DATA / "rapid" / "wild"
ROOT = Path(__file__).resolve().parents[1]


@lru_cache(maxsize=None)
def program(path: str, inputs: tuple = (), io: tuple = (), cycles: int = 1):
    """(JSON document, text, exit code, warnings) of ``rswarp program`` on the IRB 2600, run once a
    session for each set of options."""
    warned: list[str] = []
    out = run_program(str(IRB2600), [str(WILD / path)], io=list(io) or None, cycles=cycles,
                      inputs=list(inputs) or None, warn=warned.append)
    return out.doc, out.text, out.code, tuple(warned)


def moves(doc) -> list[dict]:
    """The moves of a run, waits left out."""
    return [m for m in doc["moves"] if m["kind"] != "wait"]


def at_line(doc, line: int) -> list[dict]:
    return [m for m in moves(doc) if m["line"] == line]


def mm(move) -> np.ndarray:
    """Where a move left the TCP in its work object, in mm."""
    assert move["tcp_m"] is not None and "error" not in move, move
    return np.array(move["tcp_m"]) * 1000


def near(move, want, tol: float = 0.5) -> bool:
    return float(np.linalg.norm(mm(move) - np.array(want, float))) < tol


def cli(*args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    return subprocess.run([sys.executable, "-m", "rswarp.cli", "program", str(IRB2600), *args], cwd=ROOT,
                          capture_output=True, text=True, env=env, timeout=300)


def interpret(path: Path):
    """The task run without a robot: (interpreter, run)."""
    interp = Interpreter(load_task([path]))
    return interp, interp.run("main")


def value(interp, name: str):
    """A data object's value after the run (the task's own before the predefined)."""
    cells = [s.get(name.lower()) for s in interp.scopes.values() if s.get(name.lower()) is not None]
    cell = next((c for c in cells if c.file), cells[0])
    v = cell.get()
    return v.items if isinstance(v, Arr) else list(v.vals) if isinstance(v, Rec) else v


# -- live reads ---------------------------------------------------------------------------------------------------

SOCKET = WILD / "socket_pick" / "PickServer.mod"
SOCKET_STOP = ("PickServer.mod:37: needs live input: SocketReceive into receive_string (read at line 31); "
               "--input receive_string=VALUE gives it")


def test_a_socket_loop_stops_where_the_motion_first_needs_what_the_socket_gives():
    """SocketReceive stores an unknown string; StrFind, StrPart and StrToVal of it stay unknown (no
    'StrPart: characters 2 to 0'), and so do x, y and pPick; the MoveJ to Offs(pPick, ...) needs it."""
    doc, text, code, warned = program("socket_pick")
    assert code == 0 and not doc["errors"]
    assert doc["stopped"] is not None and doc["stopped"].endswith(SOCKET_STOP)
    need = doc["needs_input"]
    assert {k: need[k] for k in ("name", "source", "line", "read_line")} == {
        "name": "receive_string", "source": "SocketReceive", "line": 37, "read_line": 31}
    assert Path(need["file"]).name == Path(need["read_file"]).name == "PickServer.mod"
    made = moves(doc)
    assert [m["line"] for m in made] == [26]  # the home move, planned and timed
    assert made[0]["end_s"] > made[0]["start_s"] and near(made[0], [900, 0, 900])
    assert SOCKET_STOP in text or any(w.endswith(SOCKET_STOP) for w in warned)
    assert not any("StrPart" in w or "StrFind" in w or "StrToVal" in w for w in (*warned, *doc["errors"]))


def test_a_socket_loop_makes_a_pass_for_each_value_given():
    """Two values of receive_string: the main loop runs on while values are left (past --cycles 1),
    two picks at the places they say, then the loop ends as a main loop does."""
    doc, _, code, warned = program("socket_pick", inputs=("receive_string=950,120", "receive_string=1000,-150"))
    assert code == 0 and not doc["errors"]
    assert doc["stopped"] is None and len(doc["cycles_s"]) == 2
    assert len(moves(doc)) == 1 + 2 * 6
    picks = at_line(doc, 38)
    assert len(picks) == 2 and near(picks[0], [950, 120, 400]) and near(picks[1], [1000, -150, 400])
    places = at_line(doc, 43)
    assert len(places) == 2 and all(near(m, [850, -300, 450]) for m in places)
    assert not any("--input receive_string" in w for w in warned)


def test_the_command_line_says_the_live_input_and_an_input_never_read():
    run = cli(str(WILD / "socket_pick"), "--json", "--input", "nobody=3")
    assert run.returncode == 0, run.stderr
    doc = json.loads(run.stdout)
    assert doc["stopped"].endswith(SOCKET_STOP) and doc["needs_input"]["name"] == "receive_string"
    assert f"{SOCKET}:37: needs live input: SocketReceive into receive_string" in run.stderr
    assert "--input nobody" in run.stderr


OPERATOR_FULL = ("nLayers=3", "nHeight=60", "ReadNum=25", "vShift=[50,-100,200]")


def test_operator_reads_stop_at_the_loop_bound_they_decide():
    doc, _, code, _ = program("operator.mod")
    assert code == 0 and [m["line"] for m in moves(doc)] == [14]
    need = doc["needs_input"]
    assert (need["name"], need["source"], need["line"], need["read_line"]) == ("nLayers", "TPReadNum", 23, 15)


@pytest.mark.parametrize("offset", ["ReadNum=25", "nOffset=25"])
def test_operator_reads_take_the_values_given_by_data_or_function_name(offset):
    """TPReadNum's answer by its variable, UINumEntry by the data it is assigned to, ReadNum by either;
    the record ReadAnyBin reads is still unknown and stops the move that needs it."""
    doc, _, code, _ = program("operator.mod", inputs=("nLayers=3", "nHeight=60", offset))
    assert code == 0
    need = doc["needs_input"]
    assert (need["name"], need["source"], need["line"], need["read_line"]) == ("vShift", "ReadAnyBin", 26, 21)
    layers = at_line(doc, 24)
    assert len(layers) == 3 and all(near(m, [1025, 0, 400 + 60 * k]) for k, m in enumerate(layers))


def test_operator_reads_given_every_value_run_to_the_end():
    doc, _, code, warned = program("operator.mod", inputs=OPERATOR_FULL)
    assert code == 0 and doc["stopped"] is None and doc["needs_input"] is None
    assert len(moves(doc)) == 1 + 3 + 2 and near(at_line(doc, 26)[0], [1050, -100, 600])
    assert not any("--input" in w for w in warned)


# -- every RAPID word known -----------------------------------------------------------------------------------------

def test_words_that_cannot_change_the_motion_are_silent_and_an_options_procedure_is_one_warning():
    """File I/O, RenameFile, raw bytes, ErrLog, TPWrite, IError run as nothing without a word;
    CellGripAction (a cell module's, absent) is skipped with one warning for its two calls; PmGetPartCount,
    a function no one defines, is unknown and harms nothing the motion does not need."""
    path = WILD / "silent_words.mod"
    _, run = interpret(path)
    assert run.stopped is None and sum(m.kind != "wait" for m in run.motions) == 3
    assert not [w for w in run.warnings if 20 <= w.line <= 29], [str(w) for w in run.warnings]
    options = [w for w in run.warnings if "CellGripAction" in w.message]
    assert len(options) == 1 and options[0].line == 30


def test_an_unknown_function_stops_the_run_only_where_the_motion_needs_it(tmp_path):
    path = tmp_path / "count.mod"
    path.write_text((WILD / "silent_words.mod").read_text().replace(
        "    MoveL pB,v500,fine,tool0;\n", "    IF nParts>0 MoveL pB,v500,fine,tool0;\n"))
    _, run = interpret(path)
    assert run.stopped is not None and run.stopped.line == 32
    assert sum(m.kind != "wait" for m in run.motions) == 1


def test_data_by_name_reaches_each_target_it_names():
    """GetDataVal "p"+NumToStr(i,0), SetDataVal, SetDataSearch/GetNextSym over "p.*" (the four
    points, in any order), SetAllDataVal (both lifts to 0), GetSysData/SetSysData (the active tool)."""
    doc, _, code, _ = program("data_by_name.mod")
    assert code == 0 and not doc["errors"] and doc["stopped"] is None
    p = {1: [900, -200, 500], 2: [1000, -100, 550], 3: [1050, 100, 600], 4: [950, 250, 650]}
    by_number = at_line(doc, 31)
    assert len(by_number) == 4 and all(near(m, p[k + 1]) for k, m in enumerate(by_number))
    assert near(at_line(doc, 36)[0], np.add(p[4], [0, 0, 100]))
    searched = at_line(doc, 41)
    assert len(searched) == 4
    assert sorted(tuple(np.round(mm(m))) for m in searched) == sorted(tuple(map(float, v)) for v in p.values())
    assert near(at_line(doc, 46)[0], p[1])  # SetAllDataVal set nLift1 and nLift2 to 0
    assert near(at_line(doc, 48)[0], p[2])
    assert near(at_line(doc, 50)[0], np.add(p[3], [0, 0, 120]))  # GetSysData: tGrip, the last move's tool
    assert near(at_line(doc, 53)[0], np.add(p[4], [0, 0, 50]))  # after SetSysData tool0


def test_vectors_strings_and_two_dimensional_arrays_compute_as_rapid_does():
    interp, run = interpret(WILD / "vectors.mod")
    assert run.stopped is None
    assert value(interp, "vZ") == [0, 0, 1]  # pos * pos: the vector product
    assert value(interp, "vX") == [1, 0, 0]  # CrossProd([0,1,0],[0,0,1])
    assert value(interp, "vRead") == pytest.approx([600, 500, 225.3])
    assert value(interp, "nRead") == 42.5 and value(interp, "bRead") is True
    assert [value(interp, n) for n in ("ok1", "ok2", "ok3")] == [True, True, True]
    assert value(interp, "nMatch") == 7 and value(interp, "nNoMatch") == 6
    assert value(interp, "sMapped") == "1.2.3"
    assert value(interp, "nBefore") == 6 and value(interp, "grid") == [0, 0, 2, 1, 0, 0]


def test_vectors_decide_where_the_moves_end():
    doc, _, code, _ = program("vectors.mod")
    assert code == 0 and len(moves(doc)) == 3
    assert near(at_line(doc, 37)[0], [1000, 100, 600])  # grid{2,1}*100, grid{1,3}*50, vZ.z*100
    assert near(at_line(doc, 39)[0], [950, 0, 542.5])  # vX.x*50, vRead.x-600, nRead


# -- limits as the controller applies them ------------------------------------------------------------------------

def test_grasshopper_speeds_run_at_the_top_tcp_speed_and_eax_a_0_is_ignored():
    warned: list[str] = []
    _, p = program_plan(str(IRB2600), [str(WILD / "grasshopper.mod")], warn=warned.append)
    made = [mv for mv in p.moves if mv.motion.kind != "wait"]
    assert not p.errors and len(made) == 21
    assert all(mv.motion.speed.v_tcp == pytest.approx(7.0) for mv in made)
    for before, mv in zip(made, made[1:]):  # never faster than 7 m/s along the line
        a, b = before.motion.targets[-1].pose.trans, mv.motion.targets[-1].pose.trans
        assert mv.end - mv.start >= np.linalg.norm(np.subtract(b, a)) / 7.0 - 1e-6
    assert sum("vGH" in w for w in warned) == 1
    assert sum("[1000000,1000,5000,1000]" in w for w in warned) == 1
    axes = [w for w in warned if "eax_a" in w]
    assert len(axes) == 1 and "21 targets give eax_a (0)" in axes[0]


def test_grasshopper_targets_say_the_axis_was_ignored_and_end_where_written():
    doc, _, code, _ = program("grasshopper.mod")
    assert code == 0 and not doc["errors"] and len(moves(doc)) == 21
    assert doc["targets"] and all(t["ignored"] and "eax_a" in str(t["ignored"]) for t in doc["targets"])
    assert near(moves(doc)[-1], [1000, 0, 750])
    assert doc["duration_s"] < 10


def test_external_axes_error_refuses_eax_a():
    with pytest.raises(RsxmlError, match="eax_a"):
        program_plan(str(IRB2600), [str(WILD / "grasshopper.mod")], external_axes="error")


def test_multimove_runs_this_tasks_robot_with_one_warning():
    doc, _, code, warned = program("multimove")
    assert code == 0 and not doc["errors"]
    assert [m["line"] for m in moves(doc)] == [20, 23, 24, 25, 27]
    assert near(at_line(doc, 25)[0], [1000, 200, 600]) and near(at_line(doc, 27)[0], [900, 0, 1000])
    assert sum("MultiMove" in w for w in warned) == 1


def test_a_work_object_a_positioner_moves_is_still_an_error_naming_it():
    with pytest.raises(RsxmlError, match="STN1") as exc:
        program_plan(str(IRB2600), [str(WILD / "positioner.mod")])
    assert "positioner.mod" in str(exc.value)


# -- names as the controller binds them ---------------------------------------------------------------------------

def test_a_name_read_and_declared_nowhere_is_a_load_error_at_its_line():
    path = WILD / "undeclared.mod"
    run = cli(str(path))
    assert run.returncode == 1
    line = next(x for x in run.stderr.splitlines() if ":8: " in x)
    assert line.split(":8: ")[0].endswith("undeclared.mod")
    assert "'nApproach'" in line and "declared nowhere" in line


def test_a_missing_tool_is_said_to_be_a_tooldata_of_calibdata():
    with pytest.raises(RsxmlError) as exc:
        interpret(WILD / "missing_tool.mod")
    assert exc.value.line == 12
    said = exc.value.message
    assert "tSuction" in said and "tooldata" in said and "CalibData.mod" in said


@pytest.mark.parametrize("io, lines", [
    ((), [10, 17]),
    (("diPartReady=1",), [10, 12, 17]),
    (("diInspect=1",), [10, 15, 17]),
])
def test_names_used_as_signals_anywhere_are_signals_read_bare(io, lines):
    """SetDO, WaitDI and DInput in a routine never called make doGrip, diPartReady and diInspect
    signals: read bare in main, 0 unless --io sets them."""
    doc, _, code, _ = program("signals_by_use.mod", io=io)
    assert code == 0 and [m["line"] for m in moves(doc)] == lines


def test_a_backups_io_configuration_declares_its_signals_at_their_defaults():
    """EIO.cfg: diStart and diPartReady default 1 (one entry continued with a backslash), diReject 0;
    each read bare in the task. The device, the cross connection and the system signals are not
    signals of their own."""
    doc, _, code, warned = program("backup")
    assert code == 0 and not doc["errors"]
    assert [m["line"] for m in moves(doc)] == [18, 30, 31, 34, 35, 36, 38, 26]
    assert near(at_line(doc, 31)[0], [950, -150, 450]) and near(at_line(doc, 36)[0], [1000, 200, 700])
    config = [w for w in warned if "EIO.cfg" in w]
    assert len(config) == 1 and "7 signals" in config[0]
    reject, _, _, _ = program("backup", io=("diReject=1", "diPartReady=0"))
    assert [m["line"] for m in moves(reject)] == [18, 30, 34, 35, 36, 38, 23, 24, 26]
    assert near(at_line(reject, 24)[0], [800, -300, 500])


@pytest.mark.parametrize("path, target, end", [
    ("latin1.mod", "Offs(rPosición,0,0,nAltura)", [1000, 100, 600]),
    ("utf8_names.mod", "Offs(pÜbergabe,0,0,größe)", [950, -100, 580]),
])
def test_names_with_iso_8859_1_letters_are_names(path, target, end):
    raw = (WILD / path).read_bytes()
    assert (b"\xd6" in raw) == (path == "latin1.mod")  # Ö in Windows-1252, not UTF-8
    doc, _, code, _ = program(path)
    assert code == 0 and not doc["errors"]
    last = moves(doc)[-1]
    assert last["target"] == target and near(last, end)


def test_a_hose_run_over_a_program_that_stopped_says_over_what_it_ran(tmp_path):
    """The cables run over the moves before a live input; the report and the text say so."""
    from rswarp.examples import IRB2600_DRESSPACK
    from rswarp.report.cables import run_cables

    out = run_cables(str(IRB2600_DRESSPACK), str(tmp_path / "hose"), program=[str(SOCKET.parent)], frame_rate=30.0)
    assert out.doc["program_stopped"].endswith(SOCKET_STOP) and out.doc["needs_input"]["name"] == "receive_string"
    assert "program stopped: " in out.text and "not the whole program" in out.text


def test_confj_off_takes_the_solution_reached_soonest_not_a_flip_over_the_top():
    """On the dress-pack robot (J4 within ±90°) the pick's nearest solution by squared travel was a
    flip over the top (J1 +77°, J3 -172°: 2.66 s); the one reached soonest turns J6 instead (1.1 s)."""
    from rswarp.examples import IRB2600_DRESSPACK

    out = run_program(str(IRB2600_DRESSPACK), [str(WILD / "confj_off.mod")])
    pick = [m for m in out.doc["moves"] if m["line"] == 11][0]
    assert abs(np.degrees(pick["joints"][0]) + 26) < 2 and abs(np.degrees(pick["joints"][2])) < 45
    assert pick["end_s"] - pick["start_s"] < 1.3


def test_a_hose_run_over_a_task_that_stops_before_its_first_move_says_what_it_needs(tmp_path):
    from rswarp.examples import IRB2600_DRESSPACK
    from rswarp.report.cables import run_cables

    path = tmp_path / "s0.mod"
    path.write_text("MODULE S\n  VAR socketdev sock;\n  VAR string s;\n  VAR num x;\n  VAR bool ok;\n  PROC main()\n"
                    "    SocketReceive sock \\Str:=s;\n    ok := StrToVal(s, x);\n"
                    "    MoveJ [[x,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v1000, fine, tool0;\n"
                    "  ENDPROC\nENDMODULE\n")
    with pytest.raises(RsxmlError, match=r"needs live input: SocketReceive into s .* --input s=VALUE gives it \(the "
                                         r"task stops before its first move") as exc:
        run_cables(str(IRB2600_DRESSPACK), str(tmp_path / "hose"), program=[str(path)])
    assert exc.value.line == 9 and not (tmp_path / "hose").exists()
