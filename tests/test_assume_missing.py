"""Real programs whose repositories lack their configuration (issue "Real programs in real
cells"): ``--assume-missing`` runs a task whose tools, work objects, speeds and signals live in
modules never committed, each stand-in said once; without it the load error names the flag. A
run-time error stops the task at its line as the controller stops, every move before it planned,
timed and checked."""

from __future__ import annotations

import json

import pytest

from rswarp.cli import main
from rswarp.errors import RsxmlError
from rswarp.examples import IRB2600
from rswarp.motion.plan import program_plan
from rswarp.report.program import run_program

from conftest import DATA

WILD = DATA / "rapid" / "wild"


def test_without_the_flag_the_load_error_stays_and_names_the_flag(capsys):
    assert main(["program", str(IRB2600), str(WILD / "lacks")]) == 1
    err = capsys.readouterr().err
    assert "'Tool_27' is declared nowhere in the task: a tooldata here" in err
    assert "'vGlue' is declared nowhere" in err
    for line in err.splitlines():
        if "declared nowhere" in line and "did you mean" not in line:  # a near name is a typo: no stand-in offered
            assert "--assume-missing runs it with a stand-in" in line


def test_stand_ins_by_use_each_said_once_with_its_first_line():
    out = run_program(str(IRB2600), [str(WILD / "lacks")], assume_missing=True)
    assert out.code == 0
    assumed = {a["name"]: a for a in out.doc["assumed"]}
    assert {k: (a["type"], a["line"]) for k, a in assumed.items()} == {
        "Tool_27": ("tooldata", 15), "Workobject_Chapa": ("wobjdata", 15), "vMedium": ("speeddata", 15),
        "vGlue": ("speeddata", 16), "nBatchSize": ("num", 23)}
    assert assumed["vMedium"]["value"] == "v1000" and assumed["Tool_27"]["value"] == "tool0"
    assert assumed["Tool_27"]["uses"] == 5
    moves = [m for m in out.doc["moves"] if m["kind"] != "wait"]
    assert len(moves) == 5 and all(m["assumed"] for m in moves)
    assert sorted(moves[1]["assumed"]) == ["Tool_27", "Workobject_Chapa", "vGlue"]
    # a speeddata v1000: the glue line (240 mm) at 1 m/s at most, as the stand-in says
    glue = next(m for m in moves if m["line"] == 18)
    assert glue["tcp_speed"]["programmed_m_s"] == pytest.approx(1.0)
    assert "assumed: 5 names declared nowhere" in out.text and "Tool_27: a tooldata as tool0" in out.text


def test_a_finding_of_a_move_that_uses_a_stand_in_says_so(capsys):
    code = main(["program", str(IRB2600), str(WILD / "lacks"), "--assume-missing", "--floor", "0.5", "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 0
    below = [f for m in doc["moves"] for f in m["findings"] if f["kind"] == "floor"]
    assert below and all("Tool_27" in f["assumed"] for f in below)
    main(["program", str(IRB2600), str(WILD / "lacks"), "--assume-missing", "--floor", "0.5"])
    text = capsys.readouterr().out
    assert "(the move uses the stand-in Tool_27, Workobject_Chapa" in text


def test_a_target_declared_nowhere_stays_an_error(tmp_path):
    module = tmp_path / "t.mod"
    module.write_text("MODULE T\n  PROC main()\n    MoveL pNowhere, v100, fine, tool0;\n  ENDPROC\nENDMODULE\n")
    with pytest.raises(RsxmlError, match="'pNowhere' is declared nowhere in the task: a robtarget here"):
        program_plan(str(IRB2600), [str(module)], assume_missing=True)


def test_a_run_time_error_stops_the_task_there_with_every_move_before_it(capsys):
    path = WILD / "divzero" / "Calib.mod"
    out = run_program(str(IRB2600), [str(path)])
    assert out.code == 1 and out.errors == (f"{path}:19: division by zero",)
    error = out.doc["error"]
    assert (error["line"], error["message"]) == (19, "division by zero")
    assert error["chain"] == [f"main ({path}:13)", f"Measure ({path}:19)"]
    assert [m["line"] for m in out.doc["moves"]] == [11, 12]
    assert out.doc["moves"][1]["end_s"] > 0.5 and out.doc["cycle_s"] is None
    assert "called from main" in out.text
    with pytest.raises(RsxmlError, match="Calib.mod:19: division by zero"):
        program_plan(str(IRB2600), [str(path)])  # the Python API still raises it
    assert main(["program", str(IRB2600), str(path)]) == 1
    assert "Calib.mod:19: division by zero" in capsys.readouterr().err


def test_a_run_time_error_before_the_first_move_is_that_error_not_a_crash(tmp_path, capsys):
    module = tmp_path / "e.mod"
    module.write_text("MODULE E\n  PROC main()\n    reg1 := 1 / 0;\n    MoveJ [[900,0,900],[0,0,1,0],[0,0,0,0],"
                      "[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;\n  ENDPROC\nENDMODULE\n")
    assert main(["program", str(IRB2600), str(module), "--json"]) == 1
    out = capsys.readouterr()
    assert json.loads(out.out)["moves"] == [] and f"{module}:3: division by zero" in out.err
