"""Values only a running cell has: what a socket, a file, the FlexPendant or a message queue gives
(``SocketReceive``, ``ReadNum``, ``TPReadNum``, ``UINumEntry``, ...). Offline such a read stores a
``Live`` value, unknown; arithmetic on it stays unknown, and the run stops where the motion needs
it (a condition, a target, a loop bound) with one line naming the read. ``--input NAME=VALUE``
gives the values, each name's in the order the task reads them."""

from __future__ import annotations

import json
import math
import re
from collections import deque

from ..errors import Diagnostic


class Live:
    """An unknown value: what read it (``source``), into which data (``into``), where."""

    __slots__ = ("source", "into", "file", "line", "why")

    def __init__(self, source: str, into: str | None, file: str, line: int, why: str | None = None):
        self.source, self.into, self.file, self.line = source, into, file, line
        self.why = why  # what the value is, where it is no live read (a function no one defines)

    def named(self, into: str) -> "Live":
        """The same read, stored into ``into`` (a function's value assigned to data)."""
        return self if self.into else Live(self.source, into, self.file, self.line, self.why)

    def __repr__(self):
        return f"<live {self.source} into {self.into}>"


class LiveValue(Exception):
    """An expression met a ``Live`` value where it needs a known one; the statement turns it into
    ``NeedsInput`` at its own line."""

    def __init__(self, live: Live):
        self.live = live


class NeedsInput(Exception):
    """The run stops at ``file:line``: the motion depends on a live read no ``--input`` gave."""

    def __init__(self, file: str, line: int, live: Live):
        self.file, self.line, self.live = file, line, live

    @property
    def name(self) -> str:
        return self.live.into or self.live.source

    def message(self) -> str:
        live = self.live
        into = f" into {live.into}" if live.into else ""
        verb = "called" if live.why else "read"
        where = f" ({verb} at line {live.line})" if (live.file, live.line) != (self.file, self.line) else ""
        if live.file != self.file and live.file:
            where = f" ({verb} at {live.file}:{live.line})"
        what = f"the value of {live.why}" if live.why else "live input:"
        return f"needs {what} {live.source}{into}{where}; --input {self.name}=VALUE gives it"

    def diagnostic(self) -> Diagnostic:
        return Diagnostic(self.file, self.line, self.message())

    def record(self) -> dict:
        live = self.live
        return {"name": self.name, "source": live.source, "file": self.file, "line": self.line,
                "read_file": live.file, "read_line": live.line, "kind": "value" if live.why else "live read"}


def needs(value, line: int = 0):
    """``value`` itself, or ``LiveValue`` where it is unknown."""
    if value.__class__ is Live:
        raise LiveValue(value)
    return value


class Inputs:
    """``--input`` values by lower-case name, each consumed in turn; what was never asked is
    reported."""

    def __init__(self, given: dict[str, list[str]] | None = None):
        self.queues = {k.lower(): deque(v) for k, v in (given or {}).items()}
        self.names = {k.lower(): k for k in (given or {})}
        self.asked: set[str] = set()

    def take(self, name: str | None):
        """The next value given for ``name`` (text), or None."""
        if not name:
            return None
        key = name.lower()
        self.asked.add(key)
        queue = self.queues.get(key)
        return queue.popleft() if queue else None

    def pending(self) -> bool:
        """Whether values are left for a name the task has read: its main loop runs on for them."""
        return any(self.queues[k] for k in self.asked if k in self.queues)

    def unused(self) -> list[str]:
        return sorted(self.names[k] for k in self.queues if k not in self.asked or self.queues[k])


_WORD = re.compile(r"\b(TRUE|FALSE)\b", re.I)


def parse_input(text: str, base: str):
    """The text of an ``--input`` as a value of RAPID base type ``base`` (string: as given; num:
    a number; bool: TRUE or FALSE; a record: its aggregate, ``[100, 200, 300]``); ValueError if
    it is not one."""
    if base == "string":
        value = text[1:-1] if len(text) >= 2 and text[0] == text[-1] == '"' else text
        if len(value) > 80:
            raise ValueError(f"a string of {len(value)} characters: RAPID strings hold at most 80")
        return value
    if base == "bool":
        word = text.strip().upper()
        if word not in ("TRUE", "FALSE"):
            raise ValueError(f"TRUE or FALSE, not '{text}'")
        return word == "TRUE"
    stripped = text.strip()
    if stripped.startswith("["):
        try:
            return _lists(json.loads(_WORD.sub(lambda m: m.group(1).lower(), stripped)))
        except json.JSONDecodeError as exc:
            raise ValueError(f"an aggregate such as [100, 200, 300], not '{text}'") from exc
        except RecursionError:
            raise ValueError("an aggregate nested too deep") from None
    try:
        value = float(stripped)
    except ValueError:
        raise ValueError(f"a number, not '{text}'") from None
    if not math.isfinite(value):
        raise ValueError(f"a finite number, not '{text}'")
    return value


def _lists(v):
    if isinstance(v, list):
        return [_lists(x) for x in v]
    if isinstance(v, (int, float)) and not isinstance(v, bool):
        return float(v)
    return v


def input_value(interp, live: Live, name: str, type_: str, line: int):
    """What ``--input`` gives ``name`` (of ``type_``) for a live read stored there, else the read,
    unknown; a value not of the type is an error at the read's line."""
    from .errors import fail
    from .values import Mismatch

    text = interp.inputs.take(name)
    if text is None:
        return live.named(name)
    base = interp.types.base(type_)
    try:
        return interp.types.coerce(parse_input(text, base), type_, f"--input {name}")
    except (ValueError, Mismatch) as exc:
        fail(interp.path, line, f"--input {name}={text}: {name} is a {base}, and the value is not one: {exc}")


def function_input(text: str):
    """An ``--input`` for a live function's value: a number, TRUE or FALSE, an aggregate, else the
    text as a string."""
    for base in ("num", "bool"):
        try:
            return parse_input(text, base)
        except ValueError:
            pass
    return parse_input(text, "string")
