"""Bounded nesting (issue "Hardening the cell surfaces"): a cell file, a robot-data file, a TOML
file of design variables and a live input nested a hundred thousand deep are each one
``file:line: message`` and exit 1, never a RecursionError (exit 2)."""

from __future__ import annotations

import pytest

from rswarp.cli import main
from rswarp.examples import IRB2600, IRB2600_DRESSPACK, IRB2600_PROGRAM

DEEP = "[" * 100_000 + "]" * 100_000


def test_a_cell_file_nested_too_deep_is_one_line_at_its_line(tmp_path, capsys):
    cell = tmp_path / "deep.toml"
    cell.write_text(f'[robot]\nrsxml = "{IRB2600.as_posix()}"\nframe = {DEEP}\n')
    for command in (["check", str(cell)], ["info", str(cell)], ["program", str(cell), str(IRB2600_PROGRAM)]):
        assert main(command) == 1
        err = capsys.readouterr().err
        assert f"{cell}:3: TOML: nested too deep" in err and "Traceback" not in err


def test_a_toml_file_of_design_variables_nested_too_deep_is_one_line(tmp_path, capsys):
    vary = tmp_path / "vary.toml"
    vary.write_text(f"[vary]\nlength = {DEEP}\n")
    out = tmp_path / "sweep"
    assert main(["dresspack", str(IRB2600_DRESSPACK), "--program", str(IRB2600_PROGRAM), "--vary", str(vary),
                 "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert f"{vary}: not a TOML file of variables (nested too deep)" in err and not out.exists()


@pytest.mark.parametrize("value", [DEEP])
def test_a_live_input_nested_too_deep_is_refused_in_one_line(tmp_path, capsys, value):
    module = tmp_path / "read.mod"
    module.write_text("MODULE read\n  VAR num a{3};\n  PROC main()\n    TPReadNum a{1}, \"n?\";\n  ENDPROC\nENDMODULE\n")
    code = main(["program", str(IRB2600), str(module), "--input", f"a={value}"])
    err = capsys.readouterr().err
    assert code == 1 and "Traceback" not in err and "internal error" not in err
