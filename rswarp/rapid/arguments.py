"""The arguments of a built-in function or instruction, read as its reference manual entry lays
them out: required ones by position, optional ones and switches by name, each evaluated (or,
for an INOUT argument, referred to) when the routine asks, with a ``file:line`` error naming the
routine when one is missing or of the wrong type."""

from __future__ import annotations

from . import data as rd
from . import nodes as n
from .errors import fail
from .live import Live, LiveValue
from .values import Mismatch, Rec


class Arguments:
    def __init__(self, interp, name: str, args: tuple, frame, line: int):
        self.interp, self.name, self.frame, self.line = interp, name, frame, line
        self.required = [a for a in args if not a.optional]
        self.optional = {}
        for a in args:
            if a.optional and (a.condition is None or _present(frame, a.condition)):
                expr = n.Name(line, a.condition, a.condition.lower()) if a.condition else a.expr
                self.optional[a.name.lower()] = expr

    def __len__(self) -> int:
        return len(self.required)

    def need(self, low: int, high: int | None = None) -> None:
        high = low if high is None else high
        if not low <= len(self.required) <= high:
            count = str(low) if low == high else f"{low} to {high}"
            fail(self.interp.path, self.line, f"{self.name} takes {count} argument{'s' * (high != 1)}, given "
                                              f"{len(self.required)}")

    def node(self, k: int):
        if not -len(self.required) <= k < len(self.required):
            fail(self.interp.path, self.line, f"{self.name} takes at least {k + 1 if k >= 0 else -k} argument"
                                              f"{'s' * (k != 0)}, given {len(self.required)}")
        return self.required[k].expr

    def value(self, k: int, type_: str | None = None, what: str | None = None):
        """Required argument ``k`` (negative from the end), as ``type_`` when given."""
        expr = self.node(k)
        v = self.interp.ev(expr, self.frame)
        if v.__class__ is Live:
            raise LiveValue(v)
        if type_ is None:
            return v
        if self.interp.undeclared(expr, self.frame) and self.interp.types.base(type_) not in ("num", "dnum"):
            fail(self.interp.path, self.line, f"unknown name '{expr.name}'")
        try:
            return self.interp.types.coerce(v, type_, what or f"{self.name}'s argument '{n.written(expr)}'")
        except Mismatch as exc:
            fail(self.interp.path, self.line, str(exc))

    def number(self, k: int) -> float:
        return self.value(k, "num")

    def has(self, name: str) -> bool:
        return name.lower() in self.optional

    def option(self, name: str, type_: str | None = None, default=None):
        """Optional argument ``\\name``: its value (as ``type_``), True for a switch, ``default``
        when absent."""
        key = name.lower()
        if key not in self.optional:
            return default
        expr = self.optional[key]
        if expr is None:
            return True
        v = self.interp.ev(expr, self.frame)
        if v.__class__ is Live:
            raise LiveValue(v)
        if type_ is None:
            return v
        try:
            return self.interp.types.coerce(v, type_, f"{self.name}'s \\{name}")
        except Mismatch as exc:
            fail(self.interp.path, self.line, str(exc))

    def reference(self, k: int):
        """The data an INOUT argument names (its cell, or the element or component)."""
        from .scope import Part

        expr = self.required[k].expr
        if not isinstance(expr, n.Name):
            fail(self.interp.path, self.line, f"{self.name}'s argument '{n.written(expr)}' must be a variable")
        holder, path, type_ = self.interp.target(expr, self.frame)
        return Part(holder, path, type_, expr.name) if path else holder

    def si(self, convert, value: Rec, what: str):
        """``value`` converted by a ``data`` function (``rd.tool``, ...), errors at the line; a
        record converted before (the same tool, move after move) is not converted again."""
        cache = self.interp.converted
        if value.type in ("robtarget", "jointtarget"):  # one of a kind, mostly: not worth hashing
            cache, key = {}, None
        else:
            key = (convert, value)
        found = cache.get(key)
        if found is None:
            try:
                found = convert(value, what)
            except Mismatch as exc:
                fail(self.interp.path, self.line, f"{self.name}: {exc}")
            if len(cache) < 100_000:
                cache[key] = found
        return found

    def tool_wobj(self, tool_rec: Rec | None = None, active: bool = True) -> tuple:
        """(tool, wobj) as SI records: the given ones, else the active ones (the last move's: CRobT),
        or wobj0 where ``active`` is False (CalcJointT, CalcRobT, as the manual says)."""
        tool_rec = tool_rec or self.option("Tool", "tooldata") or self.interp.state["tool"] or \
            self.frame.module.get("tool0").get()
        wobj_rec = self.option("WObj", "wobjdata") or (self.interp.state["wobj"] if active else None) or \
            self.frame.module.get("wobj0").get()
        return tool_rec, wobj_rec, self.si(rd.tool, tool_rec, "the tool"), self.si(rd.work_object, wobj_rec, "the wobj")


def _present(frame, name: str) -> bool:
    cell = frame.cells.get(name.lower()) if frame is not None else None
    return cell is not None and cell.kind != "absent"
