"""Every number a user gives a command, with its bounds, in one table, checked once where it comes
in: at the command line (``argument``) and by the library functions that take it (``checked``).
A value out of its bounds is an ``InputError`` naming the bound and why it is there."""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass

from .errors import InputError


@dataclass(frozen=True)
class Bound:
    """The values a number may take: ``low`` to ``high`` (either end open with ``strict``), whole
    numbers only with ``whole``; ``why`` says what the upper bound protects."""

    low: float
    high: float = math.inf
    whole: bool = False
    strict: bool = False  # low itself is refused
    why: str = ""

    def check(self, name: str, value: float, shown: str | None = None) -> float:
        """``value`` if within the bounds, else an InputError "``name`` must be ..., not ``shown``"."""
        ok = math.isfinite(value) and (value > self.low if self.strict else value >= self.low) and value <= self.high
        if not ok:
            raise InputError(f"{name} {self.rule()}, not {shown if shown is not None else f'{value:g}'}")
        return int(value) if self.whole else value

    def rule(self) -> str:
        """What a value must be, in words."""
        if self.whole:
            text = f"must be at least {self.low:g}"
        elif math.isfinite(self.low):
            text = f"must be a finite number {'>' if self.strict else '>='} {self.low:g}"
        else:
            text = "must be a finite number"
        if math.isfinite(self.high):
            text += f" and at most {self.high:g}" + (f" ({self.why})" if self.why else "")
        return text


ANY = Bound(-math.inf)
POSITIVE = Bound(0.0, strict=True)
NON_NEGATIVE = Bound(0.0)

BOUNDS: dict[str, Bound] = {
    "samples": Bound(1, whole=True),
    "seed": Bound(0, whole=True),
    "envs": Bound(1, whole=True),
    "substeps": Bound(1, whole=True),
    "size": Bound(16, whole=True),
    "collision-samples": Bound(1, whole=True),
    "seconds": POSITIVE,
    "resolution": POSITIVE,
    "padding": NON_NEGATIVE,
    "min-bend-radius": POSITIVE,
    "floor": ANY,
    "density": POSITIVE,
    "frame-rate": POSITIVE,
    "mass": POSITIVE,
    "drive-hz": NON_NEGATIVE,
    "armature": NON_NEGATIVE,
    "effort": POSITIVE,
    "velocity": POSITIVE,
    "max-file-size": POSITIVE,
}


def checked(name: str, value: float) -> float:
    """``value`` if it is within the bounds of option ``name``, else an InputError."""
    return BOUNDS[name].check(f"--{name}", value)


def argument(name: str):
    """An argparse type for option ``name``: the text as a number within its bounds."""
    bound = BOUNDS[name]

    def parse(text: str):
        try:
            value = int(text) if bound.whole else float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"'{text}' is not a {'whole ' if bound.whole else ''}number") from None
        try:
            return bound.check("it", value, str(value) if bound.whole else f"'{text}'")
        except InputError as exc:
            raise argparse.ArgumentTypeError(str(exc).removeprefix("it ")) from None

    parse.__name__ = "whole number" if bound.whole else "number"
    return parse
