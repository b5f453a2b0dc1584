"""What the controller checks when it loads a task, in every routine whether it runs or not:
procedures called by a name one or two letters from one that exists; routines called with
arguments that do not fit their parameters; data assigned to, or moved to, that is declared
nowhere; GOTO to a label the routine lacks. ``file:line`` errors before any statement runs.
Elsewhere a name declared nowhere may be an I/O signal, and an instruction or function rswarp
does not know may be the controller's: the run says so where it meets them."""

from __future__ import annotations

import difflib

from . import nodes as n
from .binding import ArgumentError, match_arguments
from .errors import fail
from .instructions import KNOWN
from .moves import MOVES
from .predefined import error_number
from .task import Task

# Optional arguments of a move that name data, never a signal.
_DATA_OPTIONS = {"wobj", "tload", "v", "t", "z", "inpos"}


def check_task(task: Task, predefined: set[str], signals: set[str]) -> None:
    """Every routine of ``task`` checked as the controller checks it at load (``predefined``: the
    controller's own data by lower-case name; ``signals``: those ``--io`` names)."""
    for module in task.modules:
        own = task.locals.get(module.name.lower(), {})
        data = {k for k, s in task.globals.items() if isinstance(s.node, n.Data)}
        data |= {k for k, s in own.items() if isinstance(s.node, n.Data)}
        routines = {k: s.node for k, s in task.globals.items() if isinstance(s.node, n.Routine)}
        routines.update({k: s.node for k, s in own.items() if isinstance(s.node, n.Routine)})
        names = {k: s.node.name for k, s in {**task.globals, **own}.items() if isinstance(s.node, n.Data)}
        for r in module.routines:
            _Routine(module.file, r, data | predefined | signals, names, routines).check()


class _Routine:
    """One routine's walk: its parameters, data and FOR variables, then the module's names."""

    def __init__(self, file: str, routine: n.Routine, known: set[str], names: dict, routines: dict):
        self.file, self.routine, self.known, self.routines = file, routine, known, routines
        self.own = {p.key: p.name for p in routine.params}
        self.own.update({d.name.lower(): d.name for d in routine.body.statements if d.__class__ is n.Data})
        self.names = {**names, **self.own}  # what a misspelt name may be meant for
        self.labels: set[str] = set()

    def check(self) -> None:
        bodies = [self.routine.body] + ([self.routine.error] if self.routine.error is not None else [])
        for body in bodies:
            self._labels(body)
        for body in bodies:
            self.body(body)

    def _labels(self, body: n.Body) -> None:
        for s in body.statements:
            if s.__class__ is n.Label:
                self.labels.add(s.name.lower())
            for inner in _bodies(s):
                self._labels(inner)

    def body(self, body: n.Body) -> None:
        for s in body.statements:
            self.statement(s)

    def statement(self, s) -> None:
        kind = s.__class__
        if kind is n.ProcCall:
            self.proc_call(s)
        elif kind is n.Assign:
            self.name(s.target, s.line, declared=True)
            self.expr(s.expr, s.line)
        elif kind is n.For:
            self.own[s.key] = s.var
            for e in (s.start, s.stop, s.step):
                self.expr(e, s.line)
        elif kind is n.Goto and s.label.lower() not in self.labels:
            fail(self.file, s.line, f"GOTO {s.label}: no such label in '{self.routine.name}'")
        elif kind is n.Data:
            for e in (*(s.dims or ()), s.init):
                self.expr(e, s.line)
        else:
            for e in _expressions(s):
                self.expr(e, s.line)
        for inner in _bodies(s):
            self.body(inner)

    def proc_call(self, s: n.ProcCall) -> None:
        routine = self.routines.get(s.key)
        if routine is not None:
            if routine.kind != "proc":
                fail(self.file, s.line, f"'{s.name}' is a {routine.kind.upper()}, not a procedure")
            self.arguments(routine, s.args, s.line)
        elif s.key not in KNOWN:
            near = difflib.get_close_matches(s.key, list(KNOWN) + list(self.routines), n=1, cutoff=0.8)
            if near:
                fail(self.file, s.line, f"unknown procedure '{s.name}' (did you mean {self._written(near[0])}?)")
        spec = MOVES.get(s.key) if routine is None else None
        count = sum(1 for a in s.args if not a.optional and a.name is None)
        index = 0
        for a in s.args:
            plain = not a.optional and a.name is None
            data = spec is not None and ((plain and _data_argument(spec, index, count)) or
                                         (a.optional and a.name.lower() in _DATA_OPTIONS))
            index += plain
            self.expr(a.expr, s.line, declared=data)

    def _written(self, key: str) -> str:
        routine = self.routines.get(key)
        return routine.name if routine is not None else KNOWN.get(key, key)

    def arguments(self, routine: n.Routine, args: tuple, line: int) -> None:
        try:
            match_arguments(routine, args, lambda name: False)
        except ArgumentError as exc:
            fail(self.file, line, str(exc))
        for a in args:
            if a.condition is not None and a.condition.lower() not in self.own:
                fail(self.file, line, f"\\{a.name}?{a.condition}: '{a.condition}' is not a parameter of "
                                      f"'{self.routine.name}'")

    def expr(self, e, line: int, declared: bool = False) -> None:
        """Every name and call in expression ``e``; ``declared``: it must be declared data (a
        move's target, speed, zone or tool: never a signal)."""
        if e is None:
            return
        kind = e.__class__
        if kind is n.Name:
            self.name(e, line, declared)
        elif kind is n.Call:
            self.call(e, line)
        for sub in _subexpressions(e):
            self.expr(sub, line)

    def call(self, e: n.Call, line: int) -> None:
        routine = self.routines.get(e.key)
        if routine is not None:
            if routine.kind != "func":
                fail(self.file, e.line, f"'{e.name}' is a {routine.kind.upper()}, not a function")
            self.arguments(routine, e.args, e.line)
        for a in e.args:
            self.expr(a.expr, e.line)

    def name(self, e: n.Name, line: int, declared: bool) -> None:
        """A name that must be data (assigned to, a move's target, speed, zone, tool or work
        object) and is declared nowhere; elsewhere a name declared nowhere may be a signal, which
        only the I/O configuration knows, and the run says so where it reads one."""
        key = e.key
        if not declared or key in self.own or key in self.known or error_number(key) is not None:
            return
        near = difflib.get_close_matches(key, list(self.names), n=1, cutoff=0.85)
        hint = f" (did you mean '{self.names[near[0]]}'?)" if near else ""
        fail(self.file, e.line or line, f"'{e.name}' is declared nowhere in the task{hint}")


