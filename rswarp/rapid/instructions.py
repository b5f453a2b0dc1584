"""RAPID's built-in instructions: motion (``moves``), waits, the motion settings (ConfJ, ConfL,
AccSet, VelSet, SingArea, GripLoad), data (Incr, Add, Clear, data by name), signals (SetDO and
kin, kept in the run's signal table), clocks, ExitCycle and CallByVar. The rest is as the word table
(``words``) says: an instruction that cannot change the motion (TPWrite, file and socket I/O,
interrupts) runs as nothing, silently; a live read (SocketReceive, TPReadNum, ...) stores what
``--input`` gives, else an unknown value; one that could change the motion and is not modelled
(program displacement, independent axes) is a warning at its line, as is a procedure that
neither RAPID nor the task defines (an option's, a module's not in the task)."""

from __future__ import annotations

from pathlib import Path

from . import byname, words
from . import data as rd
from . import nodes as n
from .arguments import Arguments
from .errors import fail
from .flow import ExitCycle
from .live import Live
from .motion import Motion
from .moves import MOVES, NO_LOAD_KG, HeldLoad, run_move, wait
from .nodes import written
from .scope import Cell

# Instructions real programs call that the manual's table does not hold, and how they are run.
EXTRA = {"clearioobuff": "no-op", "sendcmd": "no-op", "sendcommand": "no-op", "contacttool": "unmodelled"}


def run_instruction(interp, s, frame) -> None:
    a = Arguments(interp, s.name, s.args, frame, s.line)
    key = s.key
    if key in MOVES:
        run_move(interp, MOVES[key], a, s, frame)
    elif key in _HANDLERS:
        _HANDLERS[key](interp, a, s, frame)
    elif key in SIGNAL_SETTERS:
        if len(a) >= 1:
            _set_signal(interp, a, key)
    else:
        _by_table(interp, a, s, frame)


def _by_table(interp, a: Arguments, s, frame) -> None:
    """An instruction as the word table handles it; one no one defines is skipped with a warning."""
    w = words.word(s.key)
    handling = w.handling if w is not None and w.kind == "instruction" else EXTRA.get(s.key)
    if handling == "live":
        live_read(interp, a, s, frame)
    elif handling == "unmodelled":
        interp.warn(s.line, f"{s.name} could change the motion and is not modelled: skipped")
    elif handling is None:  # a near miss of a known name was refused at load (check.py)
        interp.warn_once(("unknown", s.key), s.line,
                         f"'{s.name}' is neither a routine of the task nor a RAPID instruction (an option's, or a "
                         "module's not in the task): skipped wherever it is called")


def live_read(interp, a: Arguments, s, frame) -> None:
    """A read only the cell answers (SocketReceive, TPReadNum, ReadAnyBin, ...): each data it
    writes gets what ``--input`` gives under that data's name, else an unknown value."""
    for node in _output_nodes(a, s.key):
        if not isinstance(node, n.Name):
            continue
        holder, path, type_ = interp.target(node, frame)
        value = interp.live_input(Live(s.name, node.name, interp.path, s.line), node.name, type_, s.line)
        holder.set(_replace(holder.get(), path, value) if path else value)


def _output_nodes(a: Arguments, key: str) -> list:
    """The argument expressions a live read writes into, as the manual lays out its parameters."""
    outs = words.outputs(key)
    if not outs:
        return [a.node(0)] if len(a) else []
    places = words.positions(key)
    nodes = []
    for p in outs:
        if p.optional:
            expr = a.optional.get(p.name.lower())
            if expr is not None:
                nodes.append(expr)
        else:
            k = next((i for i, group in enumerate(places) if p in group), None)
            if k is not None and k < len(a):
                nodes.append(a.node(k))
    return nodes


def _replace(root, path, value):
    from .scope import replace

    return replace(root, path, value) if value.__class__ is not Live else value


def _set_signal(interp, a: Arguments, key: str) -> None:
    signal = interp.signal_of(a.node(0), a.frame)
    if key == "set":
        signal.set(1.0)
    elif key == "reset":
        signal.set(0.0)
    elif key == "invertdo":
        signal.set(0.0 if signal.get() else 1.0)
    elif len(a) >= 2:
        signal.set(a.number(1))


