"""lark's parse of a RAPID file turned into ``nodes`` as it is parsed (an inline transformer: no
intermediate tree): operators given their priorities, literals read, strings unescaped, every
node with its line. A string longer than RAPID allows, or statements nested deeper than rswarp
walks, are errors at their lines."""

from __future__ import annotations

import json
import json.scanner
import math
import re

from lark import Token, Transformer

from . import nodes as n
from .errors import fail

MAX_STRING = 80  # characters: RAPID's string length; the controller refuses a longer literal
MAX_BLOCKS = 64  # compound statements (IF, FOR, WHILE, TEST) nested in each other

# Operator priorities, lowest first (RAPID kernel reference: OR, XOR and NOT lowest; then AND; the
# relations; + and -; * / DIV MOD highest). NOT, a prefix, takes everything to its right up to the
# next OR or XOR: NOT a AND b is NOT (a AND b).
_LEVELS = ({"or", "xor"}, {"and"}, {"<", "<=", "=", ">=", ">", "<>"}, {"+", "-"}, {"*", "/", "div", "mod"})

NUMBER = r"[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?"
STRING = r'"(?:[^"\n]|"")*"'
_LITERAL_ITEM = re.compile(r"\[|\]|" + STRING + r"|TRUE\b|FALSE\b|" + NUMBER, re.I)
_ESCAPE = re.compile(r"\\(\\|[0-9A-Fa-f]{2})")


def literal_regex(depth: int = 4) -> str:
    """A regular expression for an aggregate of literals (numbers, strings, TRUE, FALSE) nested
    ``depth`` deep: ``[[900,0,900],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]]``."""
    atom = f"{NUMBER}|{STRING}|(?i:TRUE|FALSE)\\b"
    level = rf"\[\s*(?:{atom})(?:\s*,\s*(?:{atom}))*\s*\]"
    for _ in range(depth - 1):
        item = f"{atom}|{level}"
        level = rf"\[\s*(?:{item})(?:\s*,\s*(?:{item}))*\s*\]"
    return level


# RAPID's names: a letter, then letters, digits and '_'; its letters are ISO 8859-1's (accented ones too).
_LETTER = "A-Za-z\u00C0-\u00D6\u00D8-\u00F6\u00F8-\u00FF"
NAME_RE = f"[{_LETTER}_][{_LETTER}0-9_]*"
# A declaration whose value is such an aggregate or a number: most lines of a module of targets.
DECLARATION = (r"(?i:(?:(?:LOCAL|TASK)\s+)?(?:CONST|VAR|PERS)\s+)" + NAME_RE + r"\s+" + NAME_RE + r"\s*:=\s*(?:"
               + literal_regex() + "|" + NUMBER + r")\s*;")
DECLARATION_PARTS = re.compile(r"[ \t]*(?:(LOCAL|TASK)\s+)?(CONST|VAR|PERS)\s+(" + NAME_RE + r")\s+(" + NAME_RE
                               + r")\s*:=\s*("
                                + literal_regex() + "|" + NUMBER + r")\s*;", re.I)
_HUGE = re.compile(r"[eE][-+]?\d{3}|\d{300}")  # where a number may be too large for a float
RUN_MARK = "\x01"  # brackets a run's number in the text lark reads (see ``runs``); \x02 a run of calls


JSON_VALUE = json.scanner.make_scanner(json.JSONDecoder())  # the C scanner, without json.loads's checks


def literal_value(text: str):
    """The nested lists of an aggregate of literals; JSON's parser where the text is JSON."""
    if '"' not in text and "T" not in text.upper().replace("E", ""):
        try:
            value, end = JSON_VALUE(text, 0)
            if end == len(text):
                return value
        except (ValueError, StopIteration):
            pass
    stack: list[list] = [[]]
    for m in _LITERAL_ITEM.finditer(text):
        x = m.group()
        if x == "[":
            stack.append([])
        elif x == "]":
            done = stack.pop()
            stack[-1].append(done)
        elif x[0] == '"':
            stack[-1].append(x[1:-1].replace('""', '"'))
        elif x[0] in "tTfF":
            stack[-1].append(x.upper() == "TRUE")
        else:
            stack[-1].append(float(x))
    return stack[0][0]


