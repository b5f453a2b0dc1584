"""How a cable's numbers discretize it, by the format's rules: a span between each two control
points, each as long as its share (by chord) of ``desiredLength``, cut into equal segments no
longer than ``maxSegmentLength`` (and at least ``MIN_SPAN_SEGMENTS``, so a span can bend).
Validation reads it to report, at the cable's line, what a run would refuse; the rest shape
(``rswarp.geometry.cable``) builds on it."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .model import Cable

LENGTH_TOLERANCE = 1e-9  # relative: a desired length this close to the polyline's is taut
MAX_CABLE_SEGMENTS = 4000  # segments of one cable: what a cable kernel holds, with room for its clamps
MIN_SPAN_SEGMENTS = 4  # segments between two control points at least: a span of one segment cannot bend
# between two clamps, which then fight it (kilonewtons on a hose of a few newtons)


@dataclass(frozen=True)
class CableSpans:
    """The control points (SI), each span's chord and length, and its segments."""

    points: np.ndarray  # (spans + 1, 3)
    chords: np.ndarray  # (spans,)
    lengths: np.ndarray  # (spans,) along the cable
    segments: np.ndarray  # (spans,) int

    @property
    def polyline(self) -> float:
        return float(self.chords.sum())


def cable_spans(cable: Cable, length_factor: float = 1.0) -> CableSpans:
    """The spans of ``cable``; ``ValueError`` saying why a run could not take it (fewer than two
    control points, two at one place, a desired length shorter than the path through them, more
    than ``MAX_CABLE_SEGMENTS`` segments). ``length_factor`` shows lengths in the file's unit."""
    pts = np.array([cp.position for cp in cable.control_points], float).reshape(-1, 3)
    if len(pts) < 2:
        raise ValueError(f"cable '{cable.name}' needs two control points or more")
    chords = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    if (chords <= 0).any():
        raise ValueError(f"cable '{cable.name}' has two control points at one place")
    polyline = float(chords.sum())
    length = polyline if cable.desired_length is None else float(cable.desired_length)
    if length < polyline * (1 - LENGTH_TOLERANCE):
        f = length_factor
        raise ValueError(f"cable '{cable.name}': desiredLength {length / f:g} is shorter than the path through its "
                         f"control points ({polyline / f:.6g})")
    lengths = chords + chords / polyline * (length - polyline)
    with np.errstate(over="ignore"):  # float, even inf: an absurd count is said, not built
        wanted = np.ceil(lengths / cable.max_segment_length - 1e-9)
    if wanted.sum() > MAX_CABLE_SEGMENTS:
        raise ValueError(f"cable '{cable.name}' would be {wanted.sum():.3g} segments of at most "
                         f"{cable.max_segment_length / length_factor:g} (maxSegmentLength); a cable takes at most "
                         f"{MAX_CABLE_SEGMENTS}: raise maxSegmentLength")
    return CableSpans(pts, chords, lengths, np.maximum(MIN_SPAN_SEGMENTS, wanted).astype(int))
