"""RAPID's string functions beyond the basic ones (StrToVal to every data type, StrMatch, StrMap,
ByteToStr, StrToByte, DecToHex, HexToDec), as the reference manual defines them: positions are
1-based, a search that finds nothing answers the length plus one."""

from __future__ import annotations

import math

from .arguments import Arguments
from .errors import fail
from .live import parse_input
from .values import Mismatch


def strtoval(interp, a: Arguments) -> bool:
    """StrToVal: the text as a value of the variable's own type (a num, a bool, a quoted string,
    a pos or robtarget written as its aggregate); FALSE, the variable untouched, when it is not."""
    a.need(2)
    text, target = a.value(0, "string"), a.reference(1)
    base = interp.types.base(target.type)
    if base == "string":
        stripped = text.strip()
        if len(stripped) < 2 or stripped[0] != '"' or stripped[-1] != '"':
            return False
    try:
        value = parse_input(text, base)
        value = interp.types.coerce(value, target.type, "StrToVal's value")
    except (ValueError, Mismatch):
        return False
    if isinstance(value, float) and not math.isfinite(value):
        return False
    target.set(value)
    return True


def strmatch(interp, a: Arguments) -> float:
    """StrMatch: where ``pattern`` starts in the string from ``start`` on, else its length + 1."""
    a.need(3)
    s, start, pattern = a.value(0, "string"), int(a.number(1)), a.value(2, "string")
    if start < 1:
        fail(interp.path, a.line, f"StrMatch: the start position {start} is before the string")
    found = s.find(pattern, start - 1)
    return float(found + 1 if found >= 0 else len(s) + 1)


def strmap(interp, a: Arguments) -> str:
    """StrMap: each character found in FromMap replaced by the one at its place in ToMap."""
    a.need(3)
    s, src, dst = a.value(0, "string"), a.value(1, "string"), a.value(2, "string")
    table = {c: dst[k] for k, c in enumerate(src) if k < len(dst)}
    return "".join(table.get(c, c) for c in s)


_BASES = (("hex", 16, "02X"), ("okt", 8, "03o"), ("bin", 2, "08b"))


def bytetostr(interp, a: Arguments) -> str:
    """ByteToStr: a byte (0 to 255) as decimal text, or \\Hex, \\Okt, \\Bin or \\Char."""
    a.need(1)
    b = a.number(0)
    if not (b == int(b) and 0 <= b <= 255):
        fail(interp.path, a.line, f"ByteToStr takes a byte of 0 to 255, not {b:g}")
    if a.has("Char"):
        return chr(int(b))
    for name, _, spec in _BASES:
        if a.has(name):
            return format(int(b), spec)
    return str(int(b))


def strtobyte(interp, a: Arguments) -> float:
    """StrToByte: the byte the text writes (decimal, or \\Hex, \\Okt, \\Bin or \\Char)."""
    a.need(1)
    text = a.value(0, "string")
    try:
        if a.has("Char"):
            value = ord(text) if len(text) == 1 else -1
        else:
            base = next((b for name, b, _ in _BASES if a.has(name)), 10)
            value = int(text, base)
    except ValueError:
        value = -1
    if not 0 <= value <= 255:
        fail(interp.path, a.line, f"StrToByte: '{text}' is no byte")
    return float(value)


def dectohex(interp, a: Arguments) -> str:
    a.need(1)
    text = a.value(0, "string")
    if not text.isdigit():
        fail(interp.path, a.line, f"DecToHex: '{text}' is not a decimal number")
    return format(int(text), "X")


def hextodec(interp, a: Arguments) -> str:
    a.need(1)
    text = a.value(0, "string")
    try:
        return str(int(text, 16))
    except ValueError:
        fail(interp.path, a.line, f"HexToDec: '{text}' is not a hexadecimal number")


_RELATIONS = {1: lambda a, b: a < b, 2: lambda a, b: a <= b, 3: lambda a, b: a == b, 4: lambda a, b: a != b,
              5: lambda a, b: a >= b, 6: lambda a, b: a > b}  # LT LTEQ EQ NOTEQ GTEQ GT
_OPERATIONS = {1: lambda a, b: a + b, 2: lambda a, b: a - b, 3: lambda a, b: a * b, 4: lambda a, b: a // b,
               5: lambda a, b: a % b}  # OpAdd OpSub OpMult OpDiv OpMod


def _digits(interp, a: Arguments, k: int) -> int:
    text = a.value(k, "string")
    if not text.isdigit() or len(text) > 80:
        fail(interp.path, a.line, f"{a.name}: '{text}' is not a string of digits")
    return int(text)


def strdigcmp(interp, a: Arguments) -> bool:
    """StrDigCmp(Str1, Relation, Str2): whole numbers written as digits compared (LT ... GT)."""
    a.need(3)
    rel = _RELATIONS.get(int(a.number(1)))
    if rel is None:
        fail(interp.path, a.line, "StrDigCmp takes LT, LTEQ, EQ, NOTEQ, GTEQ or GT")
    return rel(_digits(interp, a, 0), _digits(interp, a, 2))


def strdigcalc(interp, a: Arguments) -> str:
    """StrDigCalc(Str1, Operation, Str2): arithmetic on whole numbers written as digits."""
    a.need(3)
    op, x, y = _OPERATIONS.get(int(a.number(1))), _digits(interp, a, 0), _digits(interp, a, 2)
    if op is None:
        fail(interp.path, a.line, "StrDigCalc takes OpAdd, OpSub, OpMult, OpDiv or OpMod")
    if y == 0 and op in (_OPERATIONS[4], _OPERATIONS[5]):
        fail(interp.path, a.line, "StrDigCalc: division by zero")
    value = op(x, y)
    if value < 0:
        fail(interp.path, a.line, "StrDigCalc: the result is negative")
    return str(value)


FUNCTIONS = {"strdigcmp": strdigcmp, "strdigcalc": strdigcalc,
             "strtoval": strtoval, "strmatch": strmatch, "strmap": strmap, "bytetostr": bytetostr,
             "strtobyte": strtobyte, "dectohex": dectohex, "hextodec": hextodec}
