"""Reading a RAPID module file (.mod, .modx, .prg, .sys): bounded bytes, any encoding a controller
or RobotStudio writes, the ``%%%`` header blanked, then lark's LALR parser on ``rapid.lark``. No
entity, include or network exists in RAPID; a parse error is ``file:line: message``."""

from __future__ import annotations

import codecs
import functools
import re
from pathlib import Path

from ..errors import Diagnostic, RsxmlError
from ..files import read_regular

SUFFIXES = (".mod", ".modx", ".prg", ".sys")
MAX_NESTING = 64  # brackets and signs in a row: records nest a few deep; more is not a program
_HEADER = re.compile(r"\A\s*%%%.*?%%%", re.S)
_BOMS = ((codecs.BOM_UTF32_LE, "utf-32"), (codecs.BOM_UTF32_BE, "utf-32"), (codecs.BOM_UTF8, "utf-8-sig"),
         (codecs.BOM_UTF16_LE, "utf-16"), (codecs.BOM_UTF16_BE, "utf-16"))


@functools.lru_cache(maxsize=1)
def parser():
    from lark import Lark

    grammar = (Path(__file__).parent / "rapid.lark").read_text(encoding="utf-8")
    return Lark(grammar, parser="lalr", propagate_positions=True, maybe_placeholders=False)


def decode(data: bytes, path: str) -> str:
    """Text of a module: by its byte-order mark, else UTF-8, else Windows-1252 (what older
    controllers and RobotStudio write); a NUL outside a UTF-16/32 file is not text."""
    for bom, codec in _BOMS:
        if data.startswith(bom):
            try:
                return data.decode(codec)
            except UnicodeDecodeError as exc:
                raise RsxmlError(Diagnostic(path, 0, f"not valid {codec} text: {exc.reason}")) from None
    if b"\x00" in data:
        raise RsxmlError(Diagnostic(path, 0, "not a RAPID text file (it holds NUL bytes)"))
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return data.decode("cp1252", errors="replace")


def blank_header(text: str) -> str:
    """The ``%%% VERSION ... %%%`` header replaced by as many newlines, so lines keep their numbers."""
    return _HEADER.sub(lambda m: "\n" * m.group(0).count("\n"), text, count=1)


def check_nesting(text: str, path: str) -> None:
    """``RsxmlError`` at the line where brackets, or signs in a row, nest deeper than
    ``MAX_NESTING`` (the parse and the evaluation recurse that deep)."""
    depth, signs, line, quoted, comment = 0, 0, 1, False, False
    for ch in text:
        if ch == "\n":
            line, comment = line + 1, False
        if comment or (quoted and ch != '"'):
            continue
        if ch == '"':
            quoted = not quoted
        elif ch == "!":
            comment = True
        elif ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        if ch in "+-":
            signs += 1
        elif not ch.isspace():
            signs = 0
        if depth > MAX_NESTING or signs > MAX_NESTING:
            raise RsxmlError(Diagnostic(path, line, f"nested deeper than {MAX_NESTING}: not a RAPID program rswarp "
                                                    "reads"))


def parse_text(text: str, path: str):
    """The lark tree of a module's text; ``RsxmlError`` at the line of a syntax error."""
    from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

    text = text.replace("\r\n", "\n").replace("\r", "\n")
    check_nesting(text, path)
    try:
        return parser().parse(blank_header(text))
    except UnexpectedToken as exc:
        got = "the end of the file" if exc.token.type == "$END" else repr(str(exc.token))
        raise RsxmlError(Diagnostic(path, exc.line, f"RAPID syntax: unexpected {got}")) from None
    except UnexpectedCharacters as exc:
        raise RsxmlError(Diagnostic(path, exc.line, f"RAPID syntax: unexpected character {exc.char!r}")) from None
    except (UnexpectedEOF, UnexpectedInput) as exc:
        raise RsxmlError(Diagnostic(path, getattr(exc, "line", 0) or 0, "RAPID syntax: the module ends early")) \
            from None


def read_tree(path: str | Path):
    """(tree, text) of a module file."""
    path = Path(path)
    try:
        data = read_regular(path)
    except OSError as exc:
        raise RsxmlError(Diagnostic(str(path), 0, f"cannot read: {exc.strerror or exc}")) from None
    text = decode(data, str(path))
    return parse_text(text, str(path)), text
