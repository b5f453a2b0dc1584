"""The predefined data (issue 60, "Every predefined name"): rswarp/rapid/predefined.tsv holds every
predefined data name of ABB's RAPID manual and of the options rswarp's word table knows, each with
its type and value (and where that value comes from); every name resolves in a task and has its
value there; a parameter the manual types as a signal (AliasIO's, ValidIO's, a routine's VAR
signaldo) binds its argument's name as a signal; and the programs that stopped on a missing name
(a socket server waiting WAIT_MAX, raw bytes packed \\IntX:=DINT, an interrupt on every edge)
load and run to their motion."""

from __future__ import annotations

import re
from functools import lru_cache
from importlib import resources

import numpy as np
import pytest

import rswarp
from rswarp.examples import IRB2600
from rswarp.rapid import words
from rswarp.rapid.interpret import Interpreter
from rswarp.rapid.predefined import SOURCES, ZONES, error_number, literal, numeric_types, predefined, table
from rswarp.rapid.task import load_task
from rswarp.rapid.values import Opaque, Rec, Types

from conftest import DATA

WILD = DATA / "rapid" / "wild" / "predefined"
NAMES = DATA / "rapid" / "predefined_names.txt"


def source_names() -> list[str]:
    """The names of the source list (rapid-for-vim's constants and the manual's system data)."""
    return [w for line in NAMES.read_text(encoding="utf-8").splitlines() if not line.startswith("#")
            for w in line.split()]


def run(*paths, inputs=None):
    interp = Interpreter(load_task(list(paths)), inputs=inputs)
    return interp, interp.run()


# -- the table --------------------------------------------------------------------------------------
def test_the_table_says_its_size_and_every_row_where_its_value_comes_from():
    text = resources.files("rswarp.rapid").joinpath("predefined.tsv").read_text(encoding="utf-8")
    said = re.search(r"one a line: (\d+) names", text)
    assert said and int(said.group(1)) == len(table()) > 800
    for source in SOURCES:  # every source the rows name is said in the header
        assert re.search(rf"^#\s+{re.escape(source)}\s", text, re.M), source
    assert {r.source for r in table().values()} == set(SOURCES)


def test_the_table_holds_every_name_of_the_source_list():
    keys = set(table())
    missing = [n for n in source_names() if n.lower() not in keys and words.word(n.lower()) is None]
    assert missing == []
    assert len(source_names()) > 800


def test_no_table_name_is_a_word_and_none_is_written_twice():
    assert [k for k in table() if words.word(k) is not None] == []
    assert len({r.name.lower() for r in table().values()}) == len(table())


@pytest.mark.parametrize("name, want", [
    ("WAIT_MAX", 8388608), ("USINT", 1), ("UINT", 2), ("UDINT", 4), ("ULINT", 8), ("SINT", -1), ("INT", -2),
    ("DINT", -4), ("LINT", -8), ("edge", 2), ("high", 1), ("low", 0), ("pi", 3.1415926), ("EOF_BIN", -1),
    ("EOF_NUM", 9.998e36), ("MAX_RAWBYTES", 1024), ("inpos", 1), ("stoptime", 2), ("fllwtime", 3),
    ("SOCKET_CREATED", 1), ("SOCKET_CONNECTED", 2), ("SOCKET_CLOSED", 5), ("LT", 1), ("GT", 6),
    ("EGM_FRAME_BASE", 0), ("EGM_FRAME_TOOL", 1), ("EGM_FRAME_WOBJ", 2), ("EGM_FRAME_JOINT", 4),
    ("resOK", 1), ("btnNone", -1), ("btnOKCancel", 2), ("iconInfo", 1), ("OP_AUTO", 1), ("RUN_CONT_CYCLE", 1),
    ("OpAdd", 1), ("TYPE_ERR", 3), ("EVENT_START", 2), ("AIO_BETWEEN", 5), ("CFG_ERR", 12), ("TUNE_KP", 1),
])
def test_the_values_the_sources_give(name, want):
    assert table()[name.lower()].value == pytest.approx(want, rel=1e-12)


