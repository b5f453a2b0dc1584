"""Length and angle units of RSXML files, and number formatting that survives a round trip."""

from __future__ import annotations

import math
from decimal import Decimal

# Factor that turns a value in the unit into SI (metres, radians).
LENGTH_UNITS = {"m": 1.0, "dm": 0.1, "cm": 0.01, "mm": 0.001, "um": 1e-6, "in": 0.0254, "ft": 0.3048}
ANGLE_UNITS = {"rad": 1.0, "deg": math.pi / 180.0}
DEFAULT_LENGTH_UNIT = "m"
DEFAULT_ANGLE_UNIT = "rad"

# Physical sense, and what float32 kernels can hold: a robot (or cell) fits in a 1 km box, and a
# joint turns at most about 16,000 revolutions (ABB's "endless" axis 6 option), in SI units.
MAX_LENGTH = 1000.0  # m
MAX_ANGLE = 1e5  # rad
JOINT_VELOCITY = {True: math.radians(90.0), False: 0.5}  # a joint's default speed limit: 90 deg/s, 0.5 m/s

BOUNDS = {  # kind of value -> (largest magnitude in SI, what it means, for messages)
    "length": (MAX_LENGTH, "1 km, the most a model may span"),
    "angle": (MAX_ANGLE, f"{MAX_ANGLE:g} rad (about {MAX_ANGLE / (2 * math.pi):,.0f} turns), the most a joint may "
                         "turn"),
}


def format_number(si: float, factor: float = 1.0) -> str:
    """The shortest decimal text that reads back (``float(text) * factor``) to exactly ``si``.

    Saving a model converts SI values back to file units; this keeps ``544`` as ``544`` and not
    ``544.0000000000001``, while load -> save -> load stays bit-identical.
    """
    value = si / factor
    for digits in range(1, 18):
        text = f"{value:.{digits}g}"
        if float(text) * factor == si:
            break
    else:  # cannot happen for finite values; keep the closest text
        text = repr(value)
    if "e" in text:
        mantissa, exp = text.split("e")
        if -7 < int(exp) < 16:  # 1.8e+02 -> 180: positional whenever that stays short
            text = format(Decimal(text), "f")
            if "." in text:
                text = text.rstrip("0").rstrip(".")
        else:
            text = f"{mantissa}e{int(exp)}"
    return "0" if text == "-0" else text


def length_text(si: float, factor: float = 1.0, unit: str = "m") -> str:
    """A measured length (m) for a label, in the unit of ``factor`` to 0.1 mm: ``1.6533 m``,
    ``1653.3 mm``, ``65.091 in`` (every digit kept, so a label never rounds a figure away)."""
    digits = max(0, math.ceil(math.log10(factor / 1e-4) - 1e-9))
    text = f"{si / factor:.{digits}f}"
    return f"{text.lstrip('-') if float(text) == 0 else text} {unit}"  # never "-0.0 mm"
