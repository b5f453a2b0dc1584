"""A RAPID task run as the controller runs it: the task's data declared and initialized, then the
entry routine walked statement by statement over the tree parsed once, with a frame of its own
data per call. Procedures and functions take their arguments as RAPID passes them (by value, or
by reference for INOUT, VAR and PERS; optional ones, switches, conditional ones), loops and GOTO
run, and every move or wait becomes a ``Motion`` with its file, line and call chain.

Nothing runs without end: a loop whose condition reads nothing that its pass changed can never
end (``WHILE TRUE``, a wait for a signal that stays 0): one with moves is the task's main loop and
runs ``cycles`` passes, one without is taken as ended after a pass; both are reported (the loops,
branches and labels run in ``flow``). A task
that runs ``MAX_STATEMENTS`` statements, or calls deeper than ``MAX_DEPTH``, stops with a
``file:line`` error."""

from __future__ import annotations

import contextlib
import sys

from ..errors import Diagnostic, Diagnostics, RsxmlError, nearest
from ..files import no_cyclic_gc
from . import flow, handlers
from . import nodes as n
from .binding import bind
from .check import check_task
from .errors import RapidError, fail
from .expressions import Evaluator
from .flow import MAX_CYCLES, ExitCycle, ExitTask, Goto, Returned
from .functions import call_function
from .instructions import clock_read, run_instruction
from .live import Inputs, Live, LiveValue, NeedsInput, input_value
from .motion import Cycle, Motion, NoRobot, Run
from .predefined import predefined
from .scope import PENDING, Cell, Frame, ModuleScope, replace
from .task import Task
from .values import Arr, Mismatch

MAX_STATEMENTS = 5_000_000  # statements one run executes
MAX_MOTIONS = 1_000_000  # moves and waits of one run
MAX_DEPTH = 100  # routine calls nested
STAND_IN = {"tooldata": "tool0", "wobjdata": "wobj0", "loaddata": "load0", "speeddata": "v1000",
            "zonedata": "fine"}  # --assume-missing: the predefined data a stand-in takes its value from


