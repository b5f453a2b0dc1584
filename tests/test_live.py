"""RAPID as real programs write it, without a robot (issue "Real RAPID programs run"): live reads
stored as unknown values that stop the run only where the motion needs them, ``--input`` giving
them; data by name; the string and vector functions as the reference manual defines them; names
of ISO 8859-1 letters; a backup's I/O configuration; names bound as the controller binds them; the
controller's limits (a TCP speed above the top speed, MultiMove) said once, never refused."""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_rapid import module, value

from rswarp.errors import RsxmlError
from rswarp.rapid.interpret import Interpreter
from rswarp.rapid.task import load_task

from conftest import DATA

LIVE = DATA / "rapid" / "live"


def run(*paths, inputs=None, io=None, cycles=1):
    interp = Interpreter(load_task(list(paths)), io=io, cycles=cycles, inputs=inputs)
    return interp, interp.run()


def test_a_socket_read_stops_the_run_where_the_motion_needs_it_with_the_moves_before():
    _, r = run(LIVE / "socket_pick.mod")
    assert [m.instruction for m in r.motions] == ["MoveJ"]  # the home move before the loop stands
    assert (r.stopped.line, r.needs_input["read_line"]) == (21, 15)  # needed by the move, read by SocketReceive
    assert r.needs_input["name"] == "receive_string" and r.needs_input["source"] == "SocketReceive"
    assert "needs live input: SocketReceive into receive_string" in r.stopped.message
    assert "--input receive_string=VALUE" in r.stopped.message


def test_inputs_are_taken_in_order_one_a_read_and_the_run_goes_on_with_them():
    _, r = run(LIVE / "socket_pick.mod", inputs={"receive_string": ["900,100", "950,-100"]}, cycles=3)
    picks = [m.targets[0].pose.trans for m in r.motions[1:]]
    np.testing.assert_allclose(picks, [(0.9, 0.1, 0.7), (0.9, 0.1, 0.6), (0.95, -0.1, 0.7), (0.95, -0.1, 0.6)],
                               rtol=1e-6, atol=1e-12)  # pytest.approx's tolerance
    assert r.stopped.line == 21 and r.cycle.starts == (1, 3, 5)  # the third pass has no input: two whole passes


def test_what_the_cell_answers_is_unknown_until_given_and_never_a_symptom(tmp_path):
    path = module(tmp_path, "MODULE M\n  VAR iodev f;\n  VAR string s;\n  VAR num n;\n  PROC main()\n"
                            "    s := ReadStr(f);\n    n := StrLen(StrPart(s, 2, StrLen(s) - 3));\n"
                            "    TPReadNum reg1, \"How many?\";\n    IF n > reg1 THEN\n      reg2 := 1;\n    ENDIF\n"
                            "    reg3 := OptionFunc(1);\n  ENDPROC\nENDMODULE\n")
    _, r = run(path)  # StrPart of what ReadStr would give: unknown, not "characters 2 to -2 of a string of 0"
    assert r.stopped.line == 9 and r.needs_input["name"] == "s" and r.needs_input["source"] == "ReadStr"
    interp, r = run(path, inputs={"s": ["abcdef"], "reg1": ["2"]})
    assert r.stopped is None and value(interp, "n") == 3 and value(interp, "reg2") == 1
    assert isinstance(value(interp, "reg3"), object)  # a function no one defines: unknown, and nothing needs it


def test_an_input_not_of_the_datas_type_is_an_error_at_the_read(tmp_path):
    path = module(tmp_path, "MODULE M\n  PROC main()\n    TPReadNum reg1, \"n?\";\n  ENDPROC\nENDMODULE\n")
    with pytest.raises(RsxmlError, match=r"--input reg1=abc: reg1 is a num") as exc:
        run(path, inputs={"reg1": ["abc"]})
    assert exc.value.line == 3
    _, r = run(path, inputs={"reg1": ["1"], "nCount": ["2"]})
    assert any("--input nCount: the task reads no live input into that name" in w.message for w in r.warnings)


