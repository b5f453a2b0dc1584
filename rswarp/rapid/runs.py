"""Runs of plain lines read without lark: declarations of literals, and calls of moves whose
arguments are names, numbers and aggregates of numbers (a module of 100 000 targets, a generated
PROC of 10 000 MoveL). Each run becomes one token of the text lark reads, so lark's cost (per
token) is paid once per run. The nodes are the ones lark's rules make; a test holds them equal,
and a line this reading is not sure of is left to lark."""

from __future__ import annotations

import re

from lark import Token

from . import nodes as n
from .build import DECLARATION_PARTS, JSON_VALUE, NAME_RE, RUN_MARK, Builder, Run

CALLS_MARK = "\x02"  # brackets a run that holds calls, which only a routine may hold

# A declaration whose value is an aggregate of numbers written as JSON writes them (JSON's parser
# checks it): a cheaper match than DECLARATION_PARTS, which the rest take.
_NUMBERS_PARTS = re.compile(r"[ \t]*(?:(LOCAL|TASK)\s+)?(CONST|VAR|PERS)\s+(" + NAME_RE + r")\s+(" + NAME_RE
                            + r")\s*:=\s*"
                            r"(\[[-+\d.eE,\s\[\]]*\])\s*;", re.I)
_START = re.compile(r"^[ \t]*(?:(?:(?:LOCAL|TASK)\s+)?(?:CONST|VAR|PERS)\s|(?:Move|Trigg|Arc|Search)\w*[ \t])",
                    re.I | re.M)
_HEAD = re.compile(r"[ \t]*((?:Move|Trigg|Arc|Search)\w*)[ \t]+", re.I)
_AFTER = re.compile(r"[ \t]*(?:(,)[ \t]*|(;)|(?=\\))")  # what may follow an argument
_OPTION = re.compile(r"\\(" + NAME_RE + r")[ \t]*(:=)?[ \t]*")
_NAME = re.compile(NAME_RE)
_NUMBER = re.compile(r"\d+(?:\.\d*)?(?:[eE][+-]?\d+)?")
_NOT_NUMBERS = re.compile(r"[^-+\d.eE,\s\[\]]")
_EMPTY = re.compile(r"\[\s*\]")
_GAP = re.compile(r"(?:\s|![^\n]*)*")
_BRACKETS = {c: None for c in range(128) if chr(c) not in "[]"}
MAX_LITERAL_DEPTH = 4  # lark's LITAGG reads aggregates nested this deep; deeper ones are its to read
_RESERVED = frozenset(
    "alias and backward case connect const default div do else elseif endfor endfunc endif endmodule endproc "
    "endrecord endtest endtrap endwhile error exit for from func goto if inout local mod module not or pers proc "
    "raise record retry return step task test then to trap trynext undo var while with xor".split())


def take_runs(builder: Builder, text: str) -> str:
    """``text`` with each run of such lines made nodes (``builder.runs``) and replaced by one
    token; lines keep their numbers. A text holding a mark has no runs."""
    builder.runs = []
    if RUN_MARK in text or CALLS_MARK in text:
        return text
    pieces, taken, line, counted = [], 0, 1, 0
    for start in _START.finditer(text):
        if start.start() < taken:
            continue
        run, probe, end, read = Run(), start.start(), None, None
        while True:
            line += text.count("\n", counted, probe)
            counted = probe
            got = (read or _declaration)(builder, text, probe, line)
            if got is None and read is None:
                read, got = _call, _call(builder, text, probe, line)
            if got is None:
                break
            read = read or _declaration
            run.append(got[0])
            end = got[1]
            probe = _GAP.match(text, end).end()
        if end is not None:
            mark = CALLS_MARK if read is _call else RUN_MARK
            lines = "\n" * text.count("\n", start.start(), end)
            pieces += [text[taken:start.start()], f"{mark}{len(builder.runs)}{lines}{mark}"]
            builder.runs.append(run)
            taken = end
    return "".join(pieces) + text[taken:]


def _declaration(builder: Builder, text: str, at: int, line: int):
    """(node, end) of the declaration of a literal at ``at``, or None."""
    m = _NUMBERS_PARTS.match(text, at)
    if m is not None and not _EMPTY.search(m.group(5)):
        try:
            value, end = JSON_VALUE(m.group(5), 0)
            if end == len(m.group(5)):
                return builder.declaration(m, line, value), m.end()
        except (ValueError, StopIteration):
            pass
    m = DECLARATION_PARTS.match(text, at)
    return None if m is None else (builder.declaration(m, line), m.end())


def _call(builder: Builder, text: str, at: int, line: int):
    """(node, end) of a call of a move at ``at`` whose arguments are all plain, or None."""
    head = _HEAD.match(text, at)
    if head is None:
        return None
    args, at, required = [], head.end(), True
    while True:
        if text.startswith("\\", at):
            option = _OPTION.match(text, at)
            if option is None:
                return None
            got = _value(builder, text, option.end(), line) if option.group(2) else (None, option.end())
            if got is None:
                return None
            args.append(n.Arg(got[0], option.group(1), True))
        elif required:
            got = _value(builder, text, at, line)
            if got is None:
                return None
            args.append(n.Arg(got[0]))
        else:
            return None
        after = _AFTER.match(text, got[1])
        if after is None:
            return None
        if after.group(2):
            name = head.group(1)
            return n.ProcCall(line, name, name.lower(), tuple(args)), after.end()
        at, required = after.end(), bool(after.group(1))


def _value(builder: Builder, text: str, at: int, line: int):
    """(node, end) of a name, a number or an aggregate of numbers at ``at``, or None."""
    if text.startswith("[", at):
        try:
            value, end = JSON_VALUE(text, at)
        except (ValueError, StopIteration):
            return None
        written = text[at:end]
        if "\n" in written or _NOT_NUMBERS.search(written) or _EMPTY.search(written) or _too_deep(written):
            return None
        return builder.make_literal(written, line, value), end
    m = _NAME.match(text, at)
    if m is not None:
        word = m.group()
        return None if word.lower() in _RESERVED else (n.Name(line, word, word.lower(), ()), m.end())
    m = _NUMBER.match(text, at)
    return None if m is None else (builder.NUMBER(Token("NUMBER", m.group(), line=line)), m.end())


def _too_deep(written: str) -> bool:
    brackets = written.translate(_BRACKETS)
    for _ in range(MAX_LITERAL_DEPTH):
        brackets = brackets.replace("[]", "")
    return bool(brackets)
