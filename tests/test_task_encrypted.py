"""ABB's encrypted system modules in a task (issue 60): binary files (NUL bytes, or mostly control
characters) that the controller loads and rswarp cannot read. In a task's folder (a backup's task,
a .pgf's list) one is skipped with one warning naming it, and the task runs without it: a name it
needed from it is the usual "declared nowhere" error at its use. One named by itself on the command
line is refused: that file is all the user asked for. The binary files are made here, small."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from rswarp.errors import RsxmlError
from rswarp.motion.plan import program_plan
from rswarp.rapid.task import load_task

ROOT = Path(__file__).resolve().parents[1]
ROBOT = ROOT / "examples" / "irb2600_12_165" / "IRB2600_12_165__01.rsxml"
SKIPPED = "an encrypted module: skipped; only what the task needs from it is missing"

MAIN = """MODULE MainModule
  CONST robtarget pPick := [[900, 0, 800], [0, 0, 1, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]];
  PROC main()
    MoveJ pPick, v1000, fine, tool0;
    MoveL Offs(pPick, 0, 0, 100), v200, fine, tool0;
  ENDPROC
ENDMODULE
"""
NEEDS_TOOL = MAIN.replace("tool0;\n    MoveL", "tGun;\n    MoveL")  # tGun: declared in the encrypted module


def encrypted(path: Path, nul: bool = True) -> Path:
    """A small binary file in the manner of an encrypted module: a few bytes of header, then
    bytes that are no text (with NUL bytes, or without: control characters)."""
    body = bytes((k * 37 + 11) % 256 for k in range(600))
    if not nul:
        body = bytes(b % 31 + 1 if b % 3 else b for b in body).replace(b"\x00", b"\x01")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(b"ABBENC\x01" + body)
    return path


def task_folder(tmp_path: Path, main: str = MAIN, nul: bool = True) -> Path:
    folder = tmp_path / "backup" / "RAPID" / "TASK1"
    (folder / "PROGMOD").mkdir(parents=True)
    (folder / "PROGMOD" / "MainModule.mod").write_text(main)
    encrypted(folder / "SYSMOD" / "ScrewSys.sys", nul)
    return folder


@pytest.mark.parametrize("nul", [True, False])
def test_an_encrypted_module_in_a_task_folder_is_skipped_with_one_warning(tmp_path, nul):
    folder = task_folder(tmp_path, nul=nul)
    task = load_task([folder])
    assert [m.name for m in task.modules] == ["MainModule"]
    notes = [str(n) for n in task.notes]
    assert notes == [f"{folder / 'SYSMOD' / 'ScrewSys.sys'}: warning: {SKIPPED}"]
    said: list[str] = []
    _, plan = program_plan(str(ROBOT), [str(tmp_path / "backup")], warn=said.append)
    assert not plan.errors and [m.line for m in plan.moves] == [4, 5]
    assert sum(SKIPPED in w for w in said) == 1


def test_a_name_the_task_needs_from_it_is_declared_nowhere_at_its_use(tmp_path):
    folder = task_folder(tmp_path, NEEDS_TOOL)
    with pytest.raises(RsxmlError, match="'tGun' is declared nowhere in the task") as exc:
        program_plan(str(ROBOT), [str(folder)])
    assert exc.value.line == 4 and exc.value.file.endswith("MainModule.mod")


def test_a_program_file_naming_an_encrypted_module_skips_it(tmp_path):
    (tmp_path / "MainModule.mod").write_text(MAIN)
    encrypted(tmp_path / "ScrewSys.sys")
    pgf = tmp_path / "task.pgf"
    pgf.write_text('<?xml version="1.0" encoding="ISO-8859-1" ?>\n<Program>\n    <Module>ScrewSys.sys</Module>\n'
                   '    <Module>MainModule.mod</Module>\n</Program>\n')
    task = load_task([pgf])
    assert [m.name for m in task.modules] == ["MainModule"] and SKIPPED in task.notes[0].message


def test_an_encrypted_module_named_by_itself_is_refused(tmp_path):
    main = tmp_path / "MainModule.mod"
    main.write_text(MAIN)
    secret = encrypted(tmp_path / "ScrewSys.sys")
    with pytest.raises(RsxmlError) as exc:
        load_task([main, secret])
    assert str(exc.value) == f"{secret}: not a RAPID text file: it holds NUL bytes (binary, or an encrypted " \
                             "module); in a task's folder an encrypted module is skipped with a warning"
    run = subprocess.run([sys.executable, "-m", "rswarp.cli", "program", str(ROBOT), str(main), str(secret)],
                         capture_output=True, text=True, cwd=ROOT)
    assert run.returncode == 1 and "ScrewSys.sys: not a RAPID text file" in run.stderr
    folder = tmp_path / "only"
    encrypted(folder / "ScrewSys.sys")
    with pytest.raises(RsxmlError, match=r"every module of the task is encrypted \(ScrewSys.sys\): rswarp reads "
                                         r"none, so there is nothing to run"):
        load_task([folder])
