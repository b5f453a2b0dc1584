"""The table of RAPID words (rswarp/rapid/words.py, words.tsv): every word of the manual has a
handling, the interpreter's registries agree with it, and docs/program.md shows it."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from rswarp.rapid import functions, instructions, moves, values, words

ROOT = Path(__file__).resolve().parents[1]
# Words being implemented now: modelled, though a registry may not hold them yet.
ADDED = {"getdataval", "setdataval", "setalldataval", "syncmoveon", "syncmoveoff", "syncmoveundo", "waitsynctask",
         "getsysdata", "setsysdata", "strmatch", "crossprod", "strmap", "bytetostr", "strtobyte", "dectohex",
         "hextodec", "maxrobspeed", "mirpos", "orobt", "type", "argname", "calcrotaxisframe", "defaccframe",
         "defdframe", "cdate", "ctime", "rawbyteslen"}
# Registry entries that answer what only the cell has (a default, or an unknown value).
LIVE_STUBS = {"tpreadfk", "tpreadnum", "tpreaddnum", "readnum", "readstr", "readbin", "readstrbin", "readmotor",
              "isfile", "filesize", "socketgetstatus"} | set(getattr(functions, "LIVE", ()))
SIGNAL_SETTERS = {"setdo", "setao", "setgo", "set", "reset", "invertdo", "pulsedo"}


def _manual() -> list[tuple[str, str]]:
    """(name, kind) of each line of words.tsv."""
    text = (ROOT / "rswarp" / "rapid" / "words.tsv").read_text(encoding="utf-8")
    return [tuple(line.split("\t")[:2]) for line in text.splitlines() if line and not line.startswith("#")]


def _registries() -> set[str]:
    return set(moves.MOVES) | set(instructions._HANDLERS) | SIGNAL_SETTERS | set(functions.FUNCTIONS)


def _in_grammar(w: words.Word) -> bool:
    """A statement or operator the grammar itself takes (IF, FOR, AND, a label, a comment, a call)."""
    lark = (ROOT / "rswarp" / "rapid" / "rapid.lark").read_text()
    forms = {"comment": r"^COMMENT:", "label": r"^label:", "proccall": r"^call:", "div": r"DIV\|MOD", "mod": r"DIV\|MOD"}
    pattern = forms.get(w.name.lower(), rf"^{w.name.upper()}(\.\d+)?:")
    return re.search(pattern, lark, re.M) is not None


def test_every_manual_word_has_a_handling_and_a_category():
    table = words.words()
    for name, kind in _manual():
        w = table[name.lower()]
        assert (w.name, w.kind, w.source) == (name, kind, "manual")
        assert w.handling in words.HANDLINGS and w.category, name
    assert {w.handling for w in table.values()} == set(words.HANDLINGS)


def test_names_are_unique_and_hold_the_words_programs_trip_on():
    names = [name.lower() for name, _ in _manual()]
    assert len(names) == len(set(names))
    assert len(names) > 600
    wanted = """GetDataVal SetDataVal GetSysData RenameFile ClearRawBytes UnpackRawBytes StrMatch CrossProd
        SocketReceive TPReadNum UIAlphaEntry SyncMoveOn WaitSyncTask""".split()
    assert {w.lower() for w in wanted} <= set(names)


def test_options_are_words_of_their_own():
    for key in ("arcl", "spotl", "paintl", "displ", "fcpressl", "search_1d", "bechecktcp", "pmgettarget"):
        w = words.word(key)
        assert w is not None and w.source.startswith("option: ") and w.category == w.source, key
    assert words.word("arcl").handling == "modelled" and words.word("fcact").handling == "unmodelled"
    assert words.word("nosuchword") is None


def test_what_the_interpreter_implements_is_modelled():
    table = words.words()
    for key in _registries():
        w = table.get(key)
        if w is None or w.source != "manual":
            continue
        assert w.handling == ("live" if key in LIVE_STUBS else "modelled"), (key, w.handling)


def test_what_is_modelled_is_implemented_or_being_added():
    implemented = _registries() - LIVE_STUBS
    modelled = [w for w in words.words().values() if w.handling == "modelled" and w.kind != "type"]
    missing = {w.name for w in modelled if w.name.lower() not in implemented | ADDED and not _in_grammar(w)}
    assert missing == set()


def test_types_the_interpreter_computes_with_are_modelled():
    computed = set(values.NUMBERS) | set(values.RECORDS) | set(values.SIGNALS) | {"bool", "string"}
    table = words.words()
    assert {k for k in computed if k in table and table[k].handling != "modelled"} == set()
    assert words.word("rawbytes").handling == "no-op" and words.word("signalxx").handling == "modelled"


def test_state_functions_have_their_answer():
    state = {k for k, w in words.words().items() if w.handling == "state"}
    assert state == set(words.STATE_VALUES)
    assert all(words.word(k).kind == "function" for k in state)
    assert all(isinstance(v, (float, bool, str)) for v in words.STATE_VALUES.values())


def test_parameters_as_the_manual_lays_them_out():
    setdo = words.word("setdo").params
    assert [(p.name, p.type, p.access, p.optional, p.switch, p.alt) for p in setdo] == [
        ("SDelay", "num", "IN", True, False, False), ("Sync", "switch", "IN", True, True, True),
        ("Signal", "signaldo", "VAR", False, False, False), ("Value", "dionum", "IN", False, False, False)]
    assert [p.access for p in words.word("getsysdata").params if not p.optional] == ["PERS"]
    assert [[p.name for p in g] for g in words.positions("add")] == [["Name", "Dname"], ["AddValue", "AddDvalue"]]


def test_signals_and_outputs():
    assert words.signal_params("setdo") == (0,)
    assert words.signal_params("waitdi") == (0,)
    assert words.signal_params("moveldo") == (4,)
    assert words.signal_params("searchl") == (0,)
    assert "dibreak" in words.signal_options("tpreadnum")
    assert {"dop", "gop", "aop"} <= words.signal_options("triggio")
    assert {"Str", "RawData", "Data"} <= {p.name for p in words.outputs("socketreceive")}
    assert "Socket" not in {p.name for p in words.outputs("socketreceive")}
    assert "TPAnswer" in {p.name for p in words.outputs("tpreadnum")}
    assert words.outputs("readnum") == ()
    assert words.signal_params("nosuchword") == () and words.outputs("nosuchword") == ()


@pytest.mark.parametrize("key", ["socketreceive", "readnum", "tpreadnum", "uialphaentry", "camgetresult"])
def test_live_reads(key):
    assert words.word(key).handling == "live"


def test_docs_show_the_table():
    doc = (ROOT / "docs" / "program.md").read_text()
    assert f"<!-- words: begin -->\n{words.markdown()}<!-- words: end -->" in doc


def test_the_table_imports_nothing_of_the_interpreter():
    source = (ROOT / "rswarp" / "rapid" / "words.py").read_text()
    assert not re.search(r"^\s*(from \.|import rswarp|from rswarp)", source, re.M)