class Interpreter(Evaluator):
    """One run of a task. ``io`` sets signals (name -> value); ``robot`` answers CRobT and kin."""

    def __init__(self, task: Task, robot=None, io: dict | None = None, cycles: int = 1,
                 inputs: dict[str, list[str]] | None = None, assume_missing: bool = False):
        if not 1 <= cycles <= MAX_CYCLES:
            raise ValueError(f"cycles must be 1 to {MAX_CYCLES}")
        self.task, self.types, self.robot = task, task.types, robot or NoRobot()
        self.cycles = cycles
        self.given = {k.lower() for k in (io or {})}
        self.given_names = list(io or {})
        self.used_signals: set[str] = set()
        self.signals = {k.lower(): Cell(float(v), "signal", "var", "", 0, k) for k, v in (io or {}).items()}
        for key, sig in task.signals.items():  # a backup's I/O configuration: its signals at their defaults
            self.signals.setdefault(key, Cell(sig.default, "signal", "var", sig.file, sig.line, sig.name))
        self.motions: list[Motion] = []
        self.warnings = Diagnostics()
        self._warned: set = set()
        self.path = task.files[0] if task.files else ""
        self.statements = 0
        self.depth = 0
        self.state = {"conf_j": True, "conf_l": True, "accel": 1.0, "ramp": 1.0, "override": 1.0, "vmax": None,
                      "tool": None, "wobj": None}
        self.clocks: dict = {}  # clock cells -> (running since, seconds so far)
        self.waited = 0.0  # seconds of waits so far (the clocks' time without a robot)
        self.loop_passes: dict = {}
        self.label_at: dict = {}
        self.moves = 0  # motions that move (not waits)
        self.main_loop: tuple | None = None  # (node, file, pass starts)
        self.pass_index = 0
        self._pending: dict = {}
        self.converted: dict = {}  # records already converted to SI motion data (Arguments.si)
        self.inputs = Inputs(inputs)  # --input: what live reads give, name by name
        self.stopped: NeedsInput | None = None  # where the run stopped for a live input
        self.assume_missing = assume_missing
        self.assumed: dict = {}  # name -> check.Assumed: the stand-ins of names declared nowhere
        self.failed: tuple | None = None  # (Diagnostic, call chain): the run-time error the run stopped at

    # -- reporting ------------------------------------------------------------------------------
    def warn_once(self, key, line: int, message: str) -> None:
        """A warning said once a task for ``key``, at its first line."""
        if key not in self._warned:
            self._warned.add(key)
            self.warnings.append(Diagnostic(self.path, line, message, "warning"))

    def warn(self, line: int, message: str) -> None:
        key = (self.path, line, message)
        if key not in self._warned:
            self._warned.add(key)
            self.warnings.append(Diagnostic(self.path, line, message, "warning"))

    # -- the run ----------------------------------------------------------------------------------
    def run(self, routine: str = "main", keep: bool = False) -> Run:
        """The task run from ``routine``; with ``keep``, a run-time error stops it where it is, as the
        controller stops, kept in ``Run.error`` with every motion before it (else it is raised)."""
        entry = self.task.routine(routine)
        with _deep_stack():
            with no_cyclic_gc():  # a module's 100 000 targets: no cycles, and the collector's passes cost
                self._declare_all()
            starts = []
            for _ in range(self.cycles):
                starts.append(len(self.motions))
                try:
                    self.call(entry, (), None, 0)
                except ExitCycle:
                    pass
                except ExitTask:
                    break
                except NeedsInput as stop:  # every move before it stands, planned and timed
                    self.stopped = stop
                    break
                except RsxmlError as exc:  # a run-time error: the task stops at its line, every move before stands
                    if not keep:
                        raise
                    self.failed = (exc.diagnostics[0], getattr(exc, "chain", ()))
                    break
                if self.main_loop is not None:
                    break
                self.pass_index += 1
        for name in sorted(k for k in self.given_names if k.lower() not in self.used_signals):
            near = nearest(name.lower(), sorted(self.used_signals))
            hint = f" (did you mean {self.signals[near].name}?)" if near else ""
            self.warnings.append(Diagnostic("rswarp", 0, f"--io {name}: the task uses no signal of that name{hint}",
                                            "warning"))
        for name in self.inputs.unused():
            near = nearest(name, sorted(self.inputs.asked))
            said = "values were left unread" if name.lower() in self.inputs.asked else \
                "the task reads no live input into that name" + (f" (did you mean {near}?)" if near else "")
            self.warnings.append(Diagnostic("rswarp", 0, f"--input {name}: {said}", "warning"))
        cut = self.stopped is not None or self.failed is not None  # a pass the stop cut short is no cycle
        if self.main_loop is not None:
            node, file, passes = self.main_loop
            ends = () if cut else (len(self.motions),)
            cycle = Cycle(file, node.line, tuple(p[0] for p in passes) + ends)
        else:
            done = tuple(starts) if not cut else tuple(starts[:-1])
            cycle = Cycle(entry.file, entry.line, done + (() if cut else (len(self.motions),)), endless=False)
        return Run(tuple(self.motions), tuple(self.task.notes) + tuple(self.warnings.finish()), cycle,
                   tuple(self.task.files), entry.name, self.statements,
                   stopped=self.stopped.diagnostic() if self.stopped else None,
                   needs_input=self.stopped.record() if self.stopped else None,
                   error=self.failed[0] if self.failed else None, error_chain=self.failed[1] if self.failed else (),
                   assumed=tuple(self.assumed.values()))

    # -- data -------------------------------------------------------------------------------------
    def _declare_all(self) -> None:
        """A cell for every module's data, the scopes of every module, then each value in order
        (a value that needs a later one has it made first)."""
        base = {k: Cell(v, t, s, "", 0, k) for k, (t, s, v) in predefined(self.types).items()}
        assumed = {} if self.assume_missing else None
        check_task(self.task, set(base), set(self.signals), assumed)  # as the controller loads it: every routine
        for key, a in (assumed or {}).items():  # --assume-missing: each a variable of its stand-in's value
            value = base[STAND_IN[a.type]].value if a.type in STAND_IN else 0.0
            base[key] = Cell(value, a.type, "var", a.file, a.line, a.name)
        self.assumed = assumed or {}
        cells: dict[int, Cell] = {}
        shared: dict[str, Cell] = {}  # a global PERS declared in several modules is one object
        for sym in self.task.globals.values():
            if isinstance(sym.node, n.Data):
                key = sym.node.name.lower()
                cells[id(sym.node)] = shared.setdefault(key, self._cell(sym.node, sym.module))
        global_cells = {k: c for k, c in shared.items()}
        self.scopes = {}
        for m in self.task.modules:
            own = {}
            for d in m.data:
                c = cells.get(id(d))
                if c is None:
                    c = self._cell(d, m) if not (d.storage == "pers" and d.name.lower() in shared and
                                                 d.scope != "local") else shared[d.name.lower()]
                    cells[id(d)] = c
                own[d.name.lower()] = c
            scope = dict(base)
            scope.update(global_cells)
            scope.update(own)
            self.scopes[m.name.lower()] = ModuleScope(scope, m, self.task)
        for m in self.task.modules:
            for d in m.data:
                self._initialize(cells[id(d)])

    def _cell(self, d: n.Data, module: n.Module) -> Cell:
        cell = Cell(PENDING, d.type, d.storage, module.file, d.line, d.name)
        self._pending[id(cell)] = (d, module)
        return cell

    def _initialize(self, cell: Cell):
        pending = self._pending.pop(id(cell), None)
        if pending is None:
            if cell.value is PENDING:
                fail(cell.file, cell.line, f"'{cell.name}' is initialized from itself")
            return cell.value
        d, module = pending
        saved = self.path
        self.path = module.file
        if d.init.__class__ is n.Literal and not d.dims:  # most of a module of targets: no frame needed
            cell.value = self.coerce(d.init.value, d.type, d.line, f"'{d.name}'")
        else:
            cell.value = self.value_of(d, Frame(None, {}, self.scopes[module.name.lower()]))
        self.path = saved
        return cell.value

    def value_of(self, d: n.Data, frame):
        """The initial value of a declaration."""
        if d.dims:
            dims = tuple(self.whole(e, frame, f"a dimension of '{d.name}'") for e in d.dims)
            init = self.ev(d.init, frame) if d.init is not None else None
            try:
                return self.types.array(d.type, dims, init, d.name)
            except Mismatch as exc:
                fail(self.path, d.line, str(exc))
        if d.init is None:
            return self.types.default(d.type)
        value = self.ev(d.init, frame)
        if value.__class__ is Live:
            value = self.live_input(value, d.name, d.type, d.line)
        return self.coerce(value, d.type, d.line, f"'{d.name}'")

    def initialize(self, cell: Cell):
        """A module's data object read before its declaration's turn: made now."""
        return self._initialize(cell)

    # -- statements -----------------------------------------------------------------------------
    def body(self, body: n.Body, frame: Frame) -> None:
        stmts, labels = body.statements, body.labels
        k, count = 0, len(stmts)
        while k < count:
            s = stmts[k]
            try:
                self.statement(s, frame)
            except Goto as g:
                target = labels.get(g.label)
                if target is None:
                    raise
                if s.__class__ is n.Goto and target < k:  # an unconditional jump back: a loop that cannot end
                    starts = self.loop_passes.setdefault(id(s), [self.label_at.get(id(stmts[target]), self.mark())])
                    if flow.endless_pass(self, s, starts):
                        k += 1
                        continue
                    starts.append(self.mark())
                k = target
            k += 1

    def statement(self, s, frame: Frame) -> None:
        self.statements += 1
        if self.statements > MAX_STATEMENTS:
            fail(self.path, getattr(s, "line", 0), f"the task ran {MAX_STATEMENTS} statements without ending: a loop "
                                                   "that never ends?")
        try:
            _RUN[s.__class__](self, s, frame)
        except LiveValue as lv:
            raise NeedsInput(self.path, getattr(s, "line", 0), lv.live) from None
        except RapidError as err:
            if not handlers.takes(self, frame, err):
                raise
            handlers.recover(self, lambda again: _RUN[again.__class__](self, again, frame), s, frame, err)

    def _data(self, d: n.Data, frame: Frame) -> None:
        frame.cells[d.name.lower()] = Cell(self.value_of(d, frame), d.type, d.storage, self.path, d.line, d.name)

    def _assign(self, s: n.Assign, frame: Frame) -> None:
        holder, path, type_ = self.target(s.target, frame)
        if holder.kind in ("const", "loop"):
            what = "the constant" if holder.kind == "const" else "the FOR variable"
            fail(self.path, s.line, f"cannot assign to {what} '{s.target.name}'")
        value = self.ev(s.expr, frame)
        if value.__class__ is Live:
            value = self.live_input(value, s.target.name, type_, s.line)
        root = holder.get()
        if path and (value.__class__ is Live or root.__class__ is Live):  # a part unknown: the whole is
            holder.set(root if root.__class__ is Live else value)
            return
        current = root if not path else None
        if current.__class__ is Arr and value.__class__ is not Live:  # a whole array, from one or its aggregate
            try:
                value = self.types.array(current.type, current.dims, value, n.written(s.target))
            except Mismatch as exc:
                fail(self.path, s.line, str(exc))
            holder.set(value)
            return
        value = self.coerce(value, type_, s.line, f"'{n.written(s.target)}'")
        if holder.type in ("robtarget", "jointtarget") and holder.kind == "var":
            holder.cell.set_at = (self.path, s.line)  # a target a findings names where it was last set
        if isinstance(value, Arr):
            value = value.copy()
        holder.set(replace(holder.get(), path, value) if path else value)

    def live_input(self, live: Live, name: str, type_: str, line: int):
        """What ``--input`` gives ``name`` for a live read stored there, else the read, unknown."""
        return input_value(self, live, name, type_, line)

    def target(self, node: n.Name, frame: Frame):
        """(cell, path, type) of an assignment's target or a reference argument."""
        if node.key not in frame.cells and frame.module.get(node.key) is None:
            fail(self.path, node.line, f"unknown name '{node.name}'")
        cell = self.cell(node.key, node.name, frame, node.line)
        if cell.value is PENDING:
            self._initialize(cell)
        value, type_, path = cell.get(), cell.type, []
        for s in node.selectors:
            if s.__class__ is n.Field:
                fields = self.types.fields(type_) or ()
                k = next((i for i, (name, _) in enumerate(fields) if name == s.key), None)
                if k is None:
                    fail(self.path, node.line, f"'{n.written(node)}': a {self.types.base(type_)} has no component "
                                               f"'{s.name}'")
                type_ = fields[k][1]
                value = value.vals[k] if value.__class__ is not Live else value
            elif value.__class__ is Live:  # an element of what a live read gave
                k = 0
            else:
                k = self.offset(value, s, frame, node)
                type_ = value.type
                value = value.items[k]
            path.append(k)
        return cell, tuple(path), type_

    def mark(self) -> tuple[int, int]:
        """(motions, moves) so far: where a loop's pass starts."""
        return len(self.motions), self.moves

    def _return(self, s: n.Return, frame: Frame) -> None:
        raise Returned(self.ev(s.expr, frame) if s.expr is not None else None)

    def _jump(self, s: n.Jump, frame: Frame) -> None:
        if s.kind == "exit":
            raise ExitTask()
        handlers.jump(self, s, frame)

    def _placeholder(self, s, frame: Frame) -> None:
        self.warn(s.line, f"{s.text}: a placeholder RobotStudio left for a statement not yet written: skipped")

    # -- calls ----------------------------------------------------------------------------------
    def _proc_call(self, s: n.ProcCall, frame: Frame) -> None:
        routine = frame.module.routine(s.key)
        if routine is not None:
            if routine.kind != "proc":
                fail(self.path, s.line, f"'{s.name}' is a {routine.kind.upper()}, not a procedure")
            self.call(routine, s.args, frame, s.line)
            return
        run_instruction(self, s, frame)

    def _late_call(self, s: n.LateCall, frame: Frame) -> None:
        name = self.ev(s.expr, frame)
        if not isinstance(name, str):
            fail(self.path, s.line, "a late-bound call needs a string naming the procedure")
        self.call_named(name, s.args, frame, s.line)

    def call_named(self, name: str, args, frame: Frame, line: int) -> None:
        """The procedure a string names (late binding, CallByVar)."""
        routine = frame.module.routine(name.lower())
        if routine is None or routine.kind != "proc":
            fail(self.path, line, f"no procedure '{name}' in the task")
        self.call(routine, args, frame, line)

    def function(self, node: n.Call, frame: Frame):
        routine = frame.module.routine(node.key)
        if routine is not None:
            if routine.kind != "func":
                fail(self.path, node.line, f"'{node.name}' is a {routine.kind.upper()}, not a function")
            value = self.call(routine, node.args, frame, node.line)
        else:
            value = call_function(self, node, frame)
        return self.select(value, node.selectors, frame, node) if node.selectors else value

    def call(self, routine: n.Routine, args, frame: Frame | None, line: int):
        """Run ``routine`` with ``args`` (nodes.Arg) given in ``frame``; a FUNC's value."""
        if self.depth >= MAX_DEPTH:
            fail(self.path, line, f"calls nest deeper than {MAX_DEPTH}: a recursion that never ends?")
        cells = bind(self, routine, args, frame, line) if frame is not None else {}
        scope = self.scopes[routine.module.lower()]
        callee = Frame(routine, cells, scope, line, frame)
        saved = self.path
        self.depth += 1
        self.path = routine.file
        try:
            self.body(routine.body, callee)
        except RsxmlError as exc:
            if not hasattr(exc, "chain"):  # the calls that led to the line it stopped at
                exc.chain = (*callee.chain(), f"{routine.name} ({exc.file}:{exc.line})")
            raise
        except Returned as r:
            if routine.kind == "func":
                if r.value is None:
                    fail(self.path, line, f"FUNC '{routine.name}' returned no value")
                return self.coerce(r.value, routine.type, line, f"the value of '{routine.name}'")
            return None
        except Goto as g:
            fail(self.path, g.line, f"GOTO {g.label}: no such label in '{routine.name}'")
        finally:
            self.depth -= 1
            self.path = saved
        if routine.kind == "func":
            fail(routine.file, routine.line, f"FUNC '{routine.name}' ended without RETURN")
        return None

    def volatile(self) -> None:
        """The expression being read asks something that changes by itself (a clock, the robot):
        a loop's condition that does is never taken as unchanging."""
        if self.reads is not None:
            fresh = Cell(None, "volatile", "var")
            fresh.set(None)
            self.reads.append(fresh)

    def now(self) -> float:
        """The task's time so far (s): its moves and waits as the robot times them, else its waits."""
        try:
            return float(self.robot.seconds_after(self.motions))
        except LookupError:
            return self.waited

    def clock_read(self, ref) -> float:
        return clock_read(self, ref)

    def emit(self, motion: Motion) -> None:
        if len(self.motions) >= MAX_MOTIONS:
            fail(self.path, motion.line, f"the task made {MAX_MOTIONS} moves and waits: a loop that never ends?")
        self.motions.append(motion)
        if motion.kind != "wait":
            self.moves += 1


@contextlib.contextmanager
def _deep_stack():
    """Room for MAX_DEPTH calls of nested blocks (each a few Python frames)."""
    before = sys.getrecursionlimit()
    sys.setrecursionlimit(max(before, 20_000))
    try:
        yield
    finally:
        sys.setrecursionlimit(before)


_RUN = {
    n.Data: Interpreter._data,
    n.Assign: Interpreter._assign,
    n.ProcCall: Interpreter._proc_call,
    n.LateCall: Interpreter._late_call,
    n.If: flow.run_if,
    n.For: flow.run_for,
    n.While: flow.run_while,
    n.Test: flow.run_test,
    n.Goto: flow.run_goto,
    n.Label: flow.run_label,
    n.Return: Interpreter._return,
    n.Jump: Interpreter._jump,
    n.Connect: lambda self, s, frame: self.warn(s.line, f"interrupts are not modelled: TRAP '{s.trap}' never runs"),
    n.Placeholder: Interpreter._placeholder,
}