def test_data_by_name_reaches_the_named_objects_and_a_missing_one_is_err_sym_access():
    interp, r = run(LIVE / "data_by_name.mod")
    ends = [m.targets[0].pose.trans for m in r.motions]
    np.testing.assert_allclose(ends, [(0.9, -0.2, 0.6), (0.9, 0.0, 0.6), (0.9, 0.2, 0.6)], rtol=1e-6, atol=1e-12)
    assert value(interp, "nSpeed") == 250 and value(interp, "nFound") == 3  # p1, p2, p3; pTemp matches no pattern


def test_string_and_vector_functions_as_the_manual_defines_them():
    interp, _ = run(LIVE / "strings_vectors.mod")
    assert value(interp, "sPos") == "[100,250.5,0]" and value(interp, "sThird") == "0.333333"
    assert (value(interp, "sRound"), value(interp, "sNeg"), value(interp, "sBig")) == ("0.313", "-3", "1.23457E+06")
    assert value(interp, "c1") == [0, 0, 250.5]  # pos * pos is the vector product: x cross p
    assert value(interp, "c2") == [1, 0, 0]
    assert value(interp, "q") == pytest.approx([600, 500, 225.3]) and value(interp, "okPos")
    assert value(interp, "n") == 3.85 and value(interp, "b") is True and not value(interp, "okBad")
    assert (value(interp, "at"), value(interp, "atNone"), value(interp, "sMapped")) == (9, 6, "XYc")
    assert value(interp, "grid") == [0, 0, 2, 1, 0, 0] and value(interp, "nGrid") == 12
    assert value(interp, "nCube") == 6


def test_frames_fitted_to_points_meet_them():
    interp, _ = run(LIVE / "frames_fitted.mod")
    f = value(interp, "f")  # the points turned 90 deg about z and moved by (10, 20, 30)
    assert list(f[0].vals) == pytest.approx([10, 20, 30], abs=1e-9)
    assert list(f[1].vals) == pytest.approx([math.sqrt(0.5), 0, 0, math.sqrt(0.5)], abs=1e-9)
    g = value(interp, "g")  # four points on a circle of 100 mm about (500, 0, 0), turning about +z
    assert list(g[0].vals) == pytest.approx([500, 0, 0], abs=1e-9) and list(g[1].vals) == pytest.approx([1, 0, 0, 0])
    assert value(interp, "mx") == pytest.approx(0, abs=1e-9)


def test_names_of_iso_8859_1_letters_read_in_latin_1_and_utf_8(tmp_path):
    interp, _ = run(LIVE / "latin1_names.mod")
    assert value(interp, "rPosición") == 6
    utf8 = tmp_path / "utf8.mod"
    utf8.write_text((LIVE / "latin1_names.mod").read_bytes().decode("latin-1"), encoding="utf-8")
    interp, _ = run(utf8)
    assert value(interp, "varÖlcüm") == 3
    with pytest.raises(RsxmlError, match="unexpected"):  # not a letter of ISO 8859-1: not a name
        run(module(tmp_path, "MODULE M\n  VAR num varşey;\nENDMODULE\n", "tr.mod"))


def test_a_backups_io_configuration_makes_its_signals_known_at_their_defaults():
    interp, r = run(LIVE / "backup")
    assert value(interp, "nMode") == 2  # diMode's default
    assert [m.instruction for m in r.motions] == ["MoveJ", "MoveL"]  # diSafe 1 by default, diPartReady 0
    notes = [w for w in r.warnings if w.file.endswith("EIO.cfg")]
    assert len(notes) == 1 and "4 signals read" in notes[0].message
    _, r = run(LIVE / "backup", io={"diSafe": 0})
    assert not r.motions