def _line(tok) -> int:
    return getattr(tok, "line", 0) or 0


def _tokens(children, kind: str | None = None) -> list:
    return [c for c in children if isinstance(c, Token) and (kind is None or c.type == kind)]


class _Vis(str):
    """A visibility keyword (local, task), told apart from names among a rule's children."""


class _Storage(str):
    pass


class _Mode(str):
    pass


class Builder(Transformer):
    """Callbacks of ``rapid.lark``'s rules, called as lark reduces them."""

    def __init__(self, path: str):
        super().__init__(visit_tokens=True)
        self.path = path
        self.runs: list[Run] = []  # of the file being read (``runs.take_runs``)

    # -- tokens ---------------------------------------------------------------------------------
    def NUMBER(self, tok):
        text = str(tok)
        low = text.lower()
        base = {"0x": 16, "0b": 2, "0o": 8}.get(low[:2])
        try:
            value = float(int(text[2:], base)) if base else float(text)
        except OverflowError:
            value = float("inf")
        if not math.isfinite(value):
            fail(self.path, tok.line, f"the number {text} is out of range")
        return n.Num(tok.line, value, text)

    def STRING(self, tok):
        raw = str(tok)[1:-1].replace('""', '"')
        value = _ESCAPE.sub(lambda m: "\\" if m.group(1) == "\\" else chr(int(m.group(1), 16)), raw)
        if len(value) > MAX_STRING:
            fail(self.path, tok.line, f"a string of {len(value)} characters: RAPID strings hold at most {MAX_STRING}")
        return n.Str(tok.line, value)

    def LITAGG(self, tok):
        return self.make_literal(str(tok), tok.line)

    def make_literal(self, text: str, line: int, value=None) -> n.Literal:
        """An aggregate of literals (``value``: its nested lists, where they were read already); a
        number in it that is out of range is an error at its line, as it is alone."""
        value = literal_value(text) if value is None else value
        if _HUGE.search(text):
            for word in _LITERAL_ITEM.findall(text):
                if word[0] not in '"[]tTfF' and not math.isfinite(float(word)):
                    fail(self.path, line, f"the number {word} is out of range")
        return n.Literal(line, value, " ".join(text.split()))

    def LITDECL(self, tok):
        return Run([self.declaration(DECLARATION_PARTS.match(str(tok)), tok.line)])

    def RUN(self, tok):
        return self.runs[int(str(tok).strip("\x01\x02\n"))]

    CALLS = RUN  # a run with statements, which only a routine may hold

    def declaration(self, m: re.Match, line: int, value=None) -> n.Data:
        """The node of a declaration of a literal, from its match of ``DECLARATION_PARTS`` (or of
        a cheaper one, with the ``value`` JSON's parser read)."""
        scope, storage, type_, name, text = m.groups()
        if text[:1] != "[":
            init = self.NUMBER(Token("NUMBER", text, line=line))
        else:
            init = self.make_literal(text, line, value)
        return n.Data(line, (scope or "").lower(), storage.lower(), type_, name, None, init)

    # -- module items -----------------------------------------------------------------------------
    def start(self, children):
        return children

    def items(self, children):
        return _grow(children)

    def statements(self, children):
        return _grow(children)

    def module(self, children):
        head, name = children[0], str(children[1])
        attrs = next((c for c in children if isinstance(c, tuple) and c[:1] == ("attrs",)), ("attrs",))[1:]
        items = next((c for c in children if isinstance(c, list)), [])
        items = [c for c in items if not isinstance(c, (Token, tuple))]
        kinds = {k: tuple(i for i in items if isinstance(i, k)) for k in (n.Data, n.Routine, n.Record, n.Alias)}
        return n.Module(head.line, name, attrs, kinds[n.Data], kinds[n.Routine], kinds[n.Record], kinds[n.Alias],
                        self.path)

    def module_attrs(self, children):
        return ("attrs",) + tuple(str(c).upper() for c in children)

    def visibility(self, children):
        return _Vis(str(children[0]).lower())

    def storage(self, children):
        return _Storage(str(children[0]).lower())

    def mode(self, children):
        return _Mode(str(children[0]).lower())

    def dims(self, children):
        return ("dims", tuple(children))

    def data_decl(self, children):
        scope = next((c for c in children if isinstance(c, _Vis)), "")
        storage = next(c for c in children if isinstance(c, _Storage))
        type_, name = _tokens(children, "NAME")[:2]
        dims = next((c[1] for c in children if isinstance(c, tuple) and c[:1] == ("dims",)), None)
        rest = children[children.index(name) + 1:]
        init = next((c for c in rest if not isinstance(c, tuple)), None)
        return n.Data(type_.line, str(scope), str(storage), str(type_), str(name), dims, init)

    def record(self, children):
        head = _tokens(children, "RECORD")[0]
        name = _tokens(children, "NAME")[0]
        comps = tuple(c for c in children if isinstance(c, tuple))
        return n.Record(head.line, str(name), comps, any(isinstance(c, _Vis) and c == "local" for c in children))

    def component(self, children):
        return (str(children[0]), str(children[1]))

    def alias(self, children):
        head = _tokens(children, "ALIAS")[0]
        base, name = _tokens(children, "NAME")[:2]
        return n.Alias(head.line, str(name), str(base), any(isinstance(c, _Vis) and c == "local" for c in children))

    def _routine(self, kind: str, children, type_=None):
        head = next(c for c in children if isinstance(c, Token) and c.type in ("PROC", "FUNC", "TRAP"))
        names = _tokens(children, "NAME")
        name = names[-1]
        params = next((c for c in children if isinstance(c, list)), [])
        body = next(c for c in children if isinstance(c, n.Body))
        handlers = next(c for c in children if isinstance(c, tuple) and c[:1] == ("handlers",))[1:]
        local = any(isinstance(c, _Vis) and c == "local" for c in children)
        error = next((h for h in handlers if isinstance(h, tuple)), None)
        names = tuple(h if isinstance(h, str) else "error" for h in handlers)
        return n.Routine(head.line, kind, str(name), str(name).lower(), type_, tuple(params), body, local, names,
                         self.path, "", error[2] if error else None, error[1] if error else ())

    def proc(self, children):
        return self._routine("proc", children)

    def func(self, children):
        return self._routine("func", children, str(_tokens(children, "NAME")[0]))

    def trap(self, children):
        return self._routine("trap", children)

    def params(self, children):
        out = []
        for group, members in enumerate(children):
            out += [p.__class__(**{**{f: getattr(p, f) for f in p.__slots__}, "group": group}) for p in members]
        return out

    def param_group(self, children):
        optional = bool(_tokens(children, "BSLASH"))
        return [p.__class__(**{**{f: getattr(p, f) for f in p.__slots__}, "optional": optional})
                for p in children if isinstance(p, n.Param)]

    def param(self, children):
        mode = next((c for c in children if isinstance(c, _Mode)), "in")
        type_, name = _tokens(children, "NAME")[:2]
        dims = next((c[1] for c in children if isinstance(c, tuple) and c[:1] == ("pdims",)), 0)
        return n.Param(str(name), str(name).lower(), str(type_), str(mode), False, 0, dims)

    def param_dims(self, children):
        return ("pdims", len(children))

    # -- bodies and handlers ---------------------------------------------------------------------
    def body(self, children):
        children = children[0] if children else []
        decls = [c for c in children if isinstance(c, n.Data)]
        stmts = [c if not (isinstance(c, Token) and c.type == "PLACEHOLDER") else n.Placeholder(c.line, str(c))
                 for c in children if not isinstance(c, n.Data)]
        labels = {s.name.lower(): k for k, s in enumerate(stmts) if isinstance(s, n.Label)}
        depth = max((_depth(s) for s in stmts), default=0)
        return n.Body(tuple(decls) + tuple(stmts), labels, depth)

    def handlers(self, children):
        return ("handlers",) + tuple(children)

    def backward(self, children):
        return "backward"

    def error_handler(self, children):
        numbers = next((c[1] for c in children if isinstance(c, tuple) and c[:1] == ("numbers",)), ())
        return ("error", numbers, children[-1])

    def error_numbers(self, children):
        return ("numbers", tuple(children))

    def undo(self, children):
        return "undo"

    # -- statements ------------------------------------------------------------------------------
    def assign(self, children):
        return n.Assign(children[0].line, children[0], children[1])

    def lvalue(self, children):
        return n.Name(children[0].line, str(children[0]), str(children[0]).lower(), tuple(children[1:]))

    def call(self, children):
        args = children[1] if len(children) > 1 else ()
        return n.ProcCall(children[0].line, str(children[0]), str(children[0]).lower(), args)

    def late_call(self, children):
        args = children[-1] if isinstance(children[-1], tuple) else ()
        return n.LateCall(children[0].line, children[1], args)

    def goto(self, children):
        return n.Goto(children[0].line, str(children[1]))

    def return_(self, children):
        return n.Return(children[0].line, children[1] if len(children) > 1 else None)

    def raise_(self, children):
        return n.Jump(children[0].line, "raise", children[1] if len(children) > 1 else None)

    def exit_(self, children):
        return n.Jump(children[0].line, "exit")

    def retry(self, children):
        return n.Jump(children[0].line, "retry")

    def trynext(self, children):
        return n.Jump(children[0].line, "trynext")

    def connect(self, children):
        return n.Connect(children[0].line, children[1], str(children[2]).lower())

    def label(self, children):
        return n.Label(children[0].line, str(children[0]))

    def if_block(self, children):
        branches = [(children[1], children[2])]
        otherwise = None
        for c in children[3:]:
            if isinstance(c, tuple) and c[:1] == ("elseif",):
                branches.append(c[1:])
            else:
                otherwise = c
        return n.If(children[0].line, tuple(branches), otherwise)

    def elseif(self, children):
        return ("elseif", children[1], children[2])

    def else_(self, children):
        return children[0]

    def if_short(self, children):
        return n.If(children[0].line, ((children[1], n.Body((children[2],), {}, _depth(children[2]))),), None)

    def for_block(self, children):
        head, var, start, stop = children[:4]
        step = children[4] if len(children) == 6 else None
        return n.For(head.line, str(var), str(var).lower(), start, stop, step, children[-1])

    def while_block(self, children):
        return n.While(children[0].line, children[1], children[2])

    def test_block(self, children):
        cases = tuple(c[1:] for c in children[2:] if isinstance(c, tuple) and c[:1] == ("case",))
        default = next((c for c in children[2:] if isinstance(c, n.Body)), None)
        return n.Test(children[0].line, children[1], cases, default)

    def case(self, children):
        return ("case", tuple(children[1:-1]), children[-1])

    def default(self, children):
        return children[-1]

    # -- arguments -------------------------------------------------------------------------------
    def args(self, children):
        return tuple(children)

    def req_arg(self, children):
        if len(children) == 2:
            return n.Arg(children[1], str(children[0]))
        return n.Arg(children[0])

    def opt_arg(self, children):
        return n.Arg(children[2] if len(children) > 2 else None, str(children[1]), True)

    def cond_arg(self, children):
        return n.Arg(None, str(children[1]), True, str(children[2]).lower())

    # -- expressions -----------------------------------------------------------------------------
    def number(self, children):
        return children[0]

    def string(self, children):
        return children[0]

    def literal(self, children):
        return children[0]

    def placeholder(self, children):
        return n.Placeholder(children[0].line, str(children[0]))

    def aggregate(self, children):
        return n.Aggregate(_node_line(children[0]), tuple(children))

    def function(self, children):
        name = children[0]
        args = children[1] if len(children) > 1 and isinstance(children[1], tuple) else ()
        selectors = tuple(c for c in children[1:] if isinstance(c, (n.Field, n.Index)))
        return n.Call(name.line, str(name), str(name).lower(), args, selectors)

    def paren(self, children):
        return n.Chain(_node_line(children[0]), children[0], ())

    def name(self, children):
        return n.Name(children[0].line, str(children[0]), str(children[0]).lower(), tuple(children[1:]))

    def field(self, children):
        return n.Field(str(children[0]), str(children[0]).lower())

    def index(self, children):
        return n.Index(tuple(children))

    def prefixed(self, children):
        ops = tuple(str(c).lower() for c in children[:-1])
        return n.Prefix(children[0].line, ops, children[-1])

    def chain(self, children):
        if len(children) == 1:
            return children[0]
        operands = children[0::2]
        ops = [str(c).lower() for c in children[1::2]]
        return _climb(operands, ops, 0)


