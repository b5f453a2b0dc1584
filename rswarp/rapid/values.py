"""RAPID's values at run time and their types: num, dnum, bool and string as Python's float, bool
and str; records (robtarget, tooldata, a user's RECORD) as immutable ``Rec`` of a type and its
components; arrays as ``Arr``, filled in place; I/O signals as ``Signal``. ``Types`` knows every
record, alias and atomic type of a task and turns an aggregate into a value of a type
(``coerce``), saying where it does not fit."""

from __future__ import annotations

import math
from dataclasses import dataclass

NUMBERS = {"num", "dnum", "byte", "intnum", "errnum", "dionum", "identno", "errdomain", "errtype", "opnum",
           "symnum", "event_type", "handler_type", "iounit_state", "signalorigin", "triggmode", "bool_num",
           "trapdata_num", "listitem", "paridnum", "paridvalidnum", "sensorstate", "opcalc", "icondata",
           "buttondata", "btnres", "restartdata_num", "triggstatus", "socketstatus", "exec_level", "busstate",
           "tunetype", "aiotrigg"}
SIGNALS = {"signaldi", "signaldo", "signalgi", "signalgo", "signalai", "signalao"}
MAX_ELEMENTS = 1_000_000  # elements of one array: memory stays bounded

_N, _B, _S = "num", "bool", "string"
RECORDS: dict[str, tuple[tuple[str, str], ...]] = {
    "pos": (("x", _N), ("y", _N), ("z", _N)),
    "orient": (("q1", _N), ("q2", _N), ("q3", _N), ("q4", _N)),
    "pose": (("trans", "pos"), ("rot", "orient")),
    "confdata": (("cf1", _N), ("cf4", _N), ("cf6", _N), ("cfx", _N)),
    "extjoint": tuple((f"eax_{c}", _N) for c in "abcdef"),
    "robjoint": tuple((f"rax_{k}", _N) for k in range(1, 7)),
    "robtarget": (("trans", "pos"), ("rot", "orient"), ("robconf", "confdata"), ("extax", "extjoint")),
    "jointtarget": (("robax", "robjoint"), ("extax", "extjoint")),
    "loaddata": (("mass", _N), ("cog", "pos"), ("aom", "orient"), ("ix", _N), ("iy", _N), ("iz", _N)),
    "tooldata": (("robhold", _B), ("tframe", "pose"), ("tload", "loaddata")),
    "wobjdata": (("robhold", _B), ("ufprog", _B), ("ufmec", _S), ("uframe", "pose"), ("oframe", "pose")),
    "speeddata": (("v_tcp", _N), ("v_ori", _N), ("v_leax", _N), ("v_reax", _N)),
    "zonedata": (("finep", _B), ("pzone_tcp", _N), ("pzone_ori", _N), ("pzone_eax", _N), ("zone_ori", _N),
                 ("zone_leax", _N), ("zone_reax", _N)),
    "tasks": (("taskname", _S),),
}


class Rec:
    """A record value: its type (lower case) and components; never changed in place (a field
    assignment makes a new one), so values are shared safely."""

    __slots__ = ("type", "vals")

    def __init__(self, type_: str, vals: tuple):
        self.type = type_
        self.vals = vals

    def __eq__(self, other):
        return isinstance(other, Rec) and self.vals == other.vals

    def __hash__(self):
        return hash(self.vals)

    def __repr__(self):
        return f"{self.type}{list(self.vals)}"


class Arr:
    """An array: its element type, its dimensions and its elements in row-major order."""

    __slots__ = ("type", "dims", "items")

    def __init__(self, type_: str, dims: tuple[int, ...], items: list):
        self.type, self.dims, self.items = type_, dims, items

    def copy(self) -> "Arr":
        return Arr(self.type, self.dims, list(self.items))

    def offset(self, index: tuple[int, ...]) -> int | None:
        """The flat offset of 1-based ``index``, or None outside the array."""
        if len(index) != len(self.dims):
            return None
        k = 0
        for i, d in zip(index, self.dims):
            if not 1 <= i <= d:
                return None
            k = k * d + (i - 1)
        return k

    def __eq__(self, other):
        return isinstance(other, Arr) and self.dims == other.dims and self.items == other.items

    __hash__ = None