def test_the_hand_written_values_stay_as_they_were():
    t = table()
    assert t["v1000"].value == [1000, 500, 5000, 1000] and t["vmax"].value == [5000, 500, 5000, 1000]
    assert t["fine"].value == [True, 0, 0, 0, 0, 0, 0] and t["z10"].value == [False, 10, 15, 15, 1.5, 15, 1.5]
    assert ZONES[0] == (0.3, 0.3, 0.3, 0.03, 0.3, 0.03) and sorted(ZONES) == [0, 1, 5, 10, 15, 20, 30, 40, 50, 60,
                                                                             80, 100, 150, 200]
    assert t["tool0"].value == [True, [[0, 0, 0], [1, 0, 0, 0]], [0.001, [0, 0, 0.001], [1, 0, 0, 0], 0, 0, 0]]
    assert (t["tool0"].storage, t["wobj0"].storage, t["errno"].storage) == ("pers", "pers", "var")
    assert t["diskhome"].value == "HOME:" and t["stempty"].value == "" and t["reg3"].value == 0


def test_every_stand_in_number_is_distinct_and_error_numbers_agree():
    stand = [r.value for r in table().values() if r.source == "stand-in" and isinstance(r.value, float)]
    assert len(stand) == len(set(stand)) > 600
    errors = {k: r.value for k, r in table().items() if k.startswith("err_")}
    assert all(41000 <= v <= 41999 for v in errors.values()) and len(errors) > 200
    assert all(error_number(k) == v for k, v in errors.items())
    unknown = error_number("ERR_NOT_IN_THE_TABLE")  # a name no list holds: a stand-in no listed name has
    assert 41000 <= unknown <= 41999 and unknown not in errors.values()
    assert error_number("ERR_DIVZERO") != 41001 and error_number("resOK") is None


def test_literals_read_as_rapid_writes_them():
    assert literal('[TRUE,[1,-2.5E+3],"a""b",FALSE]') == [True, [1.0, -2500.0], 'a"b', False]
    with pytest.raises(ValueError):
        literal("[1,2")


def test_every_value_is_of_its_type_and_the_enumerations_are_numbers():
    values = predefined(Types())
    assert len(values) == len(table())
    assert {"inttypes", "egmframetype", "stoppoint", "tpnum", "motionprocessmode"} <= numeric_types()
    assert values["dint"] == ("inttypes", "const", -4.0) and values["egm_frame_wobj"][2] == 2.0
    assert values["c_progdisp"][2].type == "progdisp" and values["c_motset"][2].vals[0] == Rec("veldata",
                                                                                               (100.0, 5000.0))
    assert values["rob_id"][2] == Opaque("mecunit", "ROB_1") and values["t_rob1id"][2] == Opaque("taskid", "T_ROB1")


def test_every_name_of_the_table_resolves_in_a_task_and_has_its_value(tmp_path):
    """One module reads every predefined name into data of its type: it loads (the controller's
    load-time check knows each name) and runs, and each datum holds the table's value."""
    rows = list(table().values())
    decls = "".join(f"  VAR {r.type} x{k};\n" for k, r in enumerate(rows))
    body = "".join(f"    x{k} := {r.name};\n" for k, r in enumerate(rows))
    path = tmp_path / "AllNames.mod"
    path.write_text(f"MODULE AllNames\n{decls}  PROC main()\n{body}  ENDPROC\nENDMODULE\n", encoding="utf-8")
    interp, r = run(path)
    assert r.stopped is None and r.error is None
    want = predefined(interp.types)
    scope = interp.scopes["allnames"]
    for k, row in enumerate(rows):
        assert scope.get(f"x{k}").get() == want[row.name.lower()][2], row.name


def test_a_tasks_own_declaration_takes_a_predefined_names_place(tmp_path):
    path = tmp_path / "Own.mod"
    path.write_text("MODULE Own\n  CONST num WAIT_MAX := 60;\n  VAR num n;\n  PROC main()\n    n := WAIT_MAX;\n"
                    "  ENDPROC\nENDMODULE\n", encoding="utf-8")
    interp, _ = run(path)
    assert interp.scopes["own"].get("n").get() == 60


# -- signals where the manual types a signal --------------------------------------------------------
@pytest.mark.parametrize("word, place", [("aliasio", 0), ("aliasio", 1), ("aliasioreset", 0), ("validio", 0),
                                         ("getsignalorigin", 0), ("triggcheckio", 2)])
