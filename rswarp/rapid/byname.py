"""Data by name, as RAPID reaches it: GetDataVal and SetDataVal (a data object named by a string),
SetAllDataVal, and the symbol search SetDataSearch / GetNextSym over the task's data; plus
GetSysData and SetSysData (the active tool, work object and load). A name the task does not
declare is the controller's ERR_SYM_ACCESS, which an ERROR handler may take."""

from __future__ import annotations

import re

from .arguments import Arguments
from .errors import rapid_error
from .scope import PENDING
from .values import Mismatch, Opaque


def _found(interp, a: Arguments, name: str):
    """The cell of the data object ``name`` as the running routine sees it."""
    if a.has("TaskName") or a.has("TaskRef"):
        interp.warn(a.line, f"{a.name}: another task's data is not modelled; this task's '{name}' is used")
    key = name.lower()
    cell = a.frame.cells.get(key) or a.frame.module.get(key)
    if cell is None:
        rapid_error(interp.path, a.line, f"{a.name}: no data object '{name}' in the task", "ERR_SYM_ACCESS")
    if cell.value is PENDING:
        interp.initialize(cell)
    return cell


def _copy(interp, a: Arguments, value, type_: str, where: str):
    try:
        value = interp.types.coerce(value, type_, where)
    except Mismatch as exc:
        rapid_error(interp.path, a.line, f"{a.name}: {exc}", "ERR_SYM_ACCESS")
    return value.copy() if hasattr(value, "copy") else value


def get_data_val(interp, a: Arguments, s, frame) -> None:
    """GetDataVal Object, Value: the named object's value copied into Value."""
    a.need(2)
    cell = _found(interp, a, a.value(0, "string"))
    target = a.reference(1)
    target.set(_copy(interp, a, cell.get(), target.type, f"GetDataVal's '{cell.name}'"))


def set_data_val(interp, a: Arguments, s, frame) -> None:
    """SetDataVal Object, Value: the named object set to Value (not a constant)."""
    a.need(2)
    cell = _found(interp, a, a.value(0, "string"))
    if cell.kind == "const":
        rapid_error(interp.path, a.line, f"SetDataVal: '{cell.name}' is a constant", "ERR_SYM_ACCESS")
    cell.set(_copy(interp, a, a.value(1), cell.type, f"SetDataVal's '{cell.name}'"))


def _matching(interp, a: Arguments, type_: str, pattern: str | None):
    """Every data object of the task of ``type_`` whose name matches the regular expression."""
    rx = re.compile(pattern, re.I) if pattern else None
    seen, out = set(), []
    for scope in interp.scopes.values():
        for cell in scope.values():
            if id(cell) in seen or not getattr(cell, "file", "") or interp.types.base(cell.type) != type_:
                continue
            if rx is None or rx.fullmatch(cell.name) or rx.search(cell.name):
                seen.add(id(cell))
                out.append(cell)
    return out


def set_all_data_val(interp, a: Arguments, s, frame) -> None:
    """SetAllDataVal Type [\\Object], Value: every variable of the type (and name pattern) set."""
    a.need(2)
    type_ = interp.types.base(a.value(0, "string"))
    for cell in _matching(interp, a, type_, a.option("Object", "string")):
        if cell.kind != "const":
            if cell.value is PENDING:
                interp.initialize(cell)
            cell.set(_copy(interp, a, a.value(1), cell.type, f"SetAllDataVal's '{cell.name}'"))


def set_data_search(interp, a: Arguments, s, frame) -> None:
    """SetDataSearch Type [\\Object] ...: the task's search, whose objects GetNextSym then gives
    one by one."""
    a.need(1)
    type_ = interp.types.base(a.value(0, "string"))
    interp.state["symbols"] = [c.name for c in _matching(interp, a, type_, a.option("Object", "string"))]


def get_next_sym(interp, a: Arguments) -> bool:
    """GetNextSym(Object, Block): the next name of the task's search, FALSE when none is left."""
    a.need(2)
    names = interp.state.get("symbols") or []
    if not names:
        return False
    name = names.pop(0)
    a.reference(0).set(name)
    a.reference(1).set(Opaque("datapos", name))
    return True


_SYSTEM = {"tooldata": ("tool", "tool0"), "wobjdata": ("wobj", "wobj0")}


def get_sys_data(interp, a: Arguments, s, frame) -> None:
    """GetSysData DestObject [\\ObjectName]: the active tool, work object or load copied there."""
    a.need(1)
    target = a.reference(0)
    base = interp.types.base(target.type)
    state, default = _SYSTEM.get(base, (None, "load0" if base == "loaddata" else None))
    if default is None:
        interp.warn(s.line, f"GetSysData of a {base}: rswarp keeps no such system data; left as it is")
        return
    value = (interp.state.get(state) if state else None) or frame.module.get(default).get()
    target.set(value)
    if a.has("ObjectName"):
        holder, path, _ = interp.target(a.optional["objectname"], frame)
        holder.set(interp.state.get(f"{state}_name") or default) if not path else None


def set_sys_data(interp, a: Arguments, s, frame) -> None:
    """SetSysData SourceObject: the tool or work object the next moves take as active."""
    a.need(1)
    value = a.value(0)
    base = getattr(value, "type", "")
    if base in _SYSTEM:
        interp.state[_SYSTEM[base][0]] = value


INSTRUCTIONS = {"getdataval": get_data_val, "setdataval": set_data_val, "setalldataval": set_all_data_val,
                "setdatasearch": set_data_search, "getsysdata": get_sys_data, "setsysdata": set_sys_data}
FUNCTIONS = {"getnextsym": get_next_sym}