def _data_argument(spec, index: int, count: int) -> bool:
    """Whether positional argument ``index`` of a move (of ``count``) is a target, speed, zone or
    tool: data, never a signal."""
    places = {k % count for k in (*spec.targets, spec.speed, spec.tool) if -count <= k < count}
    if spec.zone is not None and -count <= spec.zone < count:
        places.add(spec.zone % count)
    return index in places


def _bodies(s) -> list:
    kind = s.__class__
    if kind is n.If:
        return [b for _, b in s.branches] + ([s.otherwise] if s.otherwise is not None else [])
    if kind in (n.For, n.While):
        return [s.body]
    if kind is n.Test:
        return [b for _, b in s.cases] + ([s.default] if s.default is not None else [])
    return []


def _expressions(s) -> list:
    """The expressions of a statement other than a call, an assignment or a FOR."""
    kind = s.__class__
    if kind is n.If:
        return [c for c, _ in s.branches]
    if kind is n.While:
        return [s.condition]
    if kind is n.Test:
        return [s.expr] + [v for values, _ in s.cases for v in values]
    if kind in (n.Return, n.Jump):
        return [s.expr]
    if kind is n.LateCall:
        return [s.expr] + [a.expr for a in s.args]
    if kind is n.Connect:
        return [s.target]
    return []


def _subexpressions(e) -> list:
    kind = e.__class__
    if kind is n.Name:
        return [i for sel in e.selectors if sel.__class__ is n.Index for i in sel.items]
    if kind is n.Call:
        return [i for sel in e.selectors if sel.__class__ is n.Index for i in sel.items]
    if kind is n.Prefix:
        return [e.operand]
    if kind is n.Chain:
        return [e.first] + [operand for _, operand in e.rest]
    if kind is n.Aggregate:
        return list(e.items)
    return []
