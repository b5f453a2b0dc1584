"""What the controller checks when it loads a task, in every routine whether it runs or not:
procedures called by a name one or two letters from one that exists; routines called with
arguments that do not fit their parameters; a name that is declared nowhere; GOTO to a label the
routine lacks. ``file:line`` errors before any statement runs.

A name declared nowhere is a signal where RAPID expects one (an argument the reference manual
types as a signal: ``SetDO``, ``WaitDI``, ``DInput``, ``\\DOp``, a routine's signal parameter), or
where the I/O configuration (a backup's EIO.cfg, ``--io``) declares it; anything else is an error
saying what its use makes it and where such data usually lives; with ``--assume-missing`` it is
taken, by its use, as a stand-in (``Assumed``: a tooldata or wobjdata at the identity with no load,
a speeddata v1000, a zonedata fine, a num 0), and only a target declared nowhere stays an error.
Arguments of a procedure that neither RAPID nor the task defines (an option's) are not checked:
only that option knows them."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import Diagnostic, RsxmlError, nearest
from . import nodes as n
from . import words
from .binding import ArgumentError, match_arguments
from .functions import FUNCTIONS
from .instructions import KNOWN
from .moves import MOVES
from .predefined import error_number
from .task import Task


@dataclass
class Assumed:
    """A name declared nowhere, taken as a stand-in of the type its use makes it (``--assume-missing``):
    where it is first used, and every line that uses it."""

    name: str
    type: str
    file: str
    line: int
    uses: set = field(default_factory=set)  # (file, line)


STAND_INS = ("tooldata", "wobjdata", "loaddata", "speeddata", "zonedata", "num")  # the types a stand-in may take


def check_task(task: Task, predefined: set[str], signals: set[str], assume: dict | None = None) -> None:
    """Every routine of ``task`` checked as the controller checks it at load (``predefined``: the
    controller's own data by lower-case name; ``signals``: those ``--io`` names). ``assume``: a
    dict that takes each name declared nowhere that a stand-in can take (lower-case name ->
    ``Assumed``) instead of its error."""
    signals = set(signals) | set(task.signals) | signal_uses(task)
    problems: list[Diagnostic] = []
    for module in task.modules:
        own = task.locals.get(module.name.lower(), {})
        data = {k for k, s in task.globals.items() if isinstance(s.node, n.Data)}
        data |= {k for k, s in own.items() if isinstance(s.node, n.Data)}
        routines = {k: s.node for k, s in task.globals.items() if isinstance(s.node, n.Routine)}
        routines.update({k: s.node for k, s in own.items() if isinstance(s.node, n.Routine)})
        names = {k: s.node.name for k, s in {**task.globals, **own}.items() if isinstance(s.node, n.Data)}
        for r in module.routines:
            _Routine(module.file, r, data | predefined, names, routines, signals, problems, assume).check()
        _module_data(module, data | predefined, names, routines, signals, problems, assume)
    if problems:  # every one at once, as the controller lists them when it loads the task
        order = {f: k for k, f in enumerate(task.files)}
        raise RsxmlError(sorted(problems, key=lambda d: (order.get(d.file, 0), d.line)))


def _module_data(module: n.Module, known: set[str], names: dict, routines: dict, signals: set[str],
                 problems: list, assume: dict | None = None) -> None:
    """The values a module's data are declared with, checked as a routine's statements are."""
    inits = [d for d in module.data if d.init is not None or d.dims]
    if not inits:
        return
    holder = n.Routine(module.line, "proc", f"the data of {module.name}", "", None, (), n.Body(()), False)
    walk = _Routine(module.file, holder, known, names, routines, signals, problems, assume)
    for d in inits:
        for e in (*(d.dims or ()), d.init):
            walk.expr(e, d.line)


class _Routine:
    """One routine's walk: its parameters, data and FOR variables, then the module's names."""

    def __init__(self, file: str, routine: n.Routine, known: set[str], names: dict, routines: dict,
                 signals: set[str] = frozenset(), problems: list | None = None, assume: dict | None = None):
        self.file, self.routine, self.known, self.routines = file, routine, known, routines
        self.assume = assume
        self.signals = signals
        self.problems = problems if problems is not None else []
        self.own = {p.key: p.name for p in routine.params}
        self.own.update({d.name.lower(): d.name for d in routine.body.statements if d.__class__ is n.Data})
        self.names = {**names, **self.own}  # what a misspelt name may be meant for
        self.labels: set[str] = set()

    def problem(self, line: int, message: str) -> None:
        """A problem the controller would refuse the task for; said once a place, all of them at once."""
        d = Diagnostic(self.file, line, message)
        if len(self.problems) < 1000 and d not in self.problems:
            self.problems.append(d)

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
            self.problem(s.line, f"GOTO {s.label}: no such label in '{self.routine.name}'")
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
                self.problem(s.line, f"'{s.name}' is a {routine.kind.upper()}, not a procedure")
            self.arguments(routine, s.args, s.line)
        elif s.key not in KNOWN and words.word(s.key) is None:
            near = nearest(s.key, [*KNOWN, *self.routines])
            if near:
                self.problem(s.line, f"unknown procedure '{s.name}' (did you mean {self._written(near)}?)")
            return  # an option's instruction: only the option knows what its arguments name
        spec = MOVES.get(s.key) if routine is None else None
        count = sum(1 for a in s.args if not a.optional and a.name is None)
        index = 0
        for a in s.args:
            plain = not a.optional and a.name is None
            role = _role(spec, index, count) if spec is not None and plain else \
                _OPTION_ROLES.get(a.name.lower()) if spec is not None and a.optional else \
                _typed(words.positions(s.key), index) if routine is None and plain else None
            index += plain
            self.expr(a.expr, s.line, role=role)

    def _written(self, key: str) -> str:
        routine = self.routines.get(key)
        return routine.name if routine is not None else KNOWN.get(key, key)

    def arguments(self, routine: n.Routine, args: tuple, line: int) -> None:
        try:
            match_arguments(routine, args, lambda name: False)
        except ArgumentError as exc:
            self.problem(line, str(exc))
        for a in args:
            if a.condition is not None and a.condition.lower() not in self.own:
                self.problem(line, f"\\{a.name}?{a.condition}: '{a.condition}' is not a parameter of "
                                      f"'{self.routine.name}'")

    def expr(self, e, line: int, role: str | None = None, declared: bool = False) -> None:
        """Every name and call in expression ``e``; ``role``: the data type its place makes it (a
        move's robtarget, speeddata, zonedata, tooldata or wobjdata: never a signal)."""
        if e is None:
            return
        kind = e.__class__
        if kind is n.Name:
            self.name(e, line, declared, role)
        elif kind is n.Call:
            self.call(e, line)
        for sub in _subexpressions(e):
            self.expr(sub, line)

    def call(self, e: n.Call, line: int) -> None:
        routine = self.routines.get(e.key)
        if routine is not None:
            if routine.kind != "func":
                self.problem(e.line, f"'{e.name}' is a {routine.kind.upper()}, not a function")
            self.arguments(routine, e.args, e.line)
        elif words.word(e.key) is None and e.key not in FUNCTIONS:
            return  # an option's function: only the option knows what its arguments name
        places = words.positions(e.key) if routine is None else ()
        index = 0
        for a in e.args:
            plain = not a.optional and a.name is None
            role = _typed(places, index) if plain else None
            index += plain
            self.expr(a.expr, e.line, role=role)

    def name(self, e: n.Name, line: int, declared: bool, role: str | None = None) -> None:
        """A name declared nowhere: an error, unless it is read where a signal may stand (the I/O
        configuration's, or one the task uses as a signal)."""
        key = e.key
        if key in self.own or key in self.known or error_number(key) is not None:
            return
        if not (declared or role) and key in self.signals:
            return
        if self.assume is not None and (role or "num") in STAND_INS:
            self._assumed(e, role or "num", e.line or line)
            return
        near = nearest(key, self.names)
        hint = f" (did you mean '{self.names[near]}'?)" if near else _lives(role)  # a typo: no stand-in offered
        self.problem(e.line or line, f"'{e.name}' is declared nowhere in the task{hint}")


    def _assumed(self, e: n.Name, role: str, line: int) -> None:
        """A name declared nowhere taken as a stand-in: its first use's type, a record type over a num."""
        found = self.assume.get(e.key)
        if found is None:
            found = self.assume[e.key] = Assumed(e.name, role, self.file, line)
        elif found.type == "num" and role != "num":
            found.type = role
        found.uses.add((self.file, line))


def _role(spec, index: int, count: int) -> str | None:
    """The data type positional argument ``index`` of a move (of ``count``) must be: its target,
    speed, zone or tool, never a signal; None for the others."""
    target = "jointtarget" if spec.kind == "absolute" else "robtarget"
    places = [(k, target) for k in spec.targets] + [(spec.speed, "speeddata"), (spec.tool, "tooldata")]
    if spec.zone is not None:
        places.append((spec.zone, "zonedata"))
    for k, type_ in places:
        if -count <= k < count and k % count == index:
            return type_
    return None


_OPTION_ROLES = {"wobj": "wobjdata", "tload": "loaddata", "v": "num", "t": "num", "z": "num", "inpos": "stoppointdata"}
_HOMES = {"tooldata": "tools usually live in CalibData.mod or user.sys",
          "wobjdata": "work objects usually live in CalibData.mod or user.sys",
          "loaddata": "loads usually live in CalibData.mod or user.sys",
          "robtarget": "targets live in the program's modules or a module of targets",
          "jointtarget": "targets live in the program's modules or a module of targets",
          "speeddata": "speeds usually live in user.sys or a module of data",
          "zonedata": "zones usually live in user.sys or a module of data"}


def _typed(places, index: int) -> str | None:
    """The record type the manual gives a built-in's argument ``index``, where it is one whose
    home this says (a robtarget, a tooldata, ...): never a signal."""
    if index < len(places):
        types = {p.type.lower() for p in places[index]}
        if len(types) == 1 and next(iter(types)) in _HOMES:
            return next(iter(types))
    return None


def _lives(role: str | None) -> str:
    """What a name's place makes it and where such data usually lives: the file to add (or, for
    what a stand-in can take, ``--assume-missing``)."""
    if role in _HOMES:
        flag = "; or --assume-missing runs it with a stand-in" if role in STAND_INS else ""
        return f": a {role} here ({_HOMES[role]}: add that module to the task{flag})"
    return (": data of a module the task lacks (user.sys, an option's module), or an I/O signal (a backup's "
            "SYSPAR/EIO.cfg, or --io NAME=VALUE, declares it; or --assume-missing runs it with a stand-in)")


def signal_uses(task: Task) -> set[str]:
    """The names the task uses where RAPID expects a signal: the manual's signal parameters of its
    instructions and functions, and signal parameters of the task's own routines."""
    routines = {s.node.name.lower(): s.node for s in task._all() if isinstance(s.node, n.Routine)}
    out: set[str] = set()
    for module in task.modules:
        for r in module.routines:
            for e in _calls(r.body, r.error):
                out |= _signal_arguments(e, routines.get(e.key))
    return out


def _signal_arguments(call, routine) -> set[str]:
    """The bare names a call passes where a signal is expected."""
    if routine is not None:
        places = tuple(k for k, p in enumerate(q for q in routine.params if not q.optional)
                       if p.type.lower() in words.CONFIGURED_TYPES)
        options = frozenset(p.key for p in routine.params if p.optional and p.type.lower() in words.CONFIGURED_TYPES)
    else:
        places, options = words.signal_params(call.key), words.signal_options(call.key)
    out = set()
    plain = [a for a in call.args if not a.optional and a.name is None]
    for k in places:
        if k < len(plain) and plain[k].expr.__class__ is n.Name:
            out.add(plain[k].expr.key)
    for a in call.args:
        if a.optional and a.name.lower() in options and a.expr.__class__ is n.Name:
            out.add(a.expr.key)
    return out


def _calls(*bodies):
    """Every procedure and function call in the bodies, nested ones included."""
    for body in bodies:
        if body is None:
            continue
        for s in body.statements:
            if s.__class__ is n.ProcCall:
                yield s
            exprs = [a.expr for a in s.args] if s.__class__ is n.ProcCall else \
                [s.expr] if s.__class__ is n.Assign else _expressions(s)
            for e in exprs:
                yield from _nested_calls(e)
            yield from _calls(*_bodies(s))


def _nested_calls(e):
    if e is None:
        return
    if e.__class__ is n.Call:
        yield e
        for a in e.args:
            yield from _nested_calls(a.expr)
    for sub in _subexpressions(e):
        yield from _nested_calls(sub)


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

