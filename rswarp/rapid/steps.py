"""A module's declarations evaluated in order, and one routine's statements turned into the steps
rswarp runs (``Move``, ``Wait``), each checked for its arguments at its line."""

from __future__ import annotations

from dataclasses import dataclass

from lark import Token, Tree

from ..errors import Diagnostic
from . import data as rd
from .evaluate import arguments

MOVES = {"moveabsj": "MoveAbsJ", "movej": "MoveJ", "movel": "MoveL", "movec": "MoveC"}
MAX_ARRAY = 100_000  # elements of one declared array: memory stays bounded


@dataclass(frozen=True)
class Move:
    """One motion instruction: ``targets`` one (MoveC: the circle point, then the end), each a
    ``RobTarget`` or ``JointTarget`` with the name it was written as."""

    line: int
    instruction: str
    targets: tuple
    names: tuple[str, ...]
    speed: rd.Speed
    zone: rd.Zone
    tool: rd.Tool
    wobj: rd.WorkObject


@dataclass(frozen=True)
class Wait:
    line: int
    seconds: float


RECORDS = {"robtarget": rd.robtarget, "jointtarget": rd.jointtarget}
SKIPPED = {"if_block": "IF", "if_short": "IF", "for_block": "FOR", "while_block": "WHILE", "test_block": "TEST",
           "assign": "an assignment", "goto": "GOTO", "label": "a label", "return_": "RETURN", "exit_": "EXIT",
           "retry": "RETRY", "trynext": "TRYNEXT", "raise_": "RAISE", "late_call": "a late-bound call",
           "declaration": "a routine's own data"}


def declarations(ev, nodes) -> None:
    """Each declaration's value into ``ev.data``, in file order; a record that does not have its
    type's shape is an error at its line."""
    for node in nodes:
        kids = [c for c in node.children if not (isinstance(c, Tree) and c.data in ("scope", "const", "pers", "var"))]
        type_ = str(kids[0].children[0]).lower()
        name = str(kids[1])
        dims = kids[2] if len(kids) > 2 and isinstance(kids[2], Tree) and kids[2].data == "dims" else None
        init = kids[-1] if len(kids) > (3 if dims is not None else 2) else None
        if init is None:
            value = _default(type_)
        else:
            value = ev.value(init)
        shape = rd.SHAPES.get(type_)
        if dims is not None:
            value = _array(ev, node, name, dims, value, shape)
        elif shape is not None and value is not None:
            _check(ev, node.meta.line, type_, name, value)
        ev.data[name.lower()] = (type_, value)


def _default(type_: str):
    return {"num": 0.0, "dnum": 0.0, "bool": False, "string": ""}.get(type_)


def _array(ev, node, name: str, dims, value, shape):
    sizes = [ev.value(d) for d in dims.children]
    count = 1
    for s in sizes:
        count *= int(s) if isinstance(s, float) else 0
    if count <= 0 or count > MAX_ARRAY:
        ev.fail(node.meta.line, f"array '{name}' must have 1 to {MAX_ARRAY} elements")
    if value is None:
        return None
    if not isinstance(value, list) or len(value) != int(sizes[0]):
        ev.fail(node.meta.line, f"array '{name}' is declared with {int(sizes[0])} elements, given "
                                f"{len(value) if isinstance(value, list) else 1}")
    if shape is not None and len(sizes) == 1:
        type_ = str([c for c in node.children if isinstance(c, Tree) and c.data == "type"][0].children[0]).lower()
        for k, v in enumerate(value):
            _check(ev, node.meta.line, type_, f"{name}{{{k + 1}}}", v)
    return value


def _check(ev, line: int, type_: str, name: str, value) -> None:
    why = rd.mismatch(value, rd.SHAPES[type_])
    if why:
        ev.fail(line, f"{type_} '{name}' is malformed: {why} (a {type_} is {rd.FIELDS.get(type_, type_)})")
    if type_ in ("robtarget", "pose") and rd.quaternion_norm(value) < 1e-9:
        ev.fail(line, f"{type_} '{name}' has a zero quaternion")


