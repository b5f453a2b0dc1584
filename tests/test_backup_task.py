"""A MultiMove backup's tasks (issue "Real programs in real cells"): its folder runs its first task
by default, with a note naming the others; ``--task`` runs another; a task it lacks is an error
naming those it has."""

from __future__ import annotations

from rswarp.cli import main
from rswarp.examples import IRB2600
from rswarp.motion.plan import program_plan

from conftest import DATA

BACKUP = DATA / "rapid" / "wild" / "multimove"


def test_the_first_task_by_default_and_another_by_name():
    notes = []
    _, first = program_plan(str(IRB2600), [str(BACKUP)], warn=notes.append, strict=False)
    _, second = program_plan(str(IRB2600), [str(BACKUP)], motion_task="t_rob2", strict=False)
    assert {m.motion.file.split("/")[-1] for m in first.moves} == {"MM_Rob1.mod"}
    assert {m.motion.file.split("/")[-1] for m in second.moves} == {"MM_Rob2.mod"}
    assert any("holds the tasks T_ROB1, T_ROB2: running T_ROB1 (--task names another)" in n for n in notes)


def test_a_task_the_backup_lacks_is_an_error_naming_those_it_has(capsys):
    assert main(["program", str(IRB2600), str(BACKUP), "--task", "T_ROB3"]) == 1
    assert "--task T_ROB3: the backup has no such task (it has T_ROB1, T_ROB2)" in capsys.readouterr().err
