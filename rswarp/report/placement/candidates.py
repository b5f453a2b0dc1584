"""The bases ``rswarp place`` tries: ``--vary x=MIN:MAX[:N]`` for x, y, z (mm) and yaw (degrees),
as a cell file writes frames. A variable with ``N`` is a grid of N values, ends included, and every
such variable is crossed with the others (all combinations); one without ``N`` is drawn, ``--samples
N`` times, from a scrambled Halton sequence (quasi-random, seeded: the same candidates every run).
A variable not given keeps the robot's current value."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from ...transforms import euler_zyx_matrix

VARIABLES = ("x", "y", "z", "yaw")  # the base frame's x, y, z (mm) and its turn about the world's z (degrees)
MAX_CANDIDATES = 1_000_000
MAX_GRID = 10_000  # values of one variable
_SPEC = re.compile(r"^\s*([A-Za-z_]+)\s*=\s*([^:]+):([^:]+)(?::([^:]+))?\s*$")


@dataclass(frozen=True)
class Vary:
    """One ``--vary``: the variable, its range (mm or degrees) and its count (None: drawn)."""

    name: str
    low: float
    high: float
    count: int | None = None


def parse_vary(specs) -> tuple[Vary, ...]:
    """The ``--vary`` specs, checked: each a known variable once, a range MIN <= MAX of finite
    numbers, N a whole number of at least 1 (a range of one value takes N = 1)."""
    out: list[Vary] = []
    for spec in specs:
        m = _SPEC.match(spec)
        if not m:
            raise InputError(f"--vary {spec}: give NAME=MIN:MAX or NAME=MIN:MAX:N ({', '.join(VARIABLES)}; mm and "
                             "degrees)")
        name = m.group(1).lower()
        if name not in VARIABLES:
            raise InputError(f"--vary {spec}: '{m.group(1)}' is no variable of a base (give {', '.join(VARIABLES)})")
        if name in (v.name for v in out):
            raise InputError(f"--vary {spec}: {name} is varied twice")
        low, high = (_number(spec, t) for t in m.group(2, 3))
        if low > high:
            raise InputError(f"--vary {spec}: the range is empty ({low:g} is above {high:g})")
        count = None if m.group(4) is None else _count(spec, m.group(4))
        if count is not None and count > 1 and low == high:
            raise InputError(f"--vary {spec}: {count} values of a range of one: give N = 1")
        out.append(Vary(name, low, high, count))
    if not out:
        raise InputError("give at least one --vary (x, y, z or yaw): the bases to try")
    return tuple(out)


def _number(spec: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"--vary {spec}: '{text.strip()}' is not a number") from None
    if not math.isfinite(value) or abs(value) > 1e7:
        raise InputError(f"--vary {spec}: {text.strip()} is not a finite value within 10 km or 10^7 degrees")
    return value


def _count(spec: str, text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise InputError(f"--vary {spec}: N = '{text.strip()}' is not a whole number") from None
    if not 1 <= value <= MAX_GRID:
        raise InputError(f"--vary {spec}: N must be 1 to {MAX_GRID}, not {value}")
    return value


def candidates(varies: tuple[Vary, ...], samples: int | None, current: np.ndarray, seed: int = 0) -> np.ndarray:
    """(C, 4) bases as x, y, z (mm) and yaw (degrees): the grid of the variables with N crossed with
    ``samples`` draws of the others; ``current`` (4,) holds the values of those not varied."""
    grid = [v for v in varies if v.count is not None]
    drawn = [v for v in varies if v.count is None]
    if drawn and not samples:
        names = ", ".join(v.name for v in drawn)
        raise InputError(f"--vary {names} gives no N: give --samples N (the candidates drawn) or MIN:MAX:N")
    if samples is not None and not 1 <= samples <= MAX_CANDIDATES:
        raise InputError(f"--samples must be 1 to {MAX_CANDIDATES}, not {samples}")
    total = math.prod(v.count for v in grid) * (samples if drawn else 1)
    if total > MAX_CANDIDATES:
        raise InputError(f"{total} candidates: at most {MAX_CANDIDATES} (fewer values or --samples)")
    axes = [np.linspace(v.low, v.high, v.count) for v in grid]
    points = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, len(grid)) if grid else np.zeros((1, 0))
    draws = _draws(drawn, samples, seed) if drawn else np.zeros((1, 0))
    out = np.repeat(np.asarray(current, float)[None], len(points) * len(draws), axis=0)
    for k, v in enumerate(grid):
        out[:, VARIABLES.index(v.name)] = np.repeat(points[:, k], len(draws))
    for k, v in enumerate(drawn):
        out[:, VARIABLES.index(v.name)] = np.tile(draws[:, k], len(points))
    return out


def _draws(drawn: list[Vary], samples: int, seed: int) -> np.ndarray:
    """``samples`` quasi-random points over the drawn variables' ranges (scrambled Halton, seeded)."""
    from scipy.stats import qmc

    unit = qmc.Halton(d=len(drawn), scramble=True, seed=seed).random(samples)
    low, high = np.array([v.low for v in drawn]), np.array([v.high for v in drawn])
    return low + unit * (high - low)


def base_frames(values: np.ndarray, tilt: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
    """(C, 4, 4) base frames in the world (m) of bases (C, 4) x, y, z (mm), yaw (degrees), the
    robot's current ``tilt`` (rx, ry, degrees) kept: R = Rz(yaw) Ry(ry) Rx(rx), as a cell file."""
    out = np.zeros((len(values), 4, 4))
    rest = euler_zyx_matrix(*np.radians(tilt), 0.0)  # Ry(ry) Rx(rx)
    c, s = np.cos(np.radians(values[:, 3])), np.sin(np.radians(values[:, 3]))
    turn = np.zeros((len(values), 3, 3))
    turn[:, 0, 0], turn[:, 0, 1], turn[:, 1, 0], turn[:, 1, 1], turn[:, 2, 2] = c, -s, s, c, 1.0
    out[:, :3, :3] = turn @ rest
    out[:, :3, 3] = values[:, :3] / 1000.0
    out[:, 3, 3] = 1.0
    return out
