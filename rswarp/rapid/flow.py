"""How control leaves the statement running: a GOTO to a label, a RETURN with its value, the task's
EXIT, ExitCycle. Exceptions, caught where RAPID's structure says the jump lands."""

from __future__ import annotations


class Goto(Exception):
    def __init__(self, label: str, line: int):
        self.label, self.line = label, line


class Returned(Exception):
    def __init__(self, value):
        self.value = value


class ExitTask(Exception):
    """EXIT: the task ends."""


class ExitCycle(Exception):
    """ExitCycle: the cycle ends; the next starts from the entry routine."""
