"""RAPID expressions of one module evaluated to numbers, booleans, strings and nested lists (its
records), over the data declared so far and the predefined data; Offs() and RelTool()."""

from __future__ import annotations

import numpy as np
from lark import Token, Tree

from ..errors import Diagnostic, RsxmlError
from . import data as rd


class Evaluator:
    """Expressions of one module, evaluated to numbers, booleans, strings and nested lists."""

    def __init__(self, path: str, text: str = ""):
        self.path = path
        self.text = text  # the module's text, for how an argument was written
        self.data: dict[str, tuple[str, object]] = {k.lower(): v for k, v in rd.predefined().items()}
        self.types: dict[str, str] = {}

    def fail(self, line: int, message: str):
        raise RsxmlError(Diagnostic(self.path, line, message))

    def value(self, node):
        """The value of an expression node."""
        if isinstance(node, Token):
            return str(node)
        kind = node.data
        line = node.meta.line
        if kind == "number":
            return float(node.children[0])
        if kind == "string":
            return str(node.children[0])[1:-1].replace('""', '"')
        if kind == "aggregate":
            return [self.value(c) for c in node.children]
        if kind == "neg":
            v = self.value(node.children[0])
            return -v if isinstance(v, float) else self.fail(line, "'-' needs a number")
        if kind == "name":
            return self.name(node)
        if kind in ("sum", "product"):
            return self.arithmetic(node)
        if kind == "function":
            return self.function(node)
        self.fail(line, f"rswarp cannot evaluate this expression ({kind}) in data")

    def name(self, node):
        """A name, with ``{index}`` and ``.field`` selectors on arrays and records."""
        ident = str(node.children[0])
        low = ident.lower()
        if low in ("true", "false"):
            return low == "true"
        if low not in self.data:
            self.fail(node.meta.line, f"unknown name '{ident}'")
        value = self.data[low][1]
        for sel in node.children[1:]:
            if sel.children and isinstance(sel.children[0], Token) and sel.children[0].type == "NAME":
                self.fail(node.meta.line, f"rswarp does not read record fields ('{ident}.{sel.children[0]}')")
            for index in sel.children:
                k = self.value(index)
                if not isinstance(value, list) or not isinstance(k, float) or not 1 <= k <= len(value):
                    self.fail(node.meta.line, f"index {k} of '{ident}' is outside 1..{len(value)}")
                value = value[int(k) - 1]
        return value

    def arithmetic(self, node):
        items = node.children
        out = self.value(items[0])
        for op, rhs in zip(items[1::2], items[2::2]):
            b = self.value(rhs)
            if not isinstance(out, float) or not isinstance(b, float):
                self.fail(node.meta.line, f"'{op}' needs numbers")
            o = str(op).lower()
            if o in ("/", "div", "mod") and b == 0:
                self.fail(node.meta.line, "division by zero")
            out = {"+": out + b, "-": out - b, "*": out * b, "/": out / b,
                   "div": float(int(out) // int(b)), "mod": float(int(out) % int(b))}[o]
        return out

    def function(self, node):
        fname = str(node.children[0]).lower()
        if fname not in ("offs", "reltool"):
            self.fail(node.meta.line, f"rswarp does not evaluate the function '{node.children[0]}'")
        plain, optional = arguments(self, node.children[1:])
        if len(plain) != 4:
            self.fail(node.meta.line, f"{node.children[0]} takes a robtarget and three distances")
        target, dx, dy, dz = plain
        if rd.mismatch(target, rd.SHAPES["robtarget"]) or not all(isinstance(v, float) for v in (dx, dy, dz)):
            self.fail(node.meta.line, f"{node.children[0]} takes a robtarget and three distances")
        return offs(target, dx, dy, dz) if fname == "offs" else reltool(target, dx, dy, dz, optional)


def arguments(ev: Evaluator, args) -> tuple[list, dict]:
    """(plain values, optional name -> value or True) of call arguments."""
    plain, optional = [], {}
    for a in args:
        parts = a.children if isinstance(a, Tree) and a.data == "arg" else [a]
        for p in parts:
            if isinstance(p, Tree) and p.data == "optional":
                name = str(p.children[0]).lower()
                optional[name] = ev.value(p.children[1]) if len(p.children) > 1 else True
            else:
                plain.append(ev.value(p))
    return plain, optional


def offs(target: list, dx: float, dy: float, dz: float) -> list:
    """RAPID's Offs: the robtarget displaced in its work object (mm)."""
    out = [list(target[0]), list(target[1]), list(target[2]), list(target[3])]
    out[0] = [target[0][0] + dx, target[0][1] + dy, target[0][2] + dz]
    return out


def reltool(target: list, dx: float, dy: float, dz: float, optional: dict) -> list:
    """RAPID's RelTool: the robtarget displaced in its own tool frame (mm), then turned about the
    tool's x, y and z (\\Rx, \\Ry, \\Rz, degrees, in that order)."""
    from scipy.spatial.transform import Rotation

    m = rd.pose(target[:2]).matrix()
    move = np.eye(4)
    move[:3, 3] = np.array([dx, dy, dz]) / 1000.0
    angles = [float(optional.get(k, 0.0)) for k in ("rx", "ry", "rz")]
    move[:3, :3] = Rotation.from_euler("XYZ", angles, degrees=True).as_matrix()
    m = m @ move
    x, y, z, w = Rotation.from_matrix(m[:3, :3]).as_quat()
    return [list(m[:3, 3] * 1000.0), [w, x, y, z], list(target[2]), list(target[3])]
