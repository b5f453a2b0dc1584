"""Expressions of a running task: names looked up in the routine's frame, then its module's scope
(its own data, LOCAL included, then the task's global data, then the predefined data), selectors
on records and arrays, operators with RAPID's types (num, dnum, bool, string, pos and orient
arithmetic), and calls of functions. A name declared nowhere is an I/O signal of the I/O
configuration, 0 unless ``--io`` sets it (a warning says so, once)."""

from __future__ import annotations

import math

from ..errors import nearest
from . import nodes as n
from .errors import fail, rapid_error
from .live import Live, LiveValue
from .scope import PENDING, Cell
from .values import SIGNALS, Arr, Mismatch, Rec, describe, field_index, whole


class Evaluator:
    """The expression half of the interpreter (``interpret.Interpreter``)."""

    path: str  # the file of the statement running
    reads: list | None = None  # cells read while a loop's condition is evaluated

    # -- names ----------------------------------------------------------------------------------
    def cell(self, key: str, name: str, frame, line: int):
        """The cell a name refers to (a signal's for a name declared nowhere, unless it looks like
        a misspelt name of the task's: then it is an error)."""
        cell = frame.cells.get(key)
        if cell is None:
            cell = frame.module.get(key)
            if cell is None:
                self._misspelt(key, name, frame, line)
                cell = self.signal(name, line, declared=False)
        if self.reads is not None and cell.kind != "const":
            self.reads.append(cell)
        return cell

    def signal(self, name: str, line: int, declared: bool = True) -> Cell:
        key = name.lower()
        self.used_signals.add(key)
        cell = self.signals.get(key)
        if cell is None:
            cell = self.signals[key] = Cell(0.0, "signal", "var", "", 0, name)
            if not declared:
                self.warn(line, f"'{name}' is declared nowhere in the task: taken as an I/O signal of value 0 "
                                f"(--io {name}=VALUE sets it)")
        return cell

    def _misspelt(self, key: str, name: str, frame, line: int) -> None:
        """An error for a name declared nowhere that is one or two letters from a data name the
        task declares (``nDelay`` for ``nDelays``): a typo, not an I/O signal."""
        if key in self.signals:
            return
        near = nearest(key, [k for k, c in frame.module.items() if c.file] + list(frame.cells))
        if near:
            cell = frame.cells.get(near) or frame.module.get(near)
            fail(self.path, line, f"unknown name '{name}' (did you mean '{cell.name}'?)")

    def signal_of(self, node, frame) -> Cell:
        """The signal an argument names (a declared signal variable's, or an I/O signal's), with
        no warning: an instruction that takes a signal expects one from the I/O configuration."""
        name = getattr(node, "name", None)
        if name is None or getattr(node, "selectors", ()):
            fail(self.path, getattr(node, "line", 0), f"'{n.written(node)}' is not a signal")
        cell = frame.cells.get(node.key) or frame.module.get(node.key)
        if cell is not None and cell.type not in SIGNALS and cell.kind != "absent":
            fail(self.path, node.line, f"'{name}' is a {cell.type}, not a signal")
        if self.reads is not None:
            self.reads.append(self.signal(cell.name if cell is not None else name, node.line))
        return self.signal(cell.name if cell is not None else name, node.line)

    def undeclared(self, node, frame) -> bool:
        """Whether ``node`` is a bare name the task declares nowhere (so not a target, say)."""
        return (isinstance(node, n.Name) and not node.selectors and node.key not in frame.cells
                and frame.module.get(node.key) is None and node.key not in self.given)

    def name(self, node: n.Name, frame):
        cell = self.cell(node.key, node.name, frame, node.line)
        value = cell.get()
        if value is PENDING:
            value = self.initialize(cell)
        if cell.kind == "absent":
            fail(self.path, node.line, f"the optional parameter '{node.name}' is not present (test it with Present)")
        if cell.type in SIGNALS:
            value = self.signal(cell.name, node.line).get()
        if node.selectors and cell.type == "signal":
            fail(self.path, node.line, f"unknown name '{node.name}' ({n.written(node)})")
        return self.select(value, node.selectors, frame, node) if node.selectors else value

    def select(self, value, selectors, frame, node):
        if value.__class__ is Live:  # a component of what a live read gives is as unknown
            return value
        for s in selectors:
            if s.__class__ is n.Field:
                k = field_index(self.types, value, s.key)
                if k is None:
                    fail(self.path, node.line, f"{describe(value)} has no component '{s.name}' ({n.written(node)})")
                value = value.vals[k]
            else:
                value = value.items[self.offset(value, s, frame, node)]
        return value

    def offset(self, value, index: n.Index, frame, node) -> int:
        if not isinstance(value, Arr):
            fail(self.path, node.line, f"{n.written(node)}: {describe(value)} is not an array")
        at = tuple(self.whole(e, frame, "an array index") for e in index.items)
        k = value.offset(at)
        if k is None:
            rapid_error(self.path, node.line, f"index {{{', '.join(map(str, at))}}} of {n.written(node)} is outside "
                                              f"{{{', '.join(map(str, value.dims))}}}", "ERR_OUTOFBND")
        return k

    def whole(self, node, frame, what: str) -> int:
        v = self.ev(node, frame)
        if v.__class__ is Live:
            raise LiveValue(v)
        if not whole(v):
            fail(self.path, getattr(node, "line", 0), f"{what} must be a whole number, not {describe(v)}")
        return int(v)

    # -- expressions ----------------------------------------------------------------------------
    def ev(self, node, frame):
        return _EVAL[node.__class__](self, node, frame)

    def boolean(self, node, frame) -> bool:
        v = self.ev(node, frame)
        if v.__class__ is not bool:
            if v.__class__ is Live:
                raise LiveValue(v)
            fail(self.path, getattr(node, "line", 0), f"a condition must be TRUE or FALSE, not {describe(v)}")
        return v

    def number(self, node, frame, what: str = "the value") -> float:
        v = self.ev(node, frame)
        if v.__class__ is not float:
            if isinstance(v, int) and not isinstance(v, bool):
                return float(v)
            if v.__class__ is Live:
                raise LiveValue(v)
            fail(self.path, getattr(node, "line", 0), f"{what} must be a number, not {describe(v)}")
        return v

    def coerce(self, value, type_: str, line: int, where: str):
        if value.__class__ is Live:  # unknown until the cell gives it: of any type
            return value
        try:
            return self.types.coerce(value, type_, where)
        except Mismatch as exc:
            fail(self.path, line, str(exc))

    def _chain(self, node: n.Chain, frame):
        value = self.ev(node.first, frame)
        for op, rhs in node.rest:
            value = self.operate(op, value, self.ev(rhs, frame), node.line)
        return value

    def _prefix(self, node: n.Prefix, frame):
        value = self.ev(node.operand, frame)
        if value.__class__ is Live:
            return value
        for op in reversed(node.ops):
            if op == "not":
                if value.__class__ is not bool:
                    fail(self.path, node.line, f"NOT needs TRUE or FALSE, not {describe(value)}")
                value = not value
            elif op == "-":
                value = self.operate("*", -1.0, value, node.line)
            elif not _numeric(value):
                fail(self.path, node.line, f"'+' needs a number, not {describe(value)}")
        return value

    def operate(self, op: str, a, b, line: int):
        """``a op b`` with RAPID's types."""
        if a.__class__ is float and b.__class__ is float:
            return self._numbers(op, a, b, line)
        if a.__class__ is Live or b.__class__ is Live:  # what a live read decides stays unknown
            return a if a.__class__ is Live else b
        if op in ("and", "or", "xor"):
            if a.__class__ is not bool or b.__class__ is not bool:
                fail(self.path, line, f"{op.upper()} needs TRUE or FALSE, not {describe(a)} and {describe(b)}")
            return (a and b) if op == "and" else (a or b) if op == "or" else (a != b)
        if op in ("=", "<>"):
            same = _plain(a) == _plain(b)
            return same if op == "=" else not same
        if _numeric(a) and _numeric(b):
            return self._numbers(op, float(a), float(b), line)
        if op == "+" and isinstance(a, str) and isinstance(b, str):
            return self._string(a + b, line)
        return self._records(op, a, b, line)

    def _numbers(self, op: str, a: float, b: float, line: int):
        if op == "+":
            r = a + b
        elif op == "-":
            r = a - b
        elif op == "*":
            r = a * b
        elif op == "/":
            if b == 0:
                rapid_error(self.path, line, "division by zero", "ERR_DIVZERO")
            r = a / b
        elif op in ("div", "mod"):
            if not (whole(a) and whole(b)):
                fail(self.path, line, f"{op.upper()} takes whole numbers, not {a:g} and {b:g}")
            if b == 0:
                rapid_error(self.path, line, "division by zero", "ERR_DIVZERO")
            q = abs(int(a)) // abs(int(b)) * (1 if (a < 0) == (b < 0) else -1)
            r = float(q) if op == "div" else float(int(a) - q * int(b))
        else:
            return {"<": a < b, "<=": a <= b, ">": a > b, ">=": a >= b, "=": a == b, "<>": a != b}[op]
        if not math.isfinite(r):
            fail(self.path, line, f"{a:g} {op} {b:g} overflows")
        return r

    def _records(self, op: str, a, b, line: int):
        """pos + pos, pos - pos, num * pos, pos * num, pos * pos (the vector product), orient * orient; an
        aggregate beside a record is a record of its type."""
        if isinstance(a, Rec) and isinstance(b, (list, tuple)):
            b = self.coerce(b, a.type, line, "the aggregate")
        elif isinstance(b, Rec) and isinstance(a, (list, tuple)):
            a = self.coerce(a, b.type, line, "the aggregate")
        pos_a, pos_b = _is(a, "pos"), _is(b, "pos")
        if op in "+-" and pos_a and pos_b:
            sign = 1.0 if op == "+" else -1.0
            return Rec("pos", tuple(x + sign * y for x, y in zip(a.vals, b.vals)))
        if op == "*" and pos_a and pos_b:  # RAPID's pos * pos is the vector (cross) product
            from .poses import cross

            return Rec("pos", cross(a.vals, b.vals))
        if op == "*" and pos_b and _numeric(a):
            return Rec("pos", tuple(float(a) * y for y in b.vals))
        if op in "*/" and pos_a and _numeric(b):
            if op == "/" and b == 0:
                rapid_error(self.path, line, "division by zero", "ERR_DIVZERO")
            return Rec("pos", tuple(x * b if op == "*" else x / b for x in a.vals))
        if op == "*" and _is(a, "orient") and _is(b, "orient"):
            from .poses import qmul

            return Rec("orient", qmul(a.vals, b.vals))
        fail(self.path, line, f"'{op.upper() if op.isalpha() else op}' cannot take {describe(a)} and {describe(b)}")

    def _string(self, s: str, line: int) -> str:
        from .build import MAX_STRING

        if len(s) > MAX_STRING:
            fail(self.path, line, f"a string of {len(s)} characters: RAPID strings hold at most {MAX_STRING}")
        return s

    def _placeholder(self, node: n.Placeholder, frame):
        fail(self.path, node.line, f"{node.text}: a placeholder RobotStudio left for an expression not yet written")

    def _aggregate(self, node: n.Aggregate, frame):
        items = [self.ev(e, frame) for e in node.items]
        for v in items:  # an aggregate with a part a live read gave is as unknown
            if v.__class__ is Live:
                return v
        return items


def _numeric(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _is(v, type_: str) -> bool:
    return isinstance(v, Rec) and v.type == type_


def _plain(v):
    """A value compared by its content: an aggregate's numbers as floats."""
    if isinstance(v, Rec):
        return tuple(_plain(x) for x in v.vals)
    if isinstance(v, (list, tuple)):
        return tuple(_plain(x) for x in v)
    if isinstance(v, int) and not isinstance(v, bool):
        return float(v)
    return v


_EVAL = {
    n.Num: lambda self, node, frame: node.value,
    n.Str: lambda self, node, frame: node.value,
    n.Literal: lambda self, node, frame: node.value,
    n.Aggregate: Evaluator._aggregate,
    n.Name: Evaluator.name,
    n.Call: lambda self, node, frame: self.function(node, frame),
    n.Prefix: Evaluator._prefix,
    n.Chain: Evaluator._chain,
    n.Placeholder: Evaluator._placeholder,
}
