"""The tree a RAPID task is parsed into once (``build.py``) and walked by the interpreter: frozen
dataclasses, each with the line it starts on. Names are kept as written (``name``) and compared
in lower case (``key``), as RAPID's names are."""

from __future__ import annotations

from dataclasses import dataclass, field

# -- expressions ----------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Num:
    line: int
    value: float
    text: str


@dataclass(frozen=True, slots=True)
class Str:
    line: int
    value: str


@dataclass(frozen=True, slots=True)
class Literal:
    """An aggregate of literals only, read in one go: nested lists of floats, bools and strings."""

    line: int
    value: list
    text: str


@dataclass(frozen=True, slots=True)
class Aggregate:
    line: int
    items: tuple


@dataclass(frozen=True, slots=True)
class Field:
    name: str
    key: str


@dataclass(frozen=True, slots=True)
class Index:
    items: tuple  # expressions, one per dimension


@dataclass(frozen=True, slots=True)
class Name:
    """A data name with its selectors (``p.trans.z``, ``a{i, j}``)."""

    line: int
    name: str
    key: str
    selectors: tuple = ()


@dataclass(frozen=True, slots=True)
class Arg:
    """One argument of a call: required (``name`` None, or a named required one ``ToPoint:=p``),
    optional (``\\Name:=expr``, ``\\Switch`` with no ``expr``) or conditional (``\\Name?param``)."""

    expr: object | None
    name: str | None = None
    optional: bool = False
    condition: str | None = None  # the caller's parameter a conditional argument depends on


@dataclass(frozen=True, slots=True)
class Call:
    """A function call in an expression, with selectors on its value."""

    line: int
    name: str
    key: str
    args: tuple
    selectors: tuple = ()


@dataclass(frozen=True, slots=True)
class Prefix:
    """Unary operators, outermost first (``-``, ``+``, ``NOT``), on an operand."""

    line: int
    ops: tuple
    operand: object


@dataclass(frozen=True, slots=True)
class Chain:
    """Operands joined by operators of one priority, evaluated left to right; a long chain is a
    loop, never deep recursion."""

    line: int
    first: object
    rest: tuple  # ((op, operand), ...)


@dataclass(frozen=True, slots=True)
class Placeholder:
    """``<EXP>``, ``<SMT>``, ...: a place RobotStudio left for something not yet written."""

    line: int
    text: str


# -- statements -----------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Body:
    """Statements in order, the routine's own data first; ``labels`` maps a label to the index of
    the statement after it (GOTO)."""

    statements: tuple
    labels: dict = field(default_factory=dict, hash=False, compare=False)
    depth: int = 0  # compound statements nested in it


@dataclass(frozen=True, slots=True)
class Assign:
    line: int
    target: Name
    expr: object


@dataclass(frozen=True, slots=True)
class ProcCall:
    line: int
    name: str
    key: str
    args: tuple


@dataclass(frozen=True, slots=True)
class LateCall:
    """``%"name" + suffix% args;``: the procedure named by a string expression."""

    line: int
    expr: object
    args: tuple


@dataclass(frozen=True, slots=True)
class If:
    line: int
    branches: tuple  # ((condition, Body), ...)
    otherwise: Body | None


@dataclass(frozen=True, slots=True)
class For:
    line: int
    var: str
    key: str
    start: object
    stop: object
    step: object | None
    body: Body


@dataclass(frozen=True, slots=True)
class While:
    line: int
    condition: object
    body: Body


@dataclass(frozen=True, slots=True)
class Test:
    line: int
    expr: object
    cases: tuple  # ((values, Body), ...)
    default: Body | None


@dataclass(frozen=True, slots=True)
class Goto:
    line: int
    label: str


@dataclass(frozen=True, slots=True)
class Label:
    line: int
    name: str


@dataclass(frozen=True, slots=True)
class Return:
    line: int
    expr: object | None


@dataclass(frozen=True, slots=True)
class Jump:
    """EXIT, RETRY, TRYNEXT or RAISE (with its error number)."""

    line: int
    kind: str
    expr: object | None = None


@dataclass(frozen=True, slots=True)
class Connect:
    line: int
    target: Name
    trap: str


# -- declarations ---------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Data:
    """A data declaration: ``storage`` const, var or pers; ``scope`` local, task or ''."""

    line: int
    scope: str
    storage: str
    type: str
    name: str
    dims: tuple | None
    init: object | None


@dataclass(frozen=True, slots=True)
class Param:
    """A parameter: ``mode`` in, var, pers or inout; ``optional`` written with a backslash;
    ``group`` numbers the alternatives of one ``\\A | B`` group; ``dims`` the ``{*}`` count."""

    name: str
    key: str
    type: str
    mode: str
    optional: bool
    group: int
    dims: int


@dataclass(frozen=True, slots=True)
class Routine:
    """A PROC, FUNC (with its ``type``) or TRAP; its handlers are parsed, not run."""

    line: int
    kind: str
    name: str
    key: str
    type: str | None
    params: tuple
    body: Body
    local: bool
    handlers: tuple = ()  # names of the handlers it has: backward, error, undo
    file: str = ""
    module: str = ""
    error: Body | None = None  # the ERROR handler, run when the routine meets an error
    error_numbers: tuple = ()  # the errors it takes (expressions); all when empty


@dataclass(frozen=True, slots=True)
class Record:
    line: int
    name: str
    components: tuple  # ((type, name), ...)
    local: bool


@dataclass(frozen=True, slots=True)
class Alias:
    line: int
    name: str
    type: str
    local: bool


@dataclass(frozen=True, slots=True)
class Module:
    """A module of a file: its name and attributes (SYSMODULE, NOSTEPIN, ...) and its items."""

    line: int
    name: str
    attrs: tuple
    data: tuple
    routines: tuple
    records: tuple
    aliases: tuple
    file: str = ""


def written(node) -> str:
    """An expression as RAPID writes it (for tables: how a move's target was given)."""
    if isinstance(node, Num):
        return node.text
    if isinstance(node, Str):
        return '"' + node.value.replace('"', '""') + '"'
    if isinstance(node, Literal):
        return node.text
    if isinstance(node, Aggregate):
        return "[" + ",".join(written(i) for i in node.items) + "]"
    if isinstance(node, (Name, Call)):
        head = node.name
        if isinstance(node, Call):
            head += "(" + _args_text(node.args) + ")"
        return head + "".join(_selector_text(s) for s in node.selectors)
    if isinstance(node, Prefix):
        inner = written(node.operand)
        if isinstance(node.operand, Chain) and node.operand.rest:
            inner = f"({inner})"
        return "".join(op if op in "+-" else op.upper() + " " for op in node.ops) + inner
    if isinstance(node, Chain):
        if not node.rest:
            return f"({written(node.first)})"
        return written(node.first) + "".join(f"{op}{written(e)}" if op in "+-*/" else f" {op.upper()} {written(e)}"
                                             for op, e in node.rest)
    if isinstance(node, Placeholder):
        return node.text
    return "?"


def _selector_text(s) -> str:
    if isinstance(s, Field):
        return "." + s.name
    return "{" + ",".join(written(i) for i in s.items) + "}"


def _args_text(args) -> str:
    out = ""
    for a in args:
        if a.optional:
            out += f"\\{a.name}" + (f"?{a.condition}" if a.condition else f":={written(a.expr)}" if a.expr else "")
        else:
            out += ("," if out else "") + (f"{a.name}:=" if a.name else "") + written(a.expr)
    return out