class Run(list):
    """The nodes of one token (LITDECL, RUN, CALLS), spliced into the items around them."""


def _grow(children) -> list:
    """A list rule's items, appended in place: a module of 100 000 lines is not copied 100 000 times."""
    if len(children) == 1:
        return list(children[0]) if isinstance(children[0], Run) else [children[0]]
    items, item = children
    if isinstance(item, Run):
        items.extend(item)
    else:
        items.append(item)
    return items


def _node_line(node) -> int:
    return getattr(node, "line", 0) or 0


def _depth(stmt) -> int:
    """How many compound statements nest in ``stmt``, itself included."""
    if isinstance(stmt, n.If):
        return 1 + max([b.depth for _, b in stmt.branches] + [stmt.otherwise.depth if stmt.otherwise else 0])
    if isinstance(stmt, (n.For, n.While)):
        return 1 + stmt.body.depth
    if isinstance(stmt, n.Test):
        return 1 + max([b.depth for _, b in stmt.cases] + [stmt.default.depth if stmt.default else 0])
    return 0


def _climb(operands: list, ops: list[str], level: int):
    """Operands and operators of one bracket level as n-ary chains, one per priority; a NOT
    operand takes what follows it up to the next OR or XOR."""
    operands, ops = _loose_not(operands, ops)
    if level == len(_LEVELS):
        return operands[0]
    cut = [k for k, op in enumerate(ops) if op in _LEVELS[level]]
    if not cut:
        return _climb(operands, ops, level + 1)
    parts, start = [], 0
    for k in cut + [len(ops)]:
        parts.append(_climb(operands[start:k + 1], ops[start:k], level + 1))
        start = k + 1
    first = parts[0]
    return n.Chain(_node_line(first), first, tuple(zip((ops[k] for k in cut), parts[1:])))


def _loose_not(operands: list, ops: list[str]) -> tuple[list, list[str]]:
    """The first NOT-prefixed operand (not the only operand) folded with what follows it up to the
    next OR/XOR into one ``NOT (...)`` operand."""
    for k, op in enumerate(operands):
        if isinstance(op, n.Prefix) and op.ops[0] == "not" and len(operands) > 1:
            end = next((j for j in range(k, len(ops)) if ops[j] in _LEVELS[0]), len(ops))
            if end == k:
                continue  # NOT a OR b: the NOT takes a alone
            inner = op.operand if len(op.ops) == 1 else n.Prefix(op.line, op.ops[1:], op.operand)
            rest = _climb([inner] + operands[k + 1:end + 1], ops[k:end], 0)
            folded = n.Prefix(op.line, ("not",), rest)
            return operands[:k] + [folded] + operands[end + 1:], ops[:k] + ops[end:]
    return operands, ops
