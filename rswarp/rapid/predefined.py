"""The data every controller predefines: ``predefined.tsv`` beside this file, one name a line with
its type, storage, value and where the value comes from (the table's header says its sources):
the speeds v5 to v7000, vmax, vrot and vlin, the zones z0 to z200 and fine, tool0, wobj0, load0,
reg1 to reg5, pi, WAIT_MAX, the inttypes USINT .. LINT, high, low and edge, the system data
(ERRNO, INTNO, C_MOTSET, C_PROGDISP, ROB_ID), the manual's enumerations (resOK, SOCKET_CONNECTED,
EGM_FRAME_WOBJ, ...), the error numbers ERR_ .. and the options' constants (PickMaster's
PM_ERR_JOB_EMPTY, ...). A task's own declaration of one of these names (base.sys declares tool0,
user.sys reg1) takes its place."""

from __future__ import annotations

import functools
import re
from importlib import resources

from .values import NUMBERS, Types
from .words import CONFIGURED_TYPES, DEVICE_TYPES

# The records of the system data the table holds (motsetdata, progdisp), as the manual lays them
# out: registered in a task's types unless the task declares a RECORD of that name itself.
RECORDS = {
    "veldata": (("num", "oride"), ("num", "max")),
    "accdata": (("num", "acc"), ("num", "ramp"), ("num", "finepramp")),
    "singdata": (("bool", "wrist"), ("bool", "arm"), ("bool", "base")),
    "confsupdata": (("bool", "jsup"), ("bool", "lsup"), ("num", "ax1"), ("num", "ax4"), ("num", "ax6")),
    "motsetdata": (("veldata", "vel"), ("accdata", "acc"), ("singdata", "sing"), ("confsupdata", "conf"),
                   ("num", "pathresol"), ("bool", "motionsup"), ("num", "tunevalue"), ("bool", "acclim"),
                   ("num", "accmax"), ("bool", "decellim"), ("num", "decelmax"), ("num", "cirpathreori"),
                   ("bool", "worldacclim"), ("num", "worldaccmax"), ("bool", "evtbufferact"), ("num", "prespeed")),
    "progdisp": (("pose", "pdisp"), ("extjoint", "eoffs")),
}
SOURCES = ("rswarp", "machina", "pyrapid", "rpi", "vscode", "help", "recalled", "stand-in")
_ERR_BASE = 41000  # the error numbers' stand-ins: 41000 to 41999


class Row:
    """One line of the table."""

    __slots__ = ("name", "type", "storage", "value", "source")

    def __init__(self, name: str, type_: str, storage: str, value, source: str):
        self.name, self.type, self.storage, self.value, self.source = name, type_, storage, value, source

    def __repr__(self):
        return f"Row({self.name!r}, {self.type!r}, {self.storage!r}, {self.value!r}, {self.source!r})"


@functools.lru_cache(maxsize=1)
def table() -> dict[str, Row]:
    """The rows of predefined.tsv by lower-case name (their values as Python: float, str, bool,
    nested lists; None for '-', the type's default)."""
    text = resources.files(__package__).joinpath("predefined.tsv").read_text(encoding="utf-8")
    out: dict[str, Row] = {}
    header = True
    for number, line in enumerate(text.splitlines(), 1):
        if not line or line.startswith("#"):
            continue
        cols = line.split("\t")
        if header:  # the column names
            header = False
            continue
        if len(cols) != 5 or cols[4] not in SOURCES or cols[2] not in ("const", "var", "pers"):
            raise ValueError(f"predefined.tsv:{number}: not name, type, storage, value and a source of {SOURCES}")
        name, type_, storage, value, source = cols
        if name.lower() in out:
            raise ValueError(f"predefined.tsv:{number}: {name} twice")
        out[name.lower()] = Row(name, type_.lower(), storage, None if value == "-" else literal(value), source)
    return out


_TOKEN = re.compile(r'\s*(?:(\[)|(\])|(,)|("(?:[^"]|"")*")|(TRUE|FALSE)|([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?))')


def literal(text: str):
    """A RAPID literal or aggregate as Python: numbers as float, strings, TRUE/FALSE, lists."""
    pos, stack = 0, [[]]
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if m is None:
            raise ValueError(f"not a RAPID value: {text!r}")
        pos = m.end()
        open_, close, comma, string, boolean, number = m.groups()
        if open_:
            stack.append([])
        elif close:
            done = stack.pop()
            stack[-1].append(done)
        elif comma:
            continue
        elif string is not None:
            stack[-1].append(string[1:-1].replace('""', '"'))
        elif boolean:
            stack[-1].append(boolean == "TRUE")
        else:
            stack[-1].append(float(number))
    if len(stack) != 1 or len(stack[0]) != 1:
        raise ValueError(f"not one RAPID value: {text!r}")
    return stack[0][0]


def numeric_types() -> frozenset[str]:
    """The table's types whose every value is a number and that RAPID declares as an alias of num
    (inttypes, egmframetype, stoppoint, ...): read, compared and passed as numbers."""
    kinds: dict[str, bool] = {}
    for row in table().values():
        kinds[row.type] = kinds.get(row.type, True) and isinstance(row.value, float)
    return frozenset(t for t, all_numbers in kinds.items()
                     if all_numbers and t not in NUMBERS and t not in DEVICE_TYPES and t not in CONFIGURED_TYPES
                     and t not in RECORDS and t != "num")


def register(types: Types) -> None:
    """The table's record types and numeric aliases added to a task's types, where the task has no
    RECORD or ALIAS of that name of its own."""
    for name, components in RECORDS.items():
        if name not in types.records and name not in types.aliases:
            types.add_record(name, components)
    for name in numeric_types():
        if name not in types.records and name not in types.aliases:
            types.add_alias(name, "num")


def predefined(types: Types) -> dict[str, tuple[str, str, object]]:
    """Name (lower case) -> (type, storage, value) of the predefined data."""
    register(types)
    return {k: (r.type, r.storage, types.default(r.type) if r.value is None else types.coerce(r.value, r.type, r.name))
            for k, r in table().items()}


def _zones() -> dict[int, tuple[float, ...]]:
    """The zonedata table: z<N> -> (pzone_tcp, pzone_ori, pzone_eax, zone_ori, zone_leax, zone_reax)."""
    return {int(k[1:]): tuple(r.value[1:]) for k, r in table().items()
            if r.type == "zonedata" and k[:1] == "z" and k[1:].isdigit()}


ZONES = _zones()


@functools.lru_cache(maxsize=1)
def _error_numbers() -> tuple[dict[str, float], frozenset[float]]:
    numbers = {k: r.value for k, r in table().items() if k.startswith("err_") and r.type == "errnum"}
    return numbers, frozenset(numbers.values())


def error_number(name: str) -> float | None:
    """The number of one of the controller's error constants (ERR_WAIT_MAXTIME, ...): the table's,
    else a stand-in from the name (41000 + its letters' sum modulo 1000, the next one the table
    does not use), so programs can compare ERRNO with them. None for a name not ERR_..."""
    key = name.lower()
    if not key.startswith("err_"):
        return None
    numbers, used = _error_numbers()
    if key in numbers:
        return numbers[key]
    k = sum(ord(c) for c in key) % 1000
    for _ in range(1000):
        if _ERR_BASE + k not in used:
            break
        k = (k + 1) % 1000
    return float(_ERR_BASE + k)