@dataclass(frozen=True)
class Signal:
    """An I/O signal, by name: its value is the run's (0 unless ``--io`` or the program set it)."""

    name: str


@dataclass(frozen=True)
class Opaque:
    """A value of a type rswarp does not model (triggdata, welddata, a clock): kept, passed on,
    never computed with."""

    type: str
    value: object = None


class _Unfit(Exception):
    """A value a converter cannot take (``Types.explain`` then says why)."""


_PLAIN = frozenset((int, float))  # number types of a literal (bool, an int's subclass, is not one)


def _number(v):
    if v.__class__ is float:
        return v
    if v.__class__ is int or v.__class__ is Signal:
        return float(v) if v.__class__ is int else v
    raise _Unfit()


def _bool(v):
    if v.__class__ is bool:
        return v
    raise _Unfit()


def _string(v):
    if v.__class__ is str:
        return v
    raise _Unfit()


class Mismatch(ValueError):
    """A value that does not fit its type; the message says where, the caller adds the line."""


class Types:
    """The types of a task: the built-in records and the task's RECORD and ALIAS declarations."""

    def __init__(self):
        self.records = dict(RECORDS)
        self.aliases: dict[str, str] = {"errstr": "string", "stringdig": "string"}  # RAPID's own aliases
        self._converters: dict = {}

    def add_record(self, name: str, components) -> None:
        self.records[name.lower()] = tuple((c.lower(), t.lower()) for t, c in components)
        self._converters.clear()

    def add_alias(self, name: str, base: str) -> None:
        self.aliases[name.lower()] = base.lower()
        self._converters.clear()

    def base(self, type_: str) -> str:
        type_ = type_.lower()
        for _ in range(16):  # an alias of an alias; a loop of aliases ends here
            if type_ not in self.aliases:
                break
            type_ = self.aliases[type_]
        return type_

    def fields(self, type_: str):
        return self.records.get(self.base(type_))

    def default(self, type_: str):
        """The value a declaration without one starts with: 0, FALSE, "" and records of those."""
        t = self.base(type_)
        if t in NUMBERS:
            return 0.0
        if t == "bool":
            return False
        if t == "string":
            return ""
        fields = self.records.get(t)
        if fields is not None:
            return Rec(t, tuple(self.default(ft) for _, ft in fields))
        return Opaque(t)

    def coerce(self, value, type_: str, where: str = "the value"):
        """``value`` as a value of ``type_`` (an aggregate becomes a record); ``Mismatch`` if it
        cannot be one. A converter made once per type does the work; where it fails, the slow
        reading says why."""
        convert = self._converters.get(type_)
        if convert is None:
            convert = self._converters[type_] = self._converter(self.base(type_))
        try:
            return convert(value)
        except _Unfit:
            return self.explain(value, type_, where)

    def _converter(self, t: str):
        """A function from a value to a value of base type ``t``, raising ``_Unfit``."""
        if t in NUMBERS:
            return _number
        if t == "bool":
            return _bool
        if t == "string":
            return _string
        fields = self.records.get(t)
        if fields is None:
            return lambda v: v if isinstance(v, (Opaque, Signal, Arr)) else Opaque(t, v)
        parts = [None] * len(fields)
        count = len(fields)

        def record(v):
            if v.__class__ is Rec:
                if v.type == t or self.records.get(v.type) == fields:
                    return v if v.type == t else Rec(t, v.vals)
                raise _Unfit()
            if v.__class__ not in (list, tuple) or len(v) != count:
                raise _Unfit()
            if parts[0] is None:
                parts[:] = [self._converter(self.base(ft)) for _, ft in fields]
            return Rec(t, tuple([p(x) for p, x in zip(parts, v)]))
        if not all(self.base(ft) in NUMBERS for _, ft in fields):
            return record

        def numeric(v):  # pos, orient, confdata, extjoint: most of a module of targets
            if (v.__class__ is list or v.__class__ is tuple) and len(v) == count and _PLAIN.issuperset(map(type, v)):
                return Rec(t, tuple(map(float, v)))
            return record(v)
        return numeric

    def explain(self, value, type_: str, where: str = "the value"):
        """``coerce`` the slow way, with a ``Mismatch`` that says which part does not fit."""
        t = self.base(type_)
        if t in NUMBERS:
            if isinstance(value, Signal):
                return value
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                return float(value)
            raise Mismatch(f"{where} must be a number, not {describe(value)}")
        if t == "bool":
            if isinstance(value, bool):
                return value
            raise Mismatch(f"{where} must be TRUE or FALSE, not {describe(value)}")
        if t == "string":
            if isinstance(value, str):
                return value
            raise Mismatch(f"{where} must be a string, not {describe(value)}")
        fields = self.records.get(t)
        if fields is None:
            return value if isinstance(value, (Opaque, Signal, Arr)) else Opaque(t, value)
        if isinstance(value, Rec):
            if value.type == t or self.records.get(value.type) == fields:
                return value if value.type == t else Rec(t, value.vals)
            raise Mismatch(f"{where} must be a {t}, not a {value.type}")
        if not isinstance(value, (list, tuple)):
            raise Mismatch(f"{where} must be a {t} {shape(fields)}, not {describe(value)}")
        if len(value) != len(fields):
            raise Mismatch(f"{where} must be a {t} of {len(fields)} parts {shape(fields)}, not {len(value)}")
        return Rec(t, tuple(self.explain(v, ft, f"{where}.{fn}") for v, (fn, ft) in zip(value, fields)))

    def array(self, type_: str, dims: tuple[int, ...], value, where: str) -> Arr:
        """An array of ``dims`` from nested aggregates (or default elements when ``value`` is None)."""
        count = math.prod(dims)
        if not dims or count < 1 or count > MAX_ELEMENTS:
            raise Mismatch(f"{where} must have 1 to {MAX_ELEMENTS} elements, not {count}")
        if value is None:
            first = self.default(type_)
            return Arr(type_.lower(), dims, [first] * count)
        if isinstance(value, Arr):
            if value.dims != dims:
                raise Mismatch(f"{where} has dimensions {list(dims)}, the value {list(value.dims)}")
            return value.copy()
        items: list = []
        self._flatten(value, type_, dims, where, items)
        return Arr(type_.lower(), dims, items)

    def _flatten(self, value, type_: str, dims: tuple[int, ...], where: str, out: list) -> None:
        if not isinstance(value, (list, tuple)) or len(value) != dims[0]:
            got = len(value) if isinstance(value, (list, tuple)) else 1
            raise Mismatch(f"{where} is declared with {dims[0]} elements, given {got}")
        for k, v in enumerate(value):
            at = f"{where}{{{k + 1}}}"
            if len(dims) > 1:
                self._flatten(v, type_, dims[1:], at, out)
            else:
                out.append(self.coerce(v, type_, at))


def shape(fields) -> str:
    return "[" + ", ".join(name for name, _ in fields) + "]"


def describe(value) -> str:
    """A value's kind in words, for messages."""
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, (int, float)):
        return f"the number {value:g}"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, Rec):
        return f"a {value.type}"
    if isinstance(value, (list, tuple)):
        return f"an aggregate of {len(value)} parts"
    if isinstance(value, Arr):
        return "an array"
    if isinstance(value, Signal):
        return f"the signal '{value.name}'"
    if isinstance(value, Opaque):
        return f"a {value.type}"
    if value.__class__.__name__ == "Live":  # live.py's; imported there, it would import this module back
        return "an unknown value (what a live read gives)"
    return "no value"


def field_index(types: Types, value, key: str) -> int | None:
    """The index of component ``key`` in record ``value``, or None."""
    fields = types.records.get(value.type) if isinstance(value, Rec) else None
    if fields is None:
        return None
    for k, (name, _) in enumerate(fields):
        if name == key:
            return k
    return None


def whole(x: float) -> bool:
    return isinstance(x, float) and math.isfinite(x) and x == int(x)
