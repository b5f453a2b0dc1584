"""A RAPID module as rswarp runs it: its data (CONST, PERS, VAR and TASK PERS declarations,
evaluated in order over the predefined data) and one routine's motion: MoveAbsJ, MoveJ, MoveL and
MoveC with their tool and work object, Offs() and RelTool() targets, and WaitTime. Any other
statement is skipped with a warning at its line, never silently."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from lark import Token, Tree

from ..errors import Diagnostic, RsxmlError
from .evaluate import Evaluator
from .parse import blank_header, read_tree
from .steps import declarations, routine_steps


@dataclass(frozen=True)
class Module:
    """A module's name, its data (name -> (type, value)), the chosen routine's steps (``Move`` and
    ``Wait``), and the warnings of what was skipped."""

    path: str
    name: str
    data: dict
    routine: str
    steps: tuple
    warnings: tuple[Diagnostic, ...] = field(default=())


def read_module(path: str | Path, routine: str = "main") -> Module:
    """The module at ``path`` with ``routine``'s motion; ``RsxmlError`` at the line of an unknown
    name, a malformed record or a syntax error, or when the routine is missing."""
    tree, text = read_tree(path)
    ev = Evaluator(str(path), blank_header(text.replace("\r\n", "\n").replace("\r", "\n")))
    module = tree.children[0]
    name = str(module.children[0])
    declarations(ev, [c for c in module.children if isinstance(c, Tree) and c.data == "declaration"])
    procs = {_routine_name(c).lower(): c for c in module.children
             if isinstance(c, Tree) and c.data in ("proc", "func", "trap")}
    if routine.lower() not in procs:
        raise RsxmlError(Diagnostic(str(path), module.meta.line, f"no routine '{routine}' in module '{name}' "
                                                                 f"(routines: {', '.join(procs) or 'none'})"))
    steps, warnings = routine_steps(ev, procs[routine.lower()])
    return Module(str(path), name, dict(ev.data), routine, tuple(steps), tuple(warnings))


def _routine_name(node: Tree) -> str:
    names = [c for c in node.children if isinstance(c, Token) and c.type == "NAME"]
    return str(names[1] if node.data == "func" else names[0])