def routine_steps(ev, proc) -> tuple[list, list[Diagnostic]]:
    """The routine's Move and Wait steps, and a warning for each statement skipped."""
    body = next(c for c in proc.children if isinstance(c, Tree) and c.data == "body")
    steps, warnings = [], []
    for stmt in body.children:
        if not isinstance(stmt, Tree):
            continue
        if stmt.data == "call":
            step = _call(ev, stmt)
            if step is not None:
                steps.append(step)
                continue
            what = str(stmt.children[0])
        elif stmt.data in ("body",):
            continue
        else:
            what = SKIPPED.get(stmt.data, stmt.data)
        warnings.append(Diagnostic(ev.path, stmt.meta.line, f"skipped {what}: rswarp runs MoveAbsJ, MoveJ, MoveL, "
                                                            "MoveC and WaitTime only", "warning"))
    return steps, warnings


def _call(ev, stmt):
    """A Move or Wait from a procedure call, or None for a call rswarp does not run."""
    name = str(stmt.children[0]).lower()
    args = stmt.children[1].children if len(stmt.children) > 1 else []
    if name == "waittime":
        plain, _ = arguments(ev, args)
        if len(plain) != 1 or not isinstance(plain[0], float) or plain[0] < 0:
            ev.fail(stmt.meta.line, "WaitTime takes a time in seconds, zero or more")
        return Wait(stmt.meta.line, plain[0])
    if name not in MOVES:
        return None
    return _move(ev, stmt, MOVES[name], args)


def _move(ev, stmt, instruction: str, args) -> Move:
    line = stmt.meta.line
    plain, optional = arguments(ev, args)
    count = 2 if instruction == "MoveC" else 1
    if len(plain) != count + 3:
        ev.fail(line, f"{instruction} takes {'CirPoint, ToPoint' if count == 2 else 'ToPoint'}, speed, zone and tool")
    names = tuple(_written(ev, a) for a in _plain_nodes(args)[:count])
    kind = "jointtarget" if instruction == "MoveAbsJ" else "robtarget"
    targets = []
    for value, written in zip(plain[:count], names):
        why = rd.mismatch(value, rd.SHAPES[kind])
        if why:
            ev.fail(line, f"{instruction} needs a {kind}: '{written}' {why}")
        targets.append(RECORDS[kind](value))
    speed, zone, tool = plain[count:]
    for value, kind_, word in ((speed, "speeddata", "speed"), (zone, "zonedata", "zone"), (tool, "tooldata", "tool")):
        if rd.mismatch(value, rd.SHAPES[kind_]):
            ev.fail(line, f"{instruction}: the {word} is not a {kind_}")
    wobj = optional.get("wobj", ev.data["wobj0"][1])
    if rd.mismatch(wobj, rd.SHAPES["wobjdata"]):
        ev.fail(line, f"{instruction}: \\WObj is not a wobjdata")
    if "tool" in optional:  # \Tool on MoveAbsJ names the tool the speed refers to
        tool = optional["tool"]
    return Move(line, instruction, tuple(targets), names, rd.speed(speed), rd.zone(zone), rd.tool(tool),
                rd.work_object(wobj))


def _plain_nodes(args) -> list:
    out = []
    for a in args:
        parts = a.children if isinstance(a, Tree) and a.data == "arg" else [a]
        out += [p for p in parts if not (isinstance(p, Tree) and p.data == "optional")]
    return out


def _written(ev, node) -> str:
    """How an argument was written, its spaces and line breaks collapsed."""
    meta = getattr(node, "meta", None)
    if isinstance(node, Token):
        return str(node)
    if meta is None or getattr(meta, "empty", True) or not ev.text:
        return "[...]"
    text = " ".join(ev.text[meta.start_pos:meta.end_pos].split())
    return text if len(text) <= 60 else text[:57] + "..."