def _waittime(interp, a: Arguments, s, frame) -> None:
    a.need(1)
    wait(interp, a.number(0), s, frame)


def _wait_signal(interp, a: Arguments, s, frame) -> None:
    a.need(2)
    name = written(a.node(0))
    value, want = interp.signal_of(a.node(0), frame).get(), a.number(1)
    if value != want:
        interp.warn(s.line, f"{s.name} {name}, {want:g}: the signal is {value:g} and nothing in the task sets it: "
                            f"taken as met at once (--io {name}={want:g} sets it)")
    _time_flag(a)


def _wait_until(interp, a: Arguments, s, frame) -> None:
    a.need(1)
    if not interp.boolean(a.node(0), frame):
        interp.warn(s.line, "WaitUntil: the condition is FALSE and nothing in the task makes it TRUE: taken as met "
                            "at once")
    _time_flag(a)


def _time_flag(a: Arguments) -> None:
    if a.has("TimeFlag") and a.optional["timeflag"] is not None:
        from . import nodes as n

        node = a.optional["timeflag"]
        if isinstance(node, n.Name):
            holder, path, _ = a.interp.target(node, a.frame)
            holder.set(False) if not path else None


def _conf(key: str):
    def run(interp, a: Arguments, s, frame) -> None:
        if a.has("On") == a.has("Off"):
            fail(interp.path, s.line, f"{s.name} takes \\On or \\Off")
        interp.state[key] = a.has("On")
    return run


def _accset(interp, a: Arguments, s, frame) -> None:
    a.need(2)
    acc, ramp = a.number(0), a.number(1)
    if not (0 < acc <= 100 and 0 < ramp <= 100):
        fail(interp.path, s.line, f"AccSet takes an acceleration and a ramp of 1 to 100 %, not {acc:g} and {ramp:g}")
    interp.state["accel"], interp.state["ramp"] = max(acc, 20.0) / 100.0, max(ramp, 10.0) / 100.0


def _velset(interp, a: Arguments, s, frame) -> None:
    a.need(2)
    override, vmax = a.number(0), a.number(1)
    if not (0 < override <= 100 and vmax > 0):
        fail(interp.path, s.line, f"VelSet takes an override of 1 to 100 % and a top speed above 0, not "
                                  f"{override:g} and {vmax:g}")
    interp.state["override"], interp.state["vmax"] = override / 100.0, vmax / 1000.0


def _gripload(interp, a: Arguments, s, frame) -> None:
    """GripLoad: the payload the robot holds from here on, which lowers its accelerations (kept in
    the state each move reads); ``load0`` (or any load of at most its mass) disconnects it."""
    a.need(1)
    name = written(a.node(0))
    load = a.si(rd.load, a.value(0, "loaddata"), f"the loaddata '{name}'")
    source = f"GripLoad {name} at {Path(interp.path).name}:{s.line}"
    held = HeldLoad(load.mass, load.cog, load.inertia, load.aom, source) if load.mass > NO_LOAD_KG else None
    interp.state["grip_load"] = held


def _data(op: str):
    def run(interp, a: Arguments, s, frame) -> None:
        a.need(1 if op in ("incr", "decr", "clear") else 2)
        target = a.reference(0)
        value = target.get()
        if value.__class__ is Live:  # unknown, and stays so
            return
        if not isinstance(value, float):
            fail(interp.path, s.line, f"{s.name} takes a num variable")
        step = {"incr": 1.0, "decr": -1.0, "clear": -value}.get(op)
        target.set(value + (a.number(1) if step is None else step))
    return run


def _clock(op: str):
    def run(interp, a: Arguments, s, frame) -> None:
        a.need(1)
        cell = a.reference(0).cell
        running, total = interp.clocks.get(id(cell), (None, 0.0))
        if op == "start" and running is None:
            interp.clocks[id(cell)] = (interp.now(), total)
        elif op == "stop" and running is not None:
            interp.clocks[id(cell)] = (None, total + interp.now() - running)
        elif op == "reset":
            interp.clocks[id(cell)] = (None, 0.0)
        cell.set(cell.get())
    return run