def test_a_name_read_as_data_and_declared_nowhere_is_a_load_error_saying_what_it_is(tmp_path):
    path = module(tmp_path, "MODULE M\n  CONST robtarget p:=[[900,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n"
                            "  PROC main()\n    MoveL Offs(p, 0, 0, 100), v100, fine, tool0;\n  ENDPROC\n"
                            "  PROC Unused()\n    MoveL Offs(p, 0, 0, nApproach), v100, fine, tool0;\n  ENDPROC\n"
                            "ENDMODULE\n")
    with pytest.raises(RsxmlError, match="'nApproach' is declared nowhere in the task") as exc:
        run(path)  # in a routine that never runs: the controller would not load the task
    assert exc.value.line == 7
    tool = module(tmp_path, "MODULE M\n  CONST robtarget p:=[[900,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];"
                            "\n  PROC main()\n    MoveL p, v100, fine, tGun;\n  ENDPROC\nENDMODULE\n", "tool.mod")
    with pytest.raises(RsxmlError, match=r"'tGun' is declared nowhere in the task: a tooldata here \(tools usually "
                                         r"live in CalibData.mod or user.sys"):
        run(tool)
    target = module(tmp_path, "MODULE M\n  PROC main()\n    MoveL RelTool(pDrop, 0, 0, -50), v100, fine, tool0;\n"
                              "  ENDPROC\nENDMODULE\n", "target.mod")
    with pytest.raises(RsxmlError, match="'pDrop' is declared nowhere in the task: a robtarget here"):
        run(target)


def test_signals_and_mechanical_units_are_known_where_rapid_expects_them(tmp_path):
    path = module(tmp_path, "MODULE M\n  PROC main()\n    IF diGo = 1 reg1 := 1;\n    WaitDI diGo, 0;\n"
                            "    ActUnit STN1;\n    IF IsMechUnitActive(STN1) reg2 := 1;\n  ENDPROC\nENDMODULE\n")
    interp, _ = run(path, io={"diGo": 1})
    assert value(interp, "reg1") == 1


def test_the_controllers_limits_are_warnings_said_once_never_refusals(tmp_path):
    target = "[[900,0,600],[0,0,1,0],[0,0,0,0],[0,9E9,9E9,9E9,9E9,9E9]]"
    path = module(tmp_path, "MODULE M\n  CONST speeddata vGH := [200000,500,5000,1000];\n  VAR syncident s1;\n"
                            "  PERS tasks all{2} := [[\"T_ROB1\"],[\"T_ROB2\"]];\n  PROC main()\n"
                            "    SyncMoveOn s1, all;\n"
                            f"    MoveL {target}, vGH, z1, tool0 \\ID:=10;\n    MoveL {target}, vGH, z1, tool0 \\ID:=20;\n"
                            f"    MoveL {target}, [1E6,1000,5000,1000], z1, tool0 \\ID:=30;\n"
                            "    SyncMoveOff s1;\n  ENDPROC\nENDMODULE\n")
    _, r = run(path)
    assert [m.speed.v_tcp for m in r.motions if m.kind != "wait"] == [7.0, 7.0, 7.0]  # a sync point waits 0 s
    said = [w.message for w in r.warnings]
    assert sum("'vGH' asks 200000 mm/s" in w for w in said) == 1 and sum("1e+06 mm/s" in w for w in said) == 1
    assert sum("MultiMove" in w for w in said) == 1


_EXPRS = ["s", "n", "p", "ReadNum(dev)", "ReadStr(dev)", "StrPart(s,1,2)", "StrLen(s)", "p.trans.x", "a{n}",
          "Offs(p,n,0,0)", "n + 1", "s + \"x\"", "[n,0,0]", "NOT b", "n > 2", "ValToStr(n)", "-n", "NumToStr(n,1)",
          "StrToVal(s,n)", "UINumEntry(\\Message:=\"x\")", "Foo(n)", "p.trans", "DotProd(p.trans,p.trans)"]
