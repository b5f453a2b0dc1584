"""A cable's rest shape and its discretization: a curve through the control points with the
cable's desired length; each span between two control points cut into equal segments no longer
than ``maxSegmentLength``, so every control point is a point of the discretization.

Where the desired length exceeds the polyline through the control points, each span between two
points sags: it bows by a half sine wave across its chord, downwards where it can (a hose hangs),
by as much as gives the span its share of the extra length (shares by chord length). The
simulation then lets it settle; this shape only has to be a plausible, exact-length start.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import model_error
from ..rsxml.cable_spans import LENGTH_TOLERANCE, cable_spans
from ..rsxml.model import Cable, Mechanism

SAMPLES = 256  # points per span to measure a bowed span's length


@dataclass(frozen=True)
class CableRest:
    """A discretized cable at the zero position (SI): ``points`` (n + 1, 3); ``rest`` (n,) each
    segment's length along the curve (they add up to ``length``, the desired length; the chords
    between the points are a hair shorter on a bowed span); ``anchors`` the point index of each
    control point."""

    name: str
    points: np.ndarray
    rest: np.ndarray
    anchors: tuple[int, ...]
    length: float

    @property
    def segments(self) -> int:
        return len(self.points) - 1


def cable_rest(mech: Mechanism, cable: Cable) -> CableRest:
    """The rest shape of ``cable``; ``RsxmlError`` at the cable's line where its numbers do not make
    a cable (``rswarp.rsxml.cable_spans``)."""
    try:
        spans = cable_spans(cable, mech.length_factor)
    except ValueError as exc:
        raise model_error(mech, str(exc), cable.line) from None
    pts = spans.points
    bowed = [_bowed(a, b, want) for a, b, want in zip(pts[:-1], pts[1:], spans.lengths)]
    return _cut(cable.name, bowed, spans.lengths, spans.segments)


def _bowed(a: np.ndarray, b: np.ndarray, length: float) -> np.ndarray:
    """``SAMPLES + 1`` points from a to b along a half sine bow of arc length ``length``."""
    chord = b - a
    side = _sag_direction(chord)
    if length <= np.linalg.norm(chord) * (1 + LENGTH_TOLERANCE):
        return a + np.linspace(0.0, 1.0, SAMPLES + 1)[:, None] * chord  # taut: the chord itself
    s = np.linspace(0.0, 1.0, SAMPLES + 1)[:, None]
    line, bow = a + s * chord, np.sin(np.pi * s)
    arc = _Arc(line, bow, side)
    lo, hi = 0.0, length  # a bow as deep as the length is always long enough
    for _ in range(100):  # bisection on the depth: arc length grows with it
        h = 0.5 * (lo + hi)
        if h in (lo, hi):  # the interval is one rounding wide: no later step would change it
            break
        if arc(h) < length:
            lo = h
        else:
            hi = h
    return line + 0.5 * (lo + hi) * bow * side


class _Arc:
    """The arc length of the bow ``line + h bow side`` at depth h (the sum of its sampled chords, as
    ``np.linalg.norm`` rounds each), into arrays made once: a design sweep bisects every design's
    spans, some fifty steps each, and fresh arrays and ``norm``'s checks cost more than the
    arithmetic."""

    def __init__(self, line: np.ndarray, bow: np.ndarray, side: np.ndarray):
        self.line, self.bow, self.side = line, bow, side
        self.depth, self.curve = np.empty_like(bow), np.empty_like(line)
        self.step, self.norm = np.empty((len(line) - 1, 3)), np.empty(len(line) - 1)

    def __call__(self, h: float) -> float:
        np.multiply(h, self.bow, out=self.depth)
        np.multiply(self.depth, self.side, out=self.curve)
        np.add(self.line, self.curve, out=self.curve)
        np.subtract(self.curve[1:], self.curve[:-1], out=self.step)
        np.multiply(self.step, self.step, out=self.step)
        np.add.reduce(self.step, axis=1, out=self.norm)
        return float(np.sqrt(self.norm, out=self.norm).sum())


def _sag_direction(chord: np.ndarray) -> np.ndarray:
    """Down (-z) across the chord, or sideways (+x, then +y) where the chord is vertical."""
    unit = chord / np.linalg.norm(chord)
    for d in ((0.0, 0.0, -1.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)):
        side = np.array(d) - np.dot(d, unit) * unit
        if np.linalg.norm(side) > 1e-3:
            return side / np.linalg.norm(side)
    raise AssertionError("no direction across a chord")  # unreachable: three axes span space


def _cut(name: str, spans: list[np.ndarray], lengths: np.ndarray, segments: np.ndarray) -> CableRest:
    """Each span (sampled points, its exact length) in its equal segments; the control points are
    kept as points of the discretization."""
    out, rest, anchors = [spans[0][:1]], [], [0]
    for pts, span_length, n in zip(spans, lengths, segments):
        n = int(n)
        along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
        at = np.linspace(0.0, along[-1], n + 1)[1:]
        out.append(np.stack([np.interp(at, along, pts[:, c]) for c in range(3)], axis=1))
        rest += [span_length / n] * n
        anchors.append(anchors[-1] + n)
    return CableRest(name, np.concatenate(out), np.array(rest), tuple(anchors), float(lengths.sum()))
