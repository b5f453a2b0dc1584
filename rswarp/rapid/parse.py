"""Reading a RAPID module file (.mod, .modx, .prg, .sys): bounded bytes, any encoding a controller
or RobotStudio writes, the ``%%%`` header blanked, brackets and signs bounded, then lark's LALR
parser on ``rapid.lark`` building ``nodes`` as it goes (``build.py``). No entity, include or
network exists in RAPID; a parse error is ``file:line: message``."""

from __future__ import annotations

import codecs
import contextlib
import functools
import os
import re
from pathlib import Path

import numpy as np

from ..errors import Diagnostic, RsxmlError
from ..files import cache_root, read_regular
from . import nodes
from .build import DECLARATION, MAX_STRING, STRING, Builder, literal_regex
from .errors import fail
from .runs import take_runs
from .syntax import explained

SUFFIXES = (".mod", ".modx", ".prg", ".sys")
MAX_NESTING = 64  # brackets and signs in a row: records nest a few deep; more is not a program
# Characters of one line: a generated aggregate of a few thousand targets fits; more is no program,
# and lark's lexer would hold many copies of it (a 10 MB unterminated string took 20 GB).
MAX_LINE = 256 * 1024
_HEADER = re.compile(r"\A\s*%%%.*?%%%", re.S)
_BOMS = ((codecs.BOM_UTF32_LE, "utf-32"), (codecs.BOM_UTF32_BE, "utf-32"), (codecs.BOM_UTF8, "utf-8-sig"),
         (codecs.BOM_UTF16_LE, "utf-16"), (codecs.BOM_UTF16_BE, "utf-16"))
_CONTROL = re.compile(r"[\x00-\x08\x0e-\x1f\x7f\ufffd]")
_QUOTED = re.compile(STRING + r"|![^\n]*")
_STEP = np.zeros(256, np.int8)  # +1 for an opening bracket, -1 for a closing one
_STEP[list(b"([{")] = 1
_STEP[list(b")]}")] = -1
_SIGN = np.zeros(256, bool)
_SIGN[list(b"+-")] = True
_SPACE = np.zeros(256, bool)
_SPACE[list(b" \t\r\n\f\v")] = True


@functools.lru_cache(maxsize=1)
def _grammar() -> str:
    text = (Path(__file__).parent / "rapid.lark").read_text(encoding="utf-8")
    slash = lambda r: r.replace("/", "\\/")  # noqa: E731
    return text + f"\nLITAGG.3: /{slash(literal_regex())}/\nLITDECL.5: /{slash(DECLARATION)}/\n"


def _parser(path: str):
    """lark's LALR parser of RAPID; its tables cached in rswarp's cache folder (building them takes
    most of a second). lark checks the cache against the grammar and its own version and rebuilds
    one that does not match or cannot be read; a folder that cannot be written is only slower."""
    import lark

    cache: str | bool = False
    folder = cache_root() / "rapid"
    with contextlib.suppress(OSError):
        folder.mkdir(parents=True, exist_ok=True)
        if os.access(folder, os.W_OK):
            cache = str(folder / f"grammar-lark{lark.__version__}.cache")
    return lark.Lark(_grammar(), parser="lalr", maybe_placeholders=False, transformer=Builder(path), cache=cache)


@functools.lru_cache(maxsize=1)
def _shared():
    """One parser, built once (its tables take a while); its builder is told each file's name."""
    return _parser("")


class NotText(RsxmlError):
    """A module file that is no text: binary, or encrypted (ABB's own system modules, a module
    saved NOVIEW). A task's folder skips one (``rapid.task``); one named by itself is an error."""


def decode(data: bytes, path: str) -> str:
    """Text of a module: by its byte-order mark, else UTF-8, else Windows-1252 (what older
    controllers and RobotStudio write); a NUL outside a UTF-16/32 file is not text (``NotText``)."""
    for bom, codec in _BOMS:
        if data.startswith(bom):
            try:
                return data.decode(codec)
            except UnicodeDecodeError as exc:
                fail(path, 0, f"not valid {codec} text: {exc.reason}")
    if b"\x00" in data:
        raise NotText(Diagnostic(path, 0, "not a RAPID text file: it holds NUL bytes (binary, or an encrypted module)"))
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        text = data.decode("cp1252", errors="replace")
    if len(_CONTROL.findall(text[:65536])) > 0.01 * min(len(text), 65536):
        raise NotText(Diagnostic(path, 0, "not RAPID text: binary or encrypted (a module saved NOVIEW is encrypted); "
                                          "rswarp cannot read it"))
    return text


def blank_header(text: str) -> str:
    """The ``%%% VERSION ... %%%`` header replaced by as many newlines, so lines keep their numbers."""
    return _HEADER.sub(lambda m: "\n" * m.group(0).count("\n"), text, count=1)