_TARGETS = ["s", "n", "p", "p.trans.x", "a{1}", "b", "a{n}", "p.trans", "a"]
_STATEMENTS = ["{t} := {e};", "IF {e} THEN n := 1; ENDIF", "WHILE {e} DO n := n + 1; ENDWHILE",
               "FOR i FROM 1 TO {e} DO n := i; ENDFOR", "TEST {e} CASE 1: n := 2; ENDTEST",
               "MoveL {e}, v100, fine, tool0;", "WaitTime {e};", "Incr {t};", "SocketReceive sock \\Str:={t};",
               "TPReadNum {t}, \"q\";", "SetDO doX, {e};", "MoveL p, [{e},500,5000,1000], fine, tool0;",
               "a{{{e}}} := 1;", "GetDataVal {e}, n;", "ReadAnyBin dev, {t};"]


def test_live_values_anywhere_are_run_or_said_at_a_line_never_a_crash(tmp_path):
    """Seeded: 300 short routines putting what live reads give wherever RAPID allows an expression;
    each runs, stops for the input it needs, or is an error at its line (a crash failed it once:
    a component of an unknown record incremented)."""
    import random

    rng = random.Random(20261127)
    head = ("MODULE F\n  VAR iodev dev;\n  VAR socketdev sock;\n  VAR string s;\n  VAR num n;\n  VAR bool b;\n"
            "  VAR num a{3};\n  VAR robtarget p := [[900,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n"
            "  PROC main()\n")
    kept = ["    SocketReceive sock \\Str:=p;\n    Incr p.trans.x;\n    p.trans.x := ReadNum(dev);\n"]
    for _ in range(300):
        kept.append("".join("    " + rng.choice(_STATEMENTS).format(e=rng.choice(_EXPRS), t=rng.choice(_TARGETS)) + "\n"
                            for _ in range(rng.randint(1, 5))))
    for body in kept:
        path = module(tmp_path, head + body + "  ENDPROC\nENDMODULE\n", "f.mod")
        try:
            run(path)
        except RsxmlError as exc:
            assert exc.line and exc.file == str(path)


def test_text_past_its_bounds_is_refused_at_its_line_before_it_is_parsed(tmp_path):
    """A 10 MB unterminated string once took 20 GB and minutes: a line past 256 KiB is refused."""
    path = module(tmp_path, "MODULE M\n  VAR string s := \"" + "a" * 300_000 + "\n  PROC main()\n  ENDPROC\nENDMODULE\n")
    with pytest.raises(RsxmlError, match="a line of 300019 characters: rswarp reads lines of at most 262144") as exc:
        run(path)
    assert exc.value.line == 2
    many = module(tmp_path, "MODULE M\n  VAR num a{1000001};\n  PROC main()\n  ENDPROC\nENDMODULE\n", "a.mod")
    with pytest.raises(RsxmlError, match="1 to 1000000 elements"):
        run(many)


def test_a_program_file_names_modules_in_its_folder_only(tmp_path):
    (tmp_path / "sub").mkdir()
    module(tmp_path / "sub", "MODULE A\n  PROC main()\n  ENDPROC\nENDMODULE\n", "a.mod")
    (tmp_path / "outside.mod").write_text("MODULE O\nENDMODULE\n")
    folder = tmp_path / "cell"
    folder.mkdir()
    (folder / "sub").mkdir()
    module(folder / "sub", "MODULE A\n  PROC main()\n  ENDPROC\nENDMODULE\n", "a.mod")
    for name, ok in (("sub/a.mod", True), ("sub\\a.mod", True), ("../outside.mod", False), ("/etc/passwd", False),
                     ("sub/../../outside.mod", False)):
        pgf = folder / "p.pgf"
        pgf.write_text(f'<?xml version="1.0"?>\n<Program>\n  <Module>{name}</Module>\n</Program>\n')
        if ok:
            run(pgf)
        else:
            with pytest.raises(RsxmlError, match="outside its folder") as exc:
                run(pgf)
            assert exc.value.line == 3
