"""Arguments bound to a routine's parameters as RAPID binds them: required ones in order (or by
name, ``ToPoint:=p``), optional ones by name (``\\WObj:=w``, a switch ``\\Conc``), a conditional
one (``\\WObj?wobj``) only when the caller's own optional parameter is present. IN parameters
get a copy of the value; INOUT, VAR and PERS ones the caller's data itself, or the element or
component named (``a{2}``, ``p.trans``)."""

from __future__ import annotations

from . import nodes as n
from .errors import fail
from .scope import Cell, Part
from .values import Arr, Opaque
from .words import CONFIGURED_TYPES, SIGNAL_TYPES


class ArgumentError(ValueError):
    """Arguments that do not fit a routine's parameters; the message says how."""


def match_arguments(routine: n.Routine, args: tuple, present) -> dict[str, n.Arg]:
    """The arguments by parameter key, as RAPID matches them; ``ArgumentError`` where they do not
    fit. ``present(name)``: whether the caller's optional parameter a conditional argument
    depends on is there (absent, the argument is not given)."""
    required = [p for p in routine.params if not p.optional]
    optional = {p.key: p for p in routine.params if p.optional}
    given: dict[str, n.Arg] = {}
    positional = []
    for a in args:
        if a.optional:
            p = optional.get(a.name.lower())
            if p is None:
                raise ArgumentError(f"'{routine.name}' has no optional parameter \\{a.name}")
            if a.condition is not None and not present(a.condition):
                continue
            given[p.key] = a
        elif a.name is not None:
            p = next((q for q in required if q.key == a.name.lower()), None)
            if p is None:
                raise ArgumentError(f"'{routine.name}' has no parameter '{a.name}'")
            given[p.key] = a
        else:
            positional.append(a)
    missing = [p for p in required if p.key not in given]
    if len(positional) != len(missing):
        count = len(positional) + len(required) - len(missing)
        raise ArgumentError(f"'{routine.name}' takes {len(required)} argument{'s' * (len(required) != 1)} "
                            f"({', '.join(p.name for p in required) or 'none'}), given {count}")
    for p, a in zip(missing, positional):
        given[p.key] = a
    groups: dict[int, str] = {}
    for p in routine.params:
        if p.optional and p.key in given:
            other = groups.setdefault(p.group, p.name)
            if other != p.name:
                raise ArgumentError(f"\\{other} and \\{p.name} of '{routine.name}' exclude each other")
    return given


def bind(interp, routine: n.Routine, args: tuple, frame, line: int) -> dict:
    """The callee's cells by parameter name; ``file:line`` errors for arguments that do not fit."""
    try:
        given = match_arguments(routine, args, lambda name: _present(frame, name))
    except ArgumentError as exc:
        fail(interp.path, line, str(exc))
    cells = {}
    for p in routine.params:
        a = given.get(p.key)
        cells[p.key] = _argument(interp, p, a, frame, line) if a is not None else \
            Cell(None, p.type, "absent", routine.file, routine.line, p.name)
    return cells


def _present(frame, name: str) -> bool:
    cell = frame.cells.get(name) if frame is not None else None
    return cell is not None and cell.kind != "absent"


def _argument(interp, p: n.Param, a: n.Arg, frame, line: int):
    """The cell of one parameter."""
    expr = n.Name(line, a.condition, a.condition) if a.condition is not None else a.expr
    if p.type.lower() == "switch" or expr is None:
        if expr is not None and p.type.lower() == "switch":
            return Cell(True, "switch", "in", interp.path, line, p.name)
        return Cell(True, p.type, "in", interp.path, line, p.name)
    configured = _configured(interp, p, expr, frame, line)
    if configured is not None:
        return configured
    if p.mode != "in" and isinstance(expr, n.Name):
        if interp.undeclared(expr, frame):
            fail(interp.path, line, f"unknown name '{expr.name}'")
        holder, path, type_ = interp.target(expr, frame)
        if holder.kind == "absent":
            fail(interp.path, line, f"the optional parameter '{expr.name}' is not present")
        return Part(holder, path, type_, p.name) if path else holder
    value = interp.ev(expr, frame)
    if p.dims:
        if not isinstance(value, Arr) or len(value.dims) != p.dims:
            fail(interp.path, line, f"'{p.name}' takes an array of {p.dims} dimension{'s' * (p.dims > 1)}")
        value = value.copy()
    else:
        if interp.undeclared(expr, frame) and interp.types.base(p.type) not in ("num", "dnum", "signaldi",
                                                                                 "signaldo", "signalgi", "signalgo",
                                                                                 "signalai", "signalao"):
            fail(interp.path, line, f"unknown name '{expr.name}'")
        value = interp.coerce(value, p.type, line, f"the argument '{p.name}'")
    file, at = _origin(expr, frame)
    return Cell(value, p.type, "in", file, at, p.name)


def _configured(interp, p: n.Param, expr, frame, line: int):
    """The cell of a signal or mechanical-unit parameter (``VAR signaldo sig``, ``VAR mecunit m``)
    given a bare name: one the task declares nowhere is what the controller's configuration
    declares (an I/O signal, ROB_1, STN1), bound by its name as the controller binds it; an IN
    signal parameter is the signal its argument names, not a copy under the parameter's name.
    None for other parameters and for declared data a VAR or INOUT parameter takes itself."""
    t = interp.types.base(p.type)
    if t not in CONFIGURED_TYPES or not isinstance(expr, n.Name) or expr.selectors:
        return None
    declared = not interp.undeclared(expr, frame)
    if declared and p.mode != "in":
        return None
    cell = (frame.cells.get(expr.key) or frame.module.get(expr.key)) if declared else None
    if cell is not None and interp.types.base(cell.type) not in CONFIGURED_TYPES:
        return None  # data of another type: taken (and refused) as any argument is
    name = getattr(cell, "name", expr.name)
    if t in SIGNAL_TYPES:
        interp.signal(name, line)  # the configuration's signal, without the warning a bare read gives
        return Cell(interp.types.default(t), p.type, "var" if p.mode != "in" else "in", interp.path, line, name)
    value = cell.get() if cell is not None else Opaque(t, expr.name)
    return Cell(value, p.type, "var" if p.mode != "in" else "in", interp.path, line, name)


def _origin(expr, frame) -> tuple[str, int]:
    """Where the data an IN argument is (or is built from: ``Offs(p, ...)``'s p) is declared, so a
    target passed down a call is still traced to its declaration; ("", 0) for none."""
    while isinstance(expr, n.Call):
        expr = next((g.expr for g in expr.args if not g.optional), None)
    if not isinstance(expr, n.Name) or frame is None:
        return "", 0
    cell = frame.cells.get(expr.key) or frame.module.get(expr.key)
    cell = getattr(cell, "cell", cell)
    return (cell.file, cell.line) if cell is not None and getattr(cell, "file", "") else ("", 0)
