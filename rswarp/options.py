"""Every number a user gives rswarp, with its bounds, in one table, checked once where it comes in:
at the command line (``argument``) and by the library functions that take it (``checked``), before
any work. A value out of its bounds is an ``InputError`` that names the bound and why it is there.

Lengths are typed in the file's length unit at the command line and checked in metres by the
library, within ``MAX_LENGTH`` (the bound of every length the reader takes)."""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass

from .errors import InputError
from .rsxml.units import MAX_LENGTH


@dataclass(frozen=True)
class Bound:
    """The values a number may take: ``low`` to ``high`` (``low`` itself refused with ``strict``),
    whole numbers only with ``whole``; ``why`` says what the upper bound protects, ``unit`` its
    unit. A ``length`` is checked against its magnitude in metres by the library."""

    low: float
    high: float = math.inf
    whole: bool = False
    strict: bool = False
    why: str = ""
    unit: str = ""
    length: bool = False

    def check(self, name: str, value: float, shown: str | None = None) -> float:
        """``value`` if within the bounds, else an InputError "``name`` must be ..., not ``shown``"
        saying the bound it passed."""
        too_big = math.isfinite(value) and value > self.high
        ok = math.isfinite(value) and (value > self.low if self.strict else value >= self.low) and not too_big
        if not ok:
            rule = self.upper() if too_big else self.lower()
            raise InputError(f"{name} {rule}, not {shown if shown is not None else f'{value:g}'}")
        return int(value) if self.whole else value

    def lower(self) -> str:
        """What a value must be at the low end, in words."""
        if self.whole:
            return f"must be at least {self.low:g}"
        if math.isfinite(self.low):
            return f"must be a finite number {'>' if self.strict else '>='} {self.low:g}"
        return "must be a finite number"

    def upper(self) -> str:
        """The upper bound and why it is there, in words."""
        unit = f" {self.unit}" if self.unit else ""
        return f"must be at most {self.high:g}{unit}" + (f" ({self.why})" if self.why else "")

    def rule(self) -> str:
        """Both ends, in words."""
        return self.lower() + (" and " + self.upper().removeprefix("must be ") if math.isfinite(self.high) else "")


def _length(low: float, strict: bool = False) -> Bound:
    return Bound(low, strict=strict, length=True)


BOUNDS: dict[str, Bound] = {
    "samples": Bound(1, 1e11, whole=True, why="62 hours of collision sweeps on this 2-core machine; split bigger "
                                              "jobs"),
    "collision-samples": Bound(1, 1e9, whole=True, why="an export's own sweep; run bigger ones with 'rswarp "
                                                       "collisions'"),
    "seed": Bound(0, 2 ** 63 - 1, whole=True, why="a 64-bit seed"),
    "envs": Bound(1, 1 << 16, whole=True, why="a run's state and per-frame results stay bounded"),
    "designs": Bound(1, 1 << 16, whole=True, why="each design is an environment of one run"),
    "top": Bound(1, 64, whole=True, why="each is a whole run of the program"),
    "min-margin": Bound(0.0, 100.0, why="a percentage of each rating"),
    "substeps": Bound(1, 1000, whole=True, why="17 microsecond steps at 60 frames/s"),
    "seconds": Bound(0.0, 86400.0, strict=True, unit="s", why="a day; a run also takes at most 1000000 frames"),
    "frame-rate": Bound(0.0, 1000.0, strict=True, unit="frames/s", why="a result every millisecond"),
    "size": Bound(16, 4096, whole=True, unit="pixels", why="a 4096 x 4096 preview is 64 MiB"),
    "resolution": _length(0.0, strict=True),
    "padding": _length(0.0),
    "min-bend-radius": _length(0.0, strict=True),
    "floor": _length(-math.inf),
    "density": Bound(0.0, 1e5, strict=True, unit="kg/m^3", why="denser than any material: osmium is 22 590"),
    "poisson": Bound(0.0, 0.5, why="an isotropic material's Poisson ratio: 0.5 is incompressible"),
    "friction": Bound(0.0, 10.0, why="a hose on metal is 0.3 to 0.8; past 10 it is glue, not friction"),
    "max-strain": Bound(0.0, 1.0, strict=True, why="a hose stretched to twice its length has torn"),
    "static-bend-radius": _length(0.0, strict=True),
    "max-torsion": Bound(0.0, 36000.0, strict=True, unit="deg/m", why="a hundred turns a metre is a spring"),
    "max-contact-force": Bound(0.0, 1e7, strict=True, unit="N", why="more than any robot can push"),
    "max-clamp-load": Bound(0.0, 1e7, strict=True, unit="N", why="more than any robot can pull"),
    "mass": Bound(0.0, 1e6, strict=True, unit="kg", why="the heaviest robots weigh a few tonnes"),
    "drive-hz": Bound(0.0, 1000.0, unit="Hz", why="a drive faster than the 1 ms steps that simulate it is none"),
    "armature": Bound(0.0, 1e6, unit="kg m^2"),
    "effort": Bound(0.0, 1e7, strict=True, unit="N m"),
    "velocity": Bound(0.0, 1000.0, strict=True, unit="rad/s"),
    "cycles": Bound(1, 1000, whole=True, why="passes of a main loop; a cycle's time needs one"),
    "max-file-size": Bound(0.0, 1 << 20, strict=True, unit="MiB", why="1 TiB"),
}


def checked(name: str, value: float | None, si: bool = True) -> float | None:
    """``value`` if it is within the bounds of option ``name`` (a length in metres where ``si``),
    else an InputError; None stays None."""
    if value is None:
        return None
    bound = BOUNDS[name]
    out = bound.check(f"--{name}", value)
    if bound.length and si and abs(value) > MAX_LENGTH:
        raise InputError(f"--{name} must be within {MAX_LENGTH:g} m (the bound of every length rswarp reads), not "
                         f"{value:g} m")
    return out


def argument(name: str):
    """An argparse type for option ``name``: the text as a number within its bounds."""
    bound = BOUNDS[name]

    def parse(text: str):
        try:
            value = float(text)
            if bound.whole:  # 1e6 is a whole number too
                value = int(text) if text.strip().lstrip("+-").isdigit() else int(value) if value.is_integer() \
                    else float("nan")
        except (ValueError, OverflowError):
            raise argparse.ArgumentTypeError(f"'{text}' is not a {'whole ' if bound.whole else ''}number") from None
        if bound.whole and value != value:
            raise argparse.ArgumentTypeError(f"'{text}' is not a whole number")
        try:
            return bound.check("it", value, str(value) if bound.whole else f"'{text}'")
        except InputError as exc:
            raise argparse.ArgumentTypeError(str(exc).removeprefix("it ")) from None

    parse.__name__ = "whole number" if bound.whole else "number"
    return parse


def bounds_table() -> str:
    """The table as Markdown rows (the README's), option by option."""
    return "\n".join(f"| `--{name}` | {b.rule().removeprefix('must be ')} |" for name, b in BOUNDS.items())