def check_lines(text: str, path: str) -> None:
    """A ``file:line`` error at the first line longer than ``MAX_LINE`` characters (an unterminated
    string or comment runs to its line's end, so this bounds them too)."""
    if len(text) <= MAX_LINE:
        return
    ends = np.flatnonzero(np.frombuffer(text.encode("utf-32-le"), np.uint32) == 10)
    bounds = np.concatenate([[-1], ends, [len(text)]])
    lengths = np.diff(bounds) - 1
    long = np.flatnonzero(lengths > MAX_LINE)
    if len(long):
        k = int(long[0])
        fail(path, k + 1, f"a line of {int(lengths[k])} characters: rswarp reads lines of at most {MAX_LINE} (an "
                          "unterminated string or comment?)")


def check_nesting(text: str, path: str) -> None:
    """A ``file:line`` error where brackets, or signs in a row, nest deeper than ``MAX_NESTING``
    (the evaluation recurses that deep); strings and comments do not count, however they are
    quoted. Counted with NumPy over the bytes: a file of millions of lines costs a few passes."""
    long = []

    def blank(m):
        # an escape (\XX) takes at most three characters: longer than this is too long for sure,
        # and the parser checks the exact length of the rest
        if m.group()[0] == '"' and len(m.group()) > 3 * MAX_STRING + 2 and not long:
            long.append(m.start())
        return " " * len(m.group())

    bare = _QUOTED.sub(blank, text)
    if long:  # refused before the parser reads megabytes of it
        fail(path, text.count("\n", 0, long[0]) + 1, f"a string of over {MAX_STRING} characters: RAPID strings hold "
                                                     f"at most {MAX_STRING}")
    data = np.frombuffer(bare.encode("utf-8", "replace"), np.uint8)
    places = []
    steps = _STEP[data]
    brackets = np.flatnonzero(steps)  # the depth changes only there
    deep = brackets[np.cumsum(steps[brackets], dtype=np.int32) > MAX_NESTING]
    if len(deep):
        places.append(int(deep[0]))
    solid = ~_SPACE[data]  # spaces do not end a run of signs; anything else does
    signs = np.flatnonzero(_SIGN[data[solid]])  # places among the bytes that are not spaces
    if len(signs) > MAX_NESTING:
        starts = np.concatenate([[0], np.flatnonzero(np.diff(signs) != 1) + 1])
        lengths = np.diff(np.concatenate([starts, [len(signs)]]))
        if lengths.max() > MAX_NESTING:
            first = signs[starts[int(np.argmax(lengths > MAX_NESTING))]]
            places.append(int(np.flatnonzero(solid)[first]))
    if places:
        line = int(np.count_nonzero(data[:min(places)] == 10)) + 1
        fail(path, line, f"nested deeper than {MAX_NESTING}: not a RAPID program rswarp reads")


def parse_text(text: str, path: str) -> list[nodes.Module]:
    """The modules of a file's text; ``RsxmlError`` at the line of a syntax error."""
    from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

    text = blank_header(text.replace("\r\n", "\n").replace("\r", "\n"))
    check_nesting(text, path)  # a string too long is said as such first
    check_lines(text, path)
    parser = _shared()
    builder = parser.options.transformer
    builder.path = path
    text = take_runs(builder, text)  # the same lines: errors are told at them, in this text
    try:
        modules = parser.parse(text)
    except UnexpectedToken as exc:
        end = exc.token.type == "$END"
        fail(path, *explained(text, exc.line if not end else text.count("\n") + 1, None if end else
                              _as_written(exc.token, builder), exc.expected))
    except UnexpectedCharacters as exc:
        line, message = explained(text, exc.line, None, ())
        what = "a string that does not end on its line (a \" is missing)" if exc.char == '"' else \
            f"unexpected character {exc.char!r}"
        fail(path, line, message if line < exc.line or message.startswith("an XML") else f"RAPID syntax: {what}")
    except (UnexpectedEOF, UnexpectedInput) as exc:
        fail(path, getattr(exc, "line", 0) or 0, "RAPID syntax: the module ends early")
    for module in modules:
        _check_blocks(module, path)
    return modules


def _as_written(token, builder):
    """A token as the programmer wrote it: a run's first word, not its mark."""
    if token.type not in ("RUN", "CALLS"):
        return token
    first = builder.runs[int(str(token).strip("\x01\x02\n"))][0]
    return token.new_borrow_pos("NAME", first.name if token.type == "CALLS" else first.storage.upper(), token)


def _check_blocks(module: nodes.Module, path: str) -> None:
    from .build import MAX_BLOCKS

    for r in module.routines:
        if r.body.depth > MAX_BLOCKS:
            fail(path, r.line, f"routine '{r.name}' nests IF, FOR, WHILE and TEST deeper than {MAX_BLOCKS}")


def read_file(path: str | Path) -> tuple[list[nodes.Module], str]:
    """(modules, text) of a module file."""
    path = Path(path)
    try:
        data = read_regular(path)
    except OSError as exc:
        fail(str(path), 0, f"cannot read: {exc.strerror or exc}")
    text = decode(data, str(path))
    return parse_text(text, str(path)), text
