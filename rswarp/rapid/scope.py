"""Where RAPID's data lives while a task runs: a ``Cell`` per data object (its value, type, kind
and declaration), ``Part`` for an element or a component of one (an INOUT argument ``a{2}`` or
``p.trans``), and ``Frame`` for a routine's parameters and own data. Every write stamps the cell
with a counter, so the interpreter can tell whether a loop's condition could ever change."""

from __future__ import annotations

from dataclasses import dataclass, field

from .live import Live
from .predefined import error_number
from .values import Arr, Rec

PENDING = object()  # a module's data not yet initialized (declared later, or in a later module)


class Cell:
    """One data object. ``kind`` is const, var, pers, in (a parameter passed by value), loop (a
    FOR variable) or absent (an optional parameter not given)."""

    __slots__ = ("value", "type", "kind", "file", "line", "name", "stamp", "set_at")
    clock = 0  # bumped by every write; a cell's stamp is the clock of its last write

    def __init__(self, value, type_: str, kind: str, file: str = "", line: int = 0, name: str = ""):
        self.value, self.type, self.kind = value, type_, kind
        self.file, self.line, self.name = file, line, name
        self.stamp = 0
        self.set_at: tuple[str, int] | None = None  # where a target variable was last assigned (file, line)

    def get(self):
        return self.value

    def set(self, value) -> None:
        Cell.clock += 1
        self.stamp = Cell.clock
        self.value = value

    @property
    def cell(self) -> "Cell":
        return self


class Part:
    """A component or element of a cell's value, read and written in place (``path``: component
    indices of records, flat offsets of arrays); what an INOUT argument ``a{2}.trans`` is."""

    __slots__ = ("base", "path", "type", "kind", "name")

    def __init__(self, base, path: tuple, type_: str, name: str):
        self.base, self.path, self.type, self.name = base, path, type_, name
        self.kind = base.kind

    @property
    def cell(self) -> Cell:
        return self.base.cell

    @property
    def stamp(self) -> int:
        return self.base.stamp

    @property
    def value(self):
        return self.get()

    def get(self):
        value = self.base.get()
        for step in self.path:
            if not isinstance(value, (Arr, Rec)):  # a part of an unknown value (a live read's) is as unknown
                return value
            value = value.items[step] if isinstance(value, Arr) else value.vals[step]
        return value

    def set(self, value) -> None:
        self.base.set(replace(self.base.get(), self.path, value))


def replace(root, path: tuple, value):
    """``root`` with the part at ``path`` replaced: records rebuilt, arrays written in place; an
    unknown value (a live read's) stays unknown, and a part made unknown makes the whole so."""
    if not path:
        return value
    if not isinstance(root, (Arr, Rec)):
        return root
    if value.__class__ is Live:
        return value
    head, rest = path[0], path[1:]
    if isinstance(root, Arr):
        root.items[head] = replace(root.items[head], rest, value)
        return root
    vals = list(root.vals)
    vals[head] = replace(vals[head], rest, value)
    return Rec(root.type, tuple(vals))


@dataclass
class Frame:
    """One call of a routine: its cells by lower-case name, what it was called from."""

    routine: object  # nodes.Routine
    cells: dict = field(default_factory=dict)
    module: object = None  # the module scope it runs in (task.ModuleScope)
    line: int = 0  # the line it was called from
    caller: "Frame | None" = None
    handling: object = None  # the error its ERROR handler is running for

    def chain(self) -> tuple[str, ...]:
        """The calls that led here, outermost first: ``caller (file:line of the call)``."""
        out, frame = [], self
        while frame.caller is not None and frame.caller.routine is not None:
            out.append(f"{frame.caller.routine.name} ({frame.caller.routine.file}:{frame.line})")
            frame = frame.caller
        return tuple(reversed(out))


class ModuleScope(dict):
    """A module's names: data (its own, then the task's global, then predefined) and routines."""

    def __init__(self, data: dict, module, task):
        super().__init__(data)
        self.module = module
        own = task.locals.get(module.name.lower(), {})
        self._routines = {k: s.node for k, s in task.globals.items() if s.node.__class__.__name__ == "Routine"}
        self._routines.update({k: s.node for k, s in own.items() if s.node.__class__.__name__ == "Routine"})

    def get(self, key, default=None):
        found = dict.get(self, key)
        if found is None:
            number = error_number(key)
            if number is not None:
                found = self[key] = Cell(number, "errnum", "const", "", 0, key)
        return found if found is not None else default

    def routine(self, key: str):
        return self._routines.get(key)

    def routines(self) -> dict:
        """The routines this module sees, by lower-case name."""
        return self._routines
