"""How control flows through a routine's statements: IF and TEST choose a body, FOR and WHILE run
one again, a label marks where a GOTO lands; and how control leaves the statement running: a GOTO
to a label, a RETURN with its value, the task's EXIT, ExitCycle (exceptions, caught where RAPID's
structure says the jump lands). A loop whose condition reads nothing that its pass changed can
never end: one with moves is the task's main loop and runs the run's ``cycles`` passes, one
without is taken as ended after a pass (``endless_pass``); both are warnings."""

from __future__ import annotations

from . import nodes as n
from .errors import fail
from .live import Live, LiveValue
from .scope import Cell

MAX_CYCLES = 1000  # passes of the main loop one run may ask for (--cycles)


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


def run_if(interp, s: n.If, frame) -> None:
    for condition, body in s.branches:
        if interp.boolean(condition, frame):
            interp.body(body, frame)
            return
    if s.otherwise is not None:
        interp.body(s.otherwise, frame)


def run_for(interp, s: n.For, frame) -> None:
    start = interp.number(s.start, frame, "FOR's start")
    stop = interp.number(s.stop, frame, "FOR's end")
    step = interp.number(s.step, frame, "FOR's STEP") if s.step is not None else (1.0 if start <= stop else -1.0)
    if step == 0:
        fail(interp.path, s.line, "FOR with a STEP of 0 never ends")
    saved = frame.cells.get(s.key)
    cell = frame.cells[s.key] = Cell(start, "num", "loop", interp.path, s.line, s.var)
    try:
        i = start
        while (i <= stop) if step > 0 else (i >= stop):
            cell.set(i)
            interp.body(s.body, frame)
            i += step
    finally:
        if saved is None:
            frame.cells.pop(s.key, None)
        else:
            frame.cells[s.key] = saved


def run_while(interp, s: n.While, frame) -> None:
    before, starts = None, None
    while True:
        reads, value = reading(interp, s.condition, frame)
        if not value:
            return
        seen = tuple((c, c.stamp) for c in reads)
        if before is not None and seen == before and endless_pass(interp, s, starts, reads):
            return
        before = seen
        if starts is None:
            starts = interp.loop_passes[id(s)] = []
        starts.append(interp.mark())
        interp.body(s.body, frame)


def reading(interp, condition, frame):
    """(cells read, value) of a loop's condition; a condition that asks the clock or the robot
    reads a fresh cell, so it is never taken as unchanging."""
    outer, interp.reads = interp.reads, []
    try:
        value = interp.boolean(condition, frame)
        reads = interp.reads
    finally:
        interp.reads = outer
    if outer is not None:
        outer.extend(reads)
    return reads, value


def endless_pass(interp, node, starts: list, reads=()) -> bool:
    """A pass of a loop that cannot end is over: whether to leave the loop now (a loop whose
    pass made no move at once, the main loop after its cycles)."""
    if interp.moves == starts[-1][1]:
        names = sorted({c.name for c in reads if c.name})
        what = f"it reads {', '.join(names[:3])}, which nothing in the task sets" if names else "it reads nothing"
        interp.warn(node.line, f"a loop whose condition never changes ({what}): taken as ended after one pass")
        return True
    if interp.main_loop is None or interp.main_loop[0] is node:
        interp.main_loop = (node, interp.path, starts)
        if len(starts) >= interp.cycles and (not interp.inputs.pending() or len(starts) >= MAX_CYCLES):
            ran = len(starts)
            why = "(--cycles)" if ran == interp.cycles else f"(--cycles {interp.cycles}, and on while --input " \
                                                            "values were left)"
            interp.warn(node.line, f"the main loop never ends: ran {ran} pass{'es' if ran > 1 else ''} {why}")
            return True
        interp.pass_index = len(starts)
        return False
    return True


def run_test(interp, s: n.Test, frame) -> None:
    value = interp.ev(s.expr, frame)
    if value.__class__ is Live:
        raise LiveValue(value)
    for values, body in s.cases:
        if any(interp.operate("=", value, interp.ev(v, frame), s.line) for v in values):
            interp.body(body, frame)
            return
    if s.default is not None:
        interp.body(s.default, frame)


def run_goto(interp, s: n.Goto, frame) -> None:
    raise Goto(s.label.lower(), s.line)


def run_label(interp, s: n.Label, frame) -> None:
    interp.label_at[id(s)] = interp.mark()