def _exit_cycle(interp, a, s, frame) -> None:
    raise ExitCycle()


def _call_by_var(interp, a: Arguments, s, frame) -> None:
    a.need(2)
    interp.call_named(f"{a.value(0, 'string')}{int(a.number(1))}", (), frame, s.line)


def _bit(on: bool):
    """BitSet, BitClear: one bit (1 to 8, or 1 to 52 of a dnum) of a byte set or cleared."""
    def run(interp, a: Arguments, s, frame) -> None:
        a.need(2)
        target, k = a.reference(0), a.number(1)
        value = target.get()
        if not isinstance(value, float) or value != int(value) or k != int(k) or not 1 <= k <= 52:
            fail(interp.path, s.line, f"{s.name} takes a whole number and a bit of 1 to 52")
        bit = 1 << (int(k) - 1)
        target.set(float(int(value) | bit if on else int(value) & ~bit))
    return run


def _stop(interp, a: Arguments, s, frame) -> None:
    interp.warn(s.line, f"{s.name}: the controller stops here until the operator starts it again; the run goes on")


def _book_error(interp, a: Arguments, s, frame) -> None:
    """BookErrNo: a free error number (1 to 90 are the user's) for the errnum variable."""
    a.need(1)
    interp.booked = getattr(interp, "booked", 0) + 1
    a.reference(0).set(float(interp.booked))


RUN_ALONE = ("MultiMove; run alone, this task's robot stops at each meeting point and moves on at once (a cell of "
             "several robots runs their tasks together)")


def _sync(on: bool | None):
    """SyncMoveOn, SyncMoveOff, WaitSyncTask: MultiMove's meeting points, each a wait of 0 s that
    names its syncident (the robot stops there: ``motion.multimove`` makes the tasks meet), and
    synchronized moves from SyncMoveOn to SyncMoveOff (their ``\\ID``)."""
    def run(interp, a: Arguments, s, frame) -> None:
        if on is not None:
            interp.state["sync"] = on
        kind = "wait" if on is None else "on" if on else "off"
        ident = n.written(a.node(0)) if len(a) and s.key != "syncmoveundo" else None
        interp.warn_once(("multimove",), s.line, f"{s.name}: {RUN_ALONE}")
        if ident is not None:
            interp.emit(Motion("wait", s.name, interp.path, s.line, frame.routine.name, frame.chain(), seconds=0.0,
                               cycle=interp.pass_index, sync=ident, sync_kind=kind))
    return run


_HANDLERS = {
    "waittime": _waittime, "waitdi": _wait_signal, "waitdo": _wait_signal, "waitai": _wait_signal,
    "waitao": _wait_signal, "waitgi": _wait_signal, "waitgo": _wait_signal, "waituntil": _wait_until,
    "confj": _conf("conf_j"), "confl": _conf("conf_l"), "accset": _accset, "velset": _velset, "gripload": _gripload,
    "incr": _data("incr"), "decr": _data("decr"), "add": _data("add"), "clear": _data("clear"),
    "clkstart": _clock("start"), "clkstop": _clock("stop"), "clkreset": _clock("reset"),
    "exitcycle": _exit_cycle, "callbyvar": _call_by_var, "stop": _stop, "break": _stop, "bookerrno": _book_error,
    "syncmoveon": _sync(True), "syncmoveoff": _sync(False), "syncmoveundo": _sync(False),
    "waitsynctask": _sync(None), "bitset": _bit(True), "bitclear": _bit(False), **byname.INSTRUCTIONS,
}
SIGNAL_SETTERS = {"setdo", "setao", "setgo", "set", "reset", "invertdo", "pulsedo"}


def clock_read(interp, ref) -> float:
    cell = ref.cell if not isinstance(ref, Cell) else ref
    running, total = interp.clocks.get(id(cell), (None, 0.0))
    return total + (interp.now() - running if running is not None else 0.0)


# Instructions by their lower-case name, as RAPID writes them (for "did you mean").
KNOWN = {k: w.name for k, w in words.words().items() if w.kind == "instruction"}
KNOWN.update({k: KNOWN.get(k, k) for k in (*MOVES, *_HANDLERS, *EXTRA)}, searchj="SearchJ")