def test_the_manuals_signal_or_string_parameters_take_a_signal(word, place):
    assert place in words.signal_params(word)


def test_a_signal_parameter_binds_its_arguments_name_as_a_signal(tmp_path):
    """A routine's signal parameter given a name the task declares nowhere is that configured
    signal, by name; an IN one names its argument's signal, not a copy under its own name."""
    path = tmp_path / "Sig.mod"
    path.write_text("MODULE Sig\n  VAR signaldo doAlias;\n  VAR num seen;\n"
                    "  PROC SetIn(signaldo s)\n    SetDO s, 1;\n  ENDPROC\n"
                    "  PROC SetVar(VAR signaldo s)\n    SetDO s, 1;\n    seen := DOutput(s);\n  ENDPROC\n"
                    "  PROC Act(VAR mecunit m)\n    ActUnit m;\n  ENDPROC\n"
                    "  PROC main()\n    SetIn doA;\n    SetVar doB;\n    SetVar doAlias;\n    Act STN1;\n"
                    "    Act ROB_1;\n  ENDPROC\nENDMODULE\n", encoding="utf-8")
    interp, r = run(path)
    assert r.stopped is None
    assert {k: c.get() for k, c in interp.signals.items()} == {"doa": 1.0, "dob": 1.0, "doalias": 1.0}
    assert interp.scopes["sig"].get("seen").get() == 1


# -- programs in the manner of real ones ------------------------------------------------------------
@lru_cache(maxsize=None)
def planned(name: str, inputs: tuple = ()):
    """The plan of a module under WILD on the IRB 2600, with ``inputs`` (name, value) pairs."""
    given: dict[str, list[str]] = {}
    for key, value in inputs:
        given.setdefault(key, []).append(value)
    _, plan = rswarp.program(str(IRB2600), [str(WILD / name)], inputs=given)
    return plan


def tcp_mm(plan, move) -> np.ndarray:
    return np.array(move.motion.targets[0].pose.trans) * 1000


def test_a_socket_server_waiting_wait_max_runs_its_moves_from_what_it_receives():
    plan = planned("SocketServer.mod", (("received_msg", "900 100 600"), ("received_msg", "850 -100 650")))
    assert [(m.instruction, m.line) for m in plan.moves] == [("MoveJ", 24), ("MoveL", 35), ("MoveL", 35)]
    np.testing.assert_allclose([tcp_mm(plan, m) for m in plan.moves[1:]], [[900, 100, 600], [850, -100, 650]],
                               atol=1e-6)
    assert plan.run.stopped is None and all(m.error is None for m in plan.moves)


def test_the_socket_server_without_input_stops_where_it_needs_the_message():
    plan = planned("SocketServer.mod")
    assert [m.line for m in plan.moves] == [24]
    assert plan.run.needs_input["name"] == "received_msg" and plan.run.needs_input["read_line"] == 31


def test_raw_bytes_packed_and_unpacked_intx_dint_give_the_layers():
    plan = planned("RawPlc.mod", (("nLayers", "2"), ("nHeight", "120")))
    assert [m.line for m in plan.moves] == [14, 25, 26, 27, 25, 26, 27]
    np.testing.assert_allclose([tcp_mm(plan, m)[2] for m in plan.moves[1:]], [520, 420, 520, 640, 540, 640],
                               atol=1e-6)
    assert planned("RawPlc.mod").run.needs_input["name"] == "nLayers"  # UnpackRawBytes: the PLC's answer


def test_aliased_signals_and_an_interrupt_on_every_edge_run_to_their_motion():
    plan = planned("AliasGripper.mod")
    assert plan.run.stopped is None and plan.run.error is None
    assert [m.line for m in plan.moves if m.instruction != "WaitTime"] == [21, 22, 25, 26, 27, 30]


def test_system_data_and_option_constants_read_as_the_controller_has_them():
    interp, r = run(WILD / "SystemData.mod")
    scope = interp.scopes["systemdata"]
    got = {k: scope.get(k).get() for k in ("noverride", "neoffs", "nframe", "ninttype", "npmerr")}
    assert got == {"noverride": 100, "neoffs": 0, "nframe": 2, "ninttype": 8,
                   "npmerr": table()["pm_err_job_empty"].value}
    assert [m.line for m in r.motions] == [26, 31]
