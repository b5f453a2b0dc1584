"""The RAPID language as the controller runs it (issue "RAPID tasks as the controller runs them"),
without a robot: one module per construct under tests/data/rapid/lang, each value held against
what RAPID's reference manual says the controller computes; names resolved across modules; loops
that never end; errors at their lines; hostile text."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rswarp.errors import InputError, RsxmlError
from rswarp.rapid.interpret import Interpreter
from rswarp.rapid.parse import parse_text
from rswarp.rapid.task import load_task
from rswarp.rapid.values import Arr, Rec

from conftest import DATA

LANG = DATA / "rapid" / "lang"


def run(*paths, io=None, cycles=1, routine="main"):
    interp = Interpreter(load_task([LANG / p if isinstance(p, str) else p for p in paths]), io=io, cycles=cycles)
    return interp, interp.run(routine)


def value(interp, name: str):
    """A data object's value after the run (the task's own before the predefined)."""
    cells = [s.get(name.lower()) for s in interp.scopes.values() if s.get(name.lower()) is not None]
    cell = next((c for c in cells if c.file), cells[0])
    v = cell.get()
    return v.items if isinstance(v, Arr) else list(v.vals) if isinstance(v, Rec) else v


def module(tmp_path, text: str, name: str = "t.mod"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_div_and_mod_truncate_toward_zero_and_priorities_hold():
    interp, _ = run("divmod.mod")
    assert [value(interp, n) for n in ("nRow", "nCol", "nNeg", "nRem")] == [3, 2, -3, -2]
    assert value(interp, "nMix") == 2 + 3 * 4 - 10 / 4 + 7 % 3


def test_optional_arguments_switches_alternatives_and_conditional_arguments():
    interp, _ = run("optional_args.mod")
    # Mark 1\lift:=40\Fast; Pass (\lift?lift: absent, not passed on); Pass \lift:=7; Mark 3, \Slow
    assert [value(interp, n) for n in ("nSeen", "nLift", "bFast", "bSlow")] == [3, 7, False, True]


def test_records_aliases_and_component_assignment():
    interp, _ = run("record.mod")
    assert value(interp, "sNext") == [1, 3, "A1b"]
    grip = value(interp, "pGrip")
    assert list(grip[0].vals) == [900, 0, 600] and grip[2].vals[0] == -1
    assert value(interp, "xy") == [901, 2, 603]
    assert value(interp, "nSlots") == 13


def test_arrays_in_two_dimensions_by_element_and_whole():
    interp, _ = run("arrays.mod")
    assert value(interp, "grid") == [101, 2, 3, 4, 5, 60]
    assert value(interp, "total") == 101 + 2 + 3 + 4 + 5 + 60 and value(interp, "dims") == 23


def test_interrupts_are_parsed_not_run_and_handlers_run_only_for_an_error():
    interp, r = run("connect_trap.mod")
    assert value(interp, "nTrapped") == 0
    assert [w.message for w in r.warnings] == ["interrupts are not modelled: TRAP 'tstop' never runs"]
    interp, _ = run("handlers.mod")  # no error: its ERROR, BACKWARD and UNDO handlers leave no trace
    assert value(interp, "nTries") == 0 and value(interp, "nOk") == 1


def test_error_handlers_retry_trynext_and_raise_to_the_caller():
    interp, _ = run("error_handler.mod")
    assert value(interp, "ERR_NOPART") == 1  # BookErrNo: the user's first error number
    assert (value(interp, "nRetries"), value(interp, "nRatio")) == (1, 2.5)  # RETRY after nDiv := 4
    assert value(interp, "nSkipped") == 7  # TRYNEXT: on after the failing statement
    assert value(interp, "nCaught") == 1  # Pick's RAISE passed to main's handler
    assert value(interp, "nAfter") == 1  # main's TRYNEXT: on after Pick


def test_one_line_if_goto_and_labels():
    interp, _ = run("if_short.mod")
    assert (value(interp, "n"), value(interp, "nCalls")) == (0, 1)
    interp, _ = run("goto.mod")
    assert (value(interp, "n"), value(interp, "nSkipped")) == (4, 0)


def test_late_binding_and_callbyvar():
    interp, _ = run("late_binding.mod")
    assert value(interp, "nLast") == 30  # Station2 5 gave 25, then CallByVar "Job", 3


def test_routine_data_shadows_the_modules_and_in_copies_inout_refers():
    interp, _ = run("scopes.mod")
    assert value(interp, "nSeen") == 2  # Own's x, not the module's
    assert value(interp, "i") == 77 and value(interp, "nOuter") == 6  # FOR's i is its own
    assert value(interp, "x") == 16  # x unchanged by Copy's IN copy; y became 15


def test_string_and_arithmetic_functions():
    interp, _ = run("strings_math.mod")
    assert value(interp, "sMsg") == "Part 12.3 of 3"
    assert (value(interp, "nPart"), value(interp, "nFound"), value(interp, "bOk"), value(interp, "nVal")) == \
        (3, 4, True, 42.5)
    assert value(interp, "nAngle") == pytest.approx(45 + 90 + 4 + 2 + 8)
    assert value(interp, "nRound") == pytest.approx(2.46 + 3) and value(interp, "nBits") == (12 & 10) + (1 | 2)


def test_several_modules_in_one_file_local_stays_in_its_module():
    interp, _ = run("multi.prg")
    assert value(interp, "nShared") == 10 + 1 + 100


def test_a_main_loop_runs_its_cycles_and_a_wait_on_a_signal_is_taken_as_met():
    _, r = run("while_true.mod", cycles=3)
    moves = [m for m in r.motions if m.kind != "wait"]
    assert len(moves) == 6 and [m.cycle for m in moves] == [0, 0, 1, 1, 2, 2]
    assert r.cycle.endless and r.cycle.line == 7 and len(r.cycle.starts) == 4
    said = " ".join(w.message for w in r.warnings)
    assert "WaitDI diStart, 1" in said and "reads diReady" in said and "ran 3 passes" in said
    _, r = run("while_true.mod", io={"diReady": 1})
    assert not any(m.kind == "wait" for m in r.motions)  # the polling loop does not run
    _, r = run("goto_loop.mod", cycles=2)
    assert [m.line for m in r.motions] == [7, 8, 7, 8] and r.cycle.line == 9


def test_names_declared_twice_are_errors_naming_both_places(tmp_path):
    a = module(tmp_path, "MODULE A\n  VAR num n;\nENDMODULE\n", "a.mod")
    b = module(tmp_path, "MODULE B\n  PROC main()\n  ENDPROC\n  VAR num n;\nENDMODULE\n", "b.mod")
    with pytest.raises(RsxmlError, match=f"'n' is declared twice: also at {a}:2") as exc:
        load_task([a, b])
    assert exc.value.line == 4
    local = module(tmp_path, "MODULE C\n  LOCAL VAR num n;\n  PROC main()\n  ENDPROC\nENDMODULE\n", "c.mod")
    load_task([a, local])  # LOCAL: no clash
    pers = module(tmp_path, "MODULE D\n  PERS num p := 1;\nENDMODULE\n", "d.mod")
    pers2 = module(tmp_path, "MODULE E\n  PERS num p := 1;\n  PROC main()\n    p := p + 1;\n  ENDPROC\nENDMODULE\n",
                   "e.mod")
    interp = Interpreter(load_task([pers, pers2]))
    interp.run()
    assert value(interp, "p") == 2  # one persistent object


@pytest.mark.parametrize("text, line, message", [
    ("MODULE M\n  FUNC num main()\n    RETURN 1;\n  ENDFUNC\nENDMODULE\n", 2, "'main' is a FUNC: a task runs a PROC"),
    ("MODULE M\n  TRAP main\n  ENDTRAP\nENDMODULE\n", 2, "'main' is a TRAP"),
    ("MODULE M\n  PROC main()\n    VAR num n:=1;\n    VAR num n:=2;\n    WaitTime n;\n  ENDPROC\nENDMODULE\n", 4,
     "'n' is declared twice in main: it is also declared at line 3"),
    ("MODULE M\n  PROC main()\n    R 1;\n  ENDPROC\n  PROC R(num x)\n    VAR num x:=5;\n  ENDPROC\nENDMODULE\n", 6,
     "'x' is declared twice in R: it is also a parameter of R"),
    ("MODULE M\n  PROC main()\n    R 1, 2;\n  ENDPROC\n  PROC R(num x, num X)\n  ENDPROC\nENDMODULE\n", 5,
     "R has two parameters named 'X'"),
    ("MODULE M\n  VAR num a{3};\n  PROC main()\n    a{1.5} := 1;\n  ENDPROC\nENDMODULE\n", 4,
     "an array index must be a whole number, not the number 1.5"),
    ("MODULE M\n  VAR num a{3};\n  PROC main()\n    a{4} := 1;\n  ENDPROC\nENDMODULE\n", 4, "index {4} of a{4} is outside {3}"),
    ("MODULE M\n  VAR num n;\n  PROC main()\n    n := 1 / 0;\n  ENDPROC\nENDMODULE\n", 4, "division by zero"),
    ("MODULE M\n  VAR num n;\n  PROC main()\n    n := 5 DIV 0.5;\n  ENDPROC\nENDMODULE\n", 4, "DIV takes whole numbers"),
    ("MODULE M\n  VAR num n;\n  PROC main()\n    n := 1 + \"a\";\n  ENDPROC\nENDMODULE\n", 4, "'+' cannot take"),
    ("MODULE M\n  CONST num n := 1;\n  PROC main()\n    n := 2;\n  ENDPROC\nENDMODULE\n", 4, "cannot assign to the constant 'n'"),
    ("MODULE M\n  PROC main()\n    Again;\n  ENDPROC\n  PROC Again()\n    Again;\n  ENDPROC\nENDMODULE\n", 6,
     "calls nest deeper than 100"),
    ("MODULE M\n  PROC main()\n    Visit 1, 2;\n  ENDPROC\n  PROC Visit(num a)\n  ENDPROC\nENDMODULE\n", 3,
     "'Visit' takes 1 argument (a), given 2"),
    ("MODULE M\n  FUNC num F()\n  ENDFUNC\n  PROC main()\n    reg1 := F();\n  ENDPROC\nENDMODULE\n", 2,
     "FUNC 'F' ended without RETURN"),
    ("MODULE M\n  PROC main()\n    RAISE 41001;\n  ENDPROC\nENDMODULE\n", 3, "RAISE 41001 (41001): no ERROR handler takes"),
    ("MODULE M\n  PROC main()\n    reg1 := 1 / 0;\n  ERROR (41001)\n    TRYNEXT;\n  ENDPROC\nENDMODULE\n", 3,
     "division by zero"),
    ("MODULE M\n  PROC main()\n    RETRY;\n  ENDPROC\nENDMODULE\n", 3, "RETRY outside an ERROR handler"),
    ("MODULE M\n  PROC main()\n    reg1 := <EXP>;\n  ENDPROC\nENDMODULE\n", 3, "<EXP>: a placeholder"),
])
def test_run_time_errors_at_their_lines(tmp_path, text, line, message):
    path = module(tmp_path, text)
    with pytest.raises(RsxmlError) as exc:
        Interpreter(load_task([path])).run()
    assert exc.value.line == line and message in exc.value.message and exc.value.file == str(path)


def test_a_loop_that_never_ends_stops_at_a_bound_and_one_that_cannot_change_ends_after_a_pass(tmp_path, monkeypatch):
    import rswarp.rapid.interpret as interpret

    monkeypatch.setattr(interpret, "MAX_STATEMENTS", 20_000)
    runaway = module(tmp_path, "MODULE M\n  PROC main()\n    WHILE reg1 >= 0 DO\n      Incr reg1;\n    ENDWHILE\n"
                               "  ENDPROC\nENDMODULE\n")
    with pytest.raises(RsxmlError, match="the task ran 20000 statements without ending") as exc:
        run(runaway)
    assert exc.value.line in (3, 4)
    still = module(tmp_path, "MODULE M\n  PROC main()\n    WHILE TRUE DO\n      Incr reg1;\n    ENDWHILE\n"
                             "  ENDPROC\nENDMODULE\n", "still.mod")
    interp, r = run(still)
    assert value(interp, "reg1") == 1 and "taken as ended after one pass" in r.warnings[0].message


def test_what_cannot_change_the_motion_is_silent_and_what_could_is_a_warning(tmp_path):
    path = module(tmp_path, "MODULE M\n  VAR iodev io;\n  PROC main()\n    TPWrite \"hi\";\n    SetDO doLamp, 1;\n"
                            "    Open \"HOME:\" \\File:=\"a\", io;\n    PDispSet pose0;\n    MyOptionInstr 1;\n"
                            "    RenameFile \"HOME:/a\", \"HOME:/b\";\n  ENDPROC\nENDMODULE\n")
    _, r = run(path)
    said = [(w.line, w.message) for w in r.warnings]
    assert [line for line, _ in said] == [7, 8]
    assert "PDispSet could change the motion and is not modelled" in said[0][1]
    assert "'MyOptionInstr' is neither a routine of the task nor a RAPID instruction" in said[1][1]


def test_signals_are_zero_unless_given_and_set_by_the_program(tmp_path):
    path = module(tmp_path, "MODULE M\n  VAR num a;\n  VAR num b;\n  PROC main()\n    a := diPart + 1;\n"
                            "    SetDO doGrip, 1;\n    b := DOutput(doGrip) + DInput(diPart);\n  ENDPROC\nENDMODULE\n")
    interp, r = run(path)
    assert (value(interp, "a"), value(interp, "b")) == (1, 1)
    assert "'diPart' is declared nowhere in the task: taken as an I/O signal of value 0" in r.warnings[0].message
    interp, r = run(path, io={"diPart": 2})
    assert (value(interp, "a"), value(interp, "b")) == (3, 3) and not r.warnings


def test_literal_aggregates_read_in_one_go_equal_the_general_reading(tmp_path):
    fast = module(tmp_path, "MODULE M\n  CONST robtarget p:=[[1.5,-2,3E2],[1,0,0,0],[0,-1,2,1],[9E9,9E9,9E9,9E9,9E9,9E9]];"
                            "\n  PERS tooldata t:=[TRUE,[[0,0,.5],[1,0,0,0]],[3,[0,0,80],[1,0,0,0],0,0,0]];\n"
                            "  PROC main()\n  ENDPROC\nENDMODULE\n", "fast.mod")
    slow = module(tmp_path, "MODULE M\n  CONST robtarget p:=[[1.5, -2, 3E2], ! a comment: read rule by rule\n"
                            "    [1,0,0,0],[0,-1,2,1],[9E9,9E9,9E9,9E9,9E9,9E9]];\n  PERS tooldata t:=[TRUE,[[0,0,0.5],"
                            "[1,0,0,0]],[3,[0,0,2*40],[1,0,0,0],0,0,0]];\n  PROC main()\n  ENDPROC\nENDMODULE\n", "slow.mod")
    assert parse_text(fast.read_text(), "f")[0].data[0].init.__class__.__name__ == "Literal"
    assert parse_text(slow.read_text(), "s")[0].data[0].init.__class__.__name__ == "Aggregate"
    a, _ = run(fast)
    b, _ = run(slow)
    assert value(a, "p") == value(b, "p") and value(a, "t") == value(b, "t")


_RUNS = """MODULE R
  ! targets, as a generator writes them
  CONST robtarget p1:=[[900,0,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];

  LOCAL CONST robtarget p2:=[[901, 0,900.],[0,0,1,0],[0,0,0,0],[9E+09,9E9,9E9,9E9,9E9,9E9]]; ! after
  PERS num n:=3; CONST num k:=2;
  VAR num m:=n*2;
  PERS tooldata t:=[TRUE,[[0,0,.5],[1,0,0,0]],[3,[0,0,80],[1,0,0,0],0,0,0]];
  CONST robtarget p3:=[[01,0,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  TASK PERS wobjdata w:=[FALSE,TRUE,"",[[0,0,0],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  PROC main()
    VAR robtarget q:=[[900,0,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    VAR num z{2}:=[1,2];
    ConfL \\Off;
    MoveL [[900,10,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, z10, tool0\\WObj:=wobj0;
    MoveL [[900,20,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]],v100,z10,tool0 \\WObj := wobj0; ! a comment
    MoveJ \\Conc, q, v1000 \\V:=1200, fine \\Inpos:=inpos50, tool0;
    MoveC [[900,30,910],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], [[900,40,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, z1, tool0;
    MoveL Offs(q, 0, 0, 10), v100, z10, tool0;
    MoveL q, v100, z10, tool0 \\WObj?wobj0;
    MoveL [[900,50,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, 0.5, tool0;
    FOR i FROM 1 TO 2 DO
      MoveL q, v100, fine, tool0;
      MoveAbsJ [[0,0,0,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;
    ENDFOR
    MoveL p.trans, v100, z10, tool0;
    MoveL ToPoint:=q, v100, z10, tool0;
    MoveL q, v100 + 1, z10, tool0;
    MoveL [[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, z10, tool0 \\WObj:=wobj0; MoveL q, v100, z10, tool0;
  ENDPROC
ENDMODULE
"""


@pytest.mark.parametrize("text", [_RUNS, _RUNS.replace("! after", "! after \x01")])
def test_runs_of_plain_lines_read_at_once_equal_the_parsers_reading(text, monkeypatch):
    """A module's runs of declarations of literals and of plain moves are read without lark (its
    cost is per token): the same nodes at the same lines, in modules and routines, as lark's own
    reading of them; what is not plain is left to lark."""
    from rswarp.rapid import runs
    from rswarp.rapid.build import Builder

    builder = Builder("r.mod")
    runs.take_runs(builder, text)
    assert [len(r) for r in builder.runs] == ([] if "\x01" in text else [4, 3, 1, 4, 1, 2, 2])
    fast = parse_text(text, "r.mod")[0]
    monkeypatch.setattr("rswarp.rapid.parse.take_runs", lambda b, t: t)
    slow = parse_text(text, "r.mod")[0]
    assert [d.line for d in fast.data] == [3, 5, 6, 6, 7, 8, 9, 10]
    assert fast.data == slow.data and fast.routines[0].body == slow.routines[0].body


_PIECES = st.sampled_from(["p", "v100", "z10", "IF", "true", "5", "5.", ".5", "01", "-5", "1E999", "0x1F",
                            "[1,2,3]", "[1, [2,3]]", "[]", "[[1,[2,[3,[4,[5]]]]]]", "[1,2]]", "[1 -2]", "[e]",
                            '["a"]', "[TRUE]", "Offs(p,0,0,1)", "p.trans", "a{1}", "ToPoint:=p", "\\WObj:=w",
                            "\\Conc", "\\WObj?w", "\\V:=[1,2]", "!c", ""])
_SEPARATORS = st.sampled_from([", ", ",", " ", "", "\n", " , "])


@settings(max_examples=300, deadline=None)
@given(head=st.sampled_from(["MoveL", "MoveJ", "moveabsj", "TriggL", "ArcLStart", "SearchL", "Move_1"]),
       parts=st.lists(st.tuples(_SEPARATORS, _PIECES), min_size=1, max_size=6), end=st.sampled_from([";", "", ";;"]))
def test_any_move_line_reads_as_lark_reads_it(head, parts, end):
    """Whatever follows a move's name, the quick reading of plain lines gives lark's nodes or is
    left to lark: the same nodes, or the same error at the same line."""
    line = head + " " + "".join(sep + piece for sep, piece in parts)[1:].lstrip(", ") + end
    text = f"MODULE F\n  PROC main()\n    MoveL q, v100, fine, tool0;\n    {line}\n    {line}\n  ENDPROC\nENDMODULE\n"
    got = []
    for quick in (True, False):
        from rswarp.rapid import parse

        original = parse.take_runs
        if not quick:
            parse.take_runs = lambda b, t: t
        try:
            got.append(parse_text(text, "f.mod")[0].routines[0].body)
        except RsxmlError as exc:
            got.append(exc.line)
        finally:
            parse.take_runs = original
    assert got[0] == got[1]


@pytest.mark.parametrize("text, line, message", [
    ("MODULE D\n  CONST num a:=1;\n  CONST pos p:=[1,2,1E999];\nENDMODULE\n", 3, "the number 1E999 is out of range"),
    ("MODULE D\n  CONST num a:=1;\n  CONST num b{2}:=[1,2];\n  CONST pos p:=[];\nENDMODULE\n", 4,
     "RAPID syntax: unexpected"),
    ("MODULE D\n  CONST num a:=1;\n  CONST num b:=[1,2];\n  PROC main()\n  ENDPROC\nENDMODULE\n", 3,
     "'b' must be a number, not an aggregate of 2 parts"),
    ("MODULE D\n  CONST num a:=1;\n  MoveL p, v100, fine, tool0;\n  PROC main()\n  ENDPROC\nENDMODULE\n", 3,
     "RAPID syntax: unexpected 'MoveL'"),
    ("MODULE D\n  PROC main()\n    MoveL [[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9,9,9,9,9]], v100, fine, tool0;\n"
     "    MoveL [[1,2,1E999],[1,0,0,0],[0,0,0,0],[9E9,9,9,9,9,9]], v100, fine, tool0;\n  ENDPROC\nENDMODULE\n", 4,
     "the number 1E999 is out of range"),
])
def test_errors_in_runs_of_declarations_are_at_their_lines(tmp_path, text, line, message):
    with pytest.raises(RsxmlError, match=message) as exc:
        run(module(tmp_path, text))
    assert exc.value.line == line


@pytest.mark.parametrize("text, line, message", [
    ("MODULE D\n  CONST num x:=" + "[" * 5000 + "1" + "]" * 5000 + ";\nENDMODULE\n", 2, "nested deeper than 64"),
    ("MODULE D\n  CONST num x:=" + "-" * 5000 + "1;\nENDMODULE\n", 2, "nested deeper than 64"),
    ('MODULE D\n  CONST string s:="a\\";\n  CONST num x:=' + "(" * 5000 + "1" + ")" * 5000 + ";\nENDMODULE\n", 3,
     "nested deeper than 64"),
    ('MODULE D\n  CONST string s:="' + "x" * 10_000_000 + '";\nENDMODULE\n', 2, "RAPID strings hold at most 80"),
    ("MODULE D\n  CONST num x:=1E999;\nENDMODULE\n", 2, "the number 1E999 is out of range"),
    ("MODULE D\n  PROC main()\n" + "    IF TRUE THEN\n" * 70 + "    ENDIF\n" * 70 + "  ENDPROC\nENDMODULE\n", 2,
     "nests IF, FOR, WHILE and TEST deeper than 64"),
])
def test_hostile_text_is_a_clear_error_not_a_crash(tmp_path, text, line, message):
    path = module(tmp_path, text)
    with pytest.raises(RsxmlError, match=message) as exc:
        load_task([path])
    assert exc.value.line == line


def test_a_task_of_more_text_than_rswarp_reads_is_refused_before_it_is_read(tmp_path, monkeypatch):
    from rswarp.rapid import task

    monkeypatch.setattr(task, "MAX_TASK_BYTES", 100)
    module(tmp_path, "MODULE A\n  PROC main()\n  ENDPROC\nENDMODULE\n", "a.mod")
    module(tmp_path, "MODULE B\n  CONST num x:=1;\n" + "  ! padding\n" * 10 + "ENDMODULE\n", "b.mod")
    with pytest.raises(RsxmlError, match="pass 0 MiB of text with this file") as exc:
        load_task([tmp_path / "a.mod", tmp_path / "b.mod"])
    assert exc.value.file.endswith("b.mod")


def test_long_flat_expressions_and_many_declarations_read_without_recursion(tmp_path):
    path = module(tmp_path, "MODULE D\n  VAR num x;\n  PROC main()\n    x := 0" + " + 1" * 20000 + ";\n  ENDPROC\nENDMODULE\n")
    interp, _ = run(path)
    assert value(interp, "x") == 20000
    path.write_bytes(b"\x00\x01MODULE")
    with pytest.raises(RsxmlError, match="NUL bytes"):
        load_task([path])


def _target_module(tmp_path, quat, speed=(100, 500)):
    path = tmp_path / "q.mod"
    q = ",".join(repr(float(c)) for c in quat)
    path.write_text(f"MODULE Q\n  CONST robtarget p:=[[900,0,900],[{q}],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n"
                    f"  VAR speeddata vS:=[{float(speed[0])!r},{float(speed[1])!r},5000,1000];\n"
                    "  PROC main()\n    MoveL p, vS, fine, tool0;\n  ENDPROC\nENDMODULE\n")
    return path


_UNIT = st.floats(-2.0, 2.0, allow_nan=False)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(quat=st.tuples(_UNIT, _UNIT, _UNIT, _UNIT))
def test_quaternions_are_normalized_within_the_controllers_slack_or_refused(tmp_path, quat):
    """ABB refuses an orientation whose squares sum farther than 0.1 from 1; rswarp too, at the
    line of the move, and normalizes the rest (never the identity in place of a zero)."""
    path = _target_module(tmp_path, quat)
    n2 = sum(c * c for c in quat)
    if abs(n2 - 1.0) > 0.1:
        with pytest.raises(RsxmlError, match="is not normalized") as exc:
            run(path)
        assert exc.value.line == 5
    else:
        _, r = run(path)
        got = r.motions[0].targets[0].pose.quat
        assert got == pytest.approx([c / n2 ** 0.5 for c in quat], abs=1e-12)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(v_tcp=st.floats(-1e3, 1e4, allow_nan=False), v_ori=st.floats(-10.0, 1e3, allow_nan=False))
def test_speeds_above_zero_run_and_others_are_refused(tmp_path, v_tcp, v_ori):
    path = _target_module(tmp_path, (0, 0, 1, 0), (v_tcp, v_ori))
    if v_tcp > 0 and v_ori > 0:
        _, r = run(path)  # the controller runs a TCP speed above the robot's top speed at the top speed
        assert r.motions[0].speed.v_tcp == pytest.approx(min(v_tcp, 7000.0) / 1000)
    else:
        with pytest.raises(RsxmlError, match="both must be above 0") as exc:
            run(path)
        assert exc.value.line == 5


_WORDS = ["MoveL", "p", ",", ";", ":=", "(", ")", "[", "]", "{", "}", "1", "-", "+", "*", "/", "DIV", "MOD", "AND",
          "NOT", "=", "IF", "THEN", "ENDIF", "FOR", "i", "FROM", "TO", "DO", "ENDFOR", "WHILE", "ENDWHILE", "n",
          "Offs(p,0,0,1)", "\"s\"", "TRUE", "\\WObj:=wobj0", "v100", "fine", "tool0", "RETURN", "GOTO", "l", "l:",
          "Incr", "reg1", "a{2}", "p.trans.x", "RAISE", "%\"F\"%", "F", "TEST", "CASE", ":", "ENDTEST", "\n"]


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(words=st.lists(st.sampled_from(_WORDS), min_size=1, max_size=30))
def test_any_statement_text_is_run_or_refused_at_its_line_never_crashes(tmp_path, words):
    path = tmp_path / "fuzz.mod"
    path.write_text("MODULE Z\n  VAR num n;\n  VAR num a{3};\n  VAR robtarget p:=[[900,0,900],[0,0,1,0],[0,0,0,0],"
                    "[9E9,9E9,9E9,9E9,9E9,9E9]];\n  PROC F()\n    n := n + 1;\n  ENDPROC\n  PROC main()\n    "
                    + " ".join(words) + "\n  ENDPROC\nENDMODULE\n")
    try:
        run(path)
    except RsxmlError as exc:
        assert exc.file == str(path) and exc.line > 0
    except InputError:
        pass


@pytest.mark.parametrize("text, line, message", [
    ("MODULE T\n  PROC main()\n    reg1 := 1\n    reg2 := 2;\n  ENDPROC\nENDMODULE\n", 3,
     "';' missing at the end of the line (line 4 goes on with 'reg2')"),
    ("MODULE T\n  PROC main()\n    IF reg1 > 1 THEN\n      reg1 := 1;\n    ENDFI\n  ENDPROC\nENDMODULE\n", 3,
     "IF has no ENDIF (ENDPROC at line 6)"),
    ("MODULE T\n  PROC main()\n    IF reg1 > 1 reg1 := 1;\n    FOR i FROM 1 TO 2 DO\n  ENDPROC\nENDMODULE\n", 4,
     "FOR has no ENDFOR"),
    ('<?xml version="1.0"?>\n<Program/>\n', 1, "an XML file, not a RAPID module"),
])
def test_syntax_errors_are_said_where_they_were_made(tmp_path, text, line, message):
    with pytest.raises(RsxmlError) as exc:
        load_task([module(tmp_path, text)])
    assert exc.value.line == line and message in exc.value.message


def test_misspelt_names_are_errors_and_undeclared_signals_are_not(tmp_path):
    typo = module(tmp_path, "MODULE T\n  VAR num nDelays := 1;\n  PROC main()\n    WaitTime nDelay;\n  ENDPROC\n"
                            "ENDMODULE\n")
    with pytest.raises(RsxmlError, match=r"'nDelay' is declared nowhere in the task \(did you mean 'nDelays'\?\)") as exc:
        run(typo)
    assert exc.value.line == 4
    proc = module(tmp_path, "MODULE T\n  PROC main()\n    MovL p, v100, fine, tool0;\n  ENDPROC\nENDMODULE\n", "p.mod")
    with pytest.raises(RsxmlError, match=r"unknown procedure 'MovL' \(did you mean MoveL\?\)"):
        run(proc)
    missing = module(tmp_path, "MODULE T\n  VAR num n;\n  PROC main()\n    n := patBoxes.cols;\n  ENDPROC\nENDMODULE\n",
                     "m.mod")
    with pytest.raises(RsxmlError, match=r"'patBoxes' is declared nowhere in the task"):
        run(missing)
    with pytest.raises(RsxmlError, match=r"'diStart' is declared nowhere in the task: .* or an I/O signal") as exc:
        run(module(tmp_path, "MODULE T\n  PROC main()\n    reg1 := diStart;\n  ENDPROC\nENDMODULE\n", "u.mod"))
    assert exc.value.line == 3  # read as data, declared nowhere: the controller would not load the task
    _, r = run(module(tmp_path, "MODULE T\n  PROC main()\n    reg1 := diStart;\n    WaitDI diStart, 0;\n  ENDPROC\n"
                                "ENDMODULE\n", "s.mod"), io={"diStrat": 1})
    said = [w.message for w in r.warnings]
    assert any("'diStart' is declared nowhere" in w for w in said)  # a signal where RAPID expects one: read bare
    assert "--io diStrat: the task uses no signal of that name (did you mean diStart?)" in said


_UNREACHED = ("MODULE T\n  VAR num nMode := 1;\n  CONST robtarget pHome := [[900,0,900],[0,0,1,0],[0,0,0,0],"
              "[9E9,9E9,9E9,9E9,9E9,9E9]];\n  PROC main()\n    TEST nMode\n    CASE 1:\n      MoveJ pHome, v500, fine, tool0;\n"
              "    DEFAULT:\n      {}\n    ENDTEST\n  ENDPROC\n  PROC rPick(num nRow)\n    MoveL pHome, v100, z10, tool0;\n"
              "  ENDPROC\nENDMODULE\n")


@pytest.mark.parametrize("statement, message", [
    ("MovL pHome, v100, fine, tool0;", "unknown procedure 'MovL' (did you mean MoveL?)"),
    ("MoveL pHomee, v100, fine, tool0;", "'pHomee' is declared nowhere in the task (did you mean 'pHome'?)"),
    ("MoveL pHome, v100, fine, tool0 \\WObj:=wobjTable;", "'wobjTable' is declared nowhere in the task"),
    ("nMod := 2;", "'nMod' is declared nowhere in the task (did you mean 'nMode'?)"),
    ("rPick;", "'rPick' takes"),
    ("rPick 1, 2;", "'rPick' takes"),
    ("GOTO lblRetry;", "GOTO lblRetry: no such label in 'main'"),
])
def test_the_task_is_checked_as_the_controller_loads_it_in_branches_never_run(tmp_path, statement, message):
    """The controller refuses a task with these at load, whatever branch runs; so does rswarp,
    at the line, before any move (the DEFAULT branch here never runs)."""
    with pytest.raises(RsxmlError) as exc:
        run(module(tmp_path, _UNREACHED.replace("{}", statement)))
    assert exc.value.line == 9 and message in exc.value.message


def test_names_in_branches_never_run_that_are_signals_are_not_refused_at_load(tmp_path):
    """A name declared nowhere is a signal where the task uses it as one (WaitDI, SetDO), even in a
    branch that never runs; read bare elsewhere it is then that signal."""
    interp, _ = run(module(tmp_path, _UNREACHED.replace("{}", "WaitDI diPartOk, 1;\n      IF doGrip = 1 reg1 := 2;\n"
                                                              "      SetDO doGrip, 0;")))
    assert value(interp, "nMode") == 1
    with pytest.raises(RsxmlError, match="'doGrip' is declared nowhere in the task") as exc:
        run(module(tmp_path, _UNREACHED.replace("{}", "IF doGrip = 1 reg1 := 2;"), "n.mod"))
    assert exc.value.line == 9
