"""A task's data as the controller loads it: every module's data made, no routine run (what a
payload read from a tooldata needs)."""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from .interpret import Interpreter
from .scope import Cell
from .task import Task


def declared(task: Task, name: str) -> Cell:
    """The data object ``name`` of ``task`` (type, value, file, line); an InputError where the
    task has none of that name."""
    interp = Interpreter(task)
    interp._declare_all()  # what run() does first; nothing runs after it
    for scope in interp.scopes.values():
        cell = scope.get(name.lower())
        if isinstance(cell, Cell):
            return cell
    files = ", ".join(Path(f).name for f in task.files)
    raise InputError(f"no data named '{name}' in {files}")
