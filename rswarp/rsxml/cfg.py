"""ABB's CFG text format, the system parameters of a RobotWare backup (``SYSPAR/EIO.cfg``,
``SYSPAR/MOC.cfg``, ...): a header line (``MOC:CFG_1.0:6:0::``), then sections (``NAME:`` at the
start of a line, ``#`` lines between them) of instances, each a line of ``-key value`` attributes
continued on the next line after a trailing backslash. A value is quoted text, a bare word or a
number (``-3.14`` is a value, not a key), or absent: a flag (``-rotating_move``), read as True.

One tokenizer for every reader, so that EIO and MOC agree on what a line means. A strict reader
gets a ``file:line`` error for text that is no attribute; a lenient one skips it, as the
controller's own readers of optional files do."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Mapping

from ..errors import Diagnostic, RsxmlError
from ..files import read_regular

_SECTION = re.compile(r"^([A-Z][A-Z0-9_]*):\s*$")
# a key (a dash and a letter: "-3.14" is a number), quoted text (backslash escapes kept), a bare value
_TOKEN = re.compile(r'\s*(?:-([A-Za-z_]\w*)|"((?:[^"\\]|\\.)*)"|([^\s"]+))')


@dataclass(frozen=True)
class CfgInstance:
    """One instance of a section: its attributes by lower-case key (text, or True for a flag; the
    last of a repeated key), the line each key is on, and the line the instance starts on."""

    section: str
    line: int
    attrs: Mapping[str, str | bool] = field(default_factory=dict)
    lines: Mapping[str, int] = field(default_factory=dict, repr=False)

    @property
    def name(self) -> str | None:
        """The instance's ``-name`` (``-Name`` in EIO), None where it has none."""
        return self.text("name")

    def text(self, key: str) -> str | None:
        """The value of ``key`` as text; None where absent or given as a bare flag."""
        value = self.attrs.get(key)
        return value if isinstance(value, str) else None

    def flag(self, key: str) -> bool:
        """Whether ``key`` is given (a flag, or a key with any value)."""
        return key in self.attrs

    def line_of(self, key: str) -> int:
        """The line ``key`` is on, else the instance's first line."""
        return self.lines.get(key, self.line)


def decode_cfg(data: bytes, path: str) -> str:
    """The text of a CFG file: UTF-8 (a byte-order mark allowed), else Windows-1252, which older
    controllers write; a NUL byte means it is no CFG text."""
    if b"\x00" in data:
        raise RsxmlError(Diagnostic(path, 0, "not a CFG text file (it holds NUL bytes)"))
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("cp1252", errors="replace")


def read_cfg(path: str, domain: str | None = None) -> tuple[CfgInstance, ...]:
    """The instances of a CFG file read strictly (``parse_cfg``); ``file:line`` errors where it
    cannot be read or a line is no attribute."""
    try:
        data = read_regular(path)
    except OSError as exc:
        raise RsxmlError(Diagnostic(path, 0, f"cannot read: {exc.strerror or exc}")) from None
    return parse_cfg(decode_cfg(data, path), path, domain=domain)


def parse_cfg(text: str, path: str, *, strict: bool = True, domain: str | None = None) -> tuple[CfgInstance, ...]:
    """Every instance of every section, in file order. An instance starts at a ``-name`` line, or
    at a line after one without a trailing backslash that opens with the same key as the instance
    before it (sections without names, EIO's SYSSIG_OUT); any other line continues the instance,
    so a forgotten backslash loses nothing. ``domain`` (``MOC``): the first line must be its
    header. Strict: text outside a section or that is no ``-key [value]`` is an error."""
    out: list[CfgInstance] = []
    section, lines, continued = None, [], False
    for k, raw in enumerate(text.splitlines(), 1):
        stripped = raw.strip()
        if domain is not None and not out and not lines and section is None and stripped:
            _check_header(path, k, stripped, domain)
            domain = None
            continue
        head = _SECTION.match(raw)
        if head:
            _flush(out, section, lines, path, strict)
            section, lines, continued = head.group(1), [], False
            continue
        if not stripped or stripped.startswith("#"):
            continue
        if section is None:
            if strict:
                raise RsxmlError(Diagnostic(path, k, f"'{_short(stripped)}' stands before any section (NAME:)"))
            continue
        body = stripped[:-1].rstrip() if stripped.endswith("\\") else stripped
        if lines and _starts_instance(body, lines, continued):
            _flush(out, section, lines, path, strict)
            lines = []
        lines.append((k, body))
        continued = stripped.endswith("\\")
    if domain is not None:  # the file ended before its first line: empty, or only blank lines
        raise RsxmlError(Diagnostic(path, 1, f"not a {domain}.cfg: the file is empty, without the header "
                                             f"{domain}:CFG_1.0:<version>:<revision>::"))
    _flush(out, section, lines, path, strict)
    return tuple(out)


def _check_header(path: str, line: int, text: str, domain: str) -> None:
    if not re.match(rf"{re.escape(domain)}:CFG_\d+(\.\d+)*:", text, re.I):
        raise RsxmlError(Diagnostic(path, line, f"not a {domain}.cfg: its first line is '{_short(text)}', not the "
                                                f"header {domain}:CFG_1.0:<version>:<revision>::"))


def _starts_instance(body: str, lines: list[tuple[int, str]], continued: bool) -> bool:
    first = _first_key(body)
    if first == "name":
        return True
    return not continued and first is not None and first == _first_key(lines[0][1])


def _first_key(body: str) -> str | None:
    m = _TOKEN.match(body)
    return m.group(1).lower() if m and m.group(1) else None


def _flush(out: list, section: str | None, lines: list[tuple[int, str]], path: str, strict: bool) -> None:
    """The instance made of ``lines`` (line number, text), appended to ``out``."""
    if section is None or not lines:
        return
    attrs: dict[str, str | bool] = {}
    at: dict[str, int] = {}
    key = None
    for k, body in lines:
        pos = 0
        while pos < len(body):
            m = _TOKEN.match(body, pos)
            if m is None or m.end() == pos:
                if strict:
                    raise RsxmlError(Diagnostic(path, k, f"'{_short(body[pos:].strip())}': an unclosed quote"))
                break
            pos = m.end()
            if m.group(1) is not None:
                key = m.group(1).lower()
                attrs[key], at[key] = True, k
            elif key is not None and attrs[key] is True:
                attrs[key] = m.group(2) if m.group(2) is not None else m.group(3)
            elif strict:
                value = _short(m.group(0).strip())
                raise RsxmlError(Diagnostic(path, k, f"'{value}' in {section} is no attribute: give -key value"))
    if attrs:
        out.append(CfgInstance(section, lines[0][0], MappingProxyType(attrs), MappingProxyType(at)))


def _short(text: str, n: int = 60) -> str:
    return text if len(text) <= n else text[: n - 3] + "..."
