"""A cable run cut into tasks, put back together exactly as one run would have gathered it: the
per-environment results at their offsets, and the per-frame values of every environment kept in a
file (capped) whose spread is taken frame by frame at the end."""

from __future__ import annotations

import tempfile
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from .results import PER_ENV, SERIES, VALUE, CableResult, Series, spread

MAX_VALUES_BYTES = 16 << 30  # a cut run's per-frame values, kept in a file: 16 GiB at most
FRAME_BLOCK = 1024  # frames read back at a time to take their spread


def values_bytes(envs: int, frames: int, cables: int) -> int:
    """The size of a cut run's file of per-frame values (checked against MAX_VALUES_BYTES first)."""
    return frames * len(SERIES) * envs * np.dtype(VALUE).itemsize * cables


@dataclass(frozen=True)
class CablePiece:
    """What a run of some environments gave: each cable's results over them (from ``start`` on),
    each cable's per-frame values where the piece is not the whole run (else None: its results
    hold the spread already), and the recorded environment's joints."""

    start: int
    results: tuple[CableResult, ...]
    values: tuple[np.ndarray, ...] | None
    recorded_q: np.ndarray


class CableTally:
    """A cable run's pieces put together in place: per-environment arrays at their offsets; the
    per-frame values of a cut run in a file-backed (frames, len(SERIES), envs) array per cable,
    whose spread is taken frame by frame at the end; the recorded environment from its piece. A
    task's own piece is kept as it is until merged."""

    def __init__(self, envs: int, frames: int, cables: int):
        self.envs, self.frames, self.cables = envs, frames, cables
        self.pieces: list[CablePiece] = []  # added here, not yet placed
        self.whole: CablePiece | None = None
        self.fields: list[dict[str, np.ndarray]] = []
        self.values: list[np.ndarray] = []
        self.recorded: list[CableResult | None] = [None] * cables
        self.recorded_q = np.zeros((0,))
        self.first: CablePiece | None = None
        self._folder: tempfile.TemporaryDirectory | None = None

    def add(self, piece: CablePiece) -> None:
        self.pieces.append(piece)

    def merge(self, other: "CableTally") -> None:
        for piece in other.pieces:
            self._place(piece)

    def _place(self, piece: CablePiece) -> None:
        if piece.values is None:  # the whole run in one piece
            self.whole = piece
            return
        if not self.fields:
            self._allocate(piece)
        for c, (r, v) in enumerate(zip(piece.results, piece.values)):
            for k in PER_ENV:
                self.fields[c][k][piece.start:piece.start + r.envs] = getattr(r, k)
            self.values[c][:, :, piece.start:piece.start + r.envs] = v
            if len(r.recorded):
                self.recorded[c], self.recorded_q = r, piece.recorded_q
        self.first = piece

    def _allocate(self, piece: CablePiece) -> None:
        self._folder = tempfile.TemporaryDirectory(prefix="rswarp-cables-")
        self.fields = [{k: np.empty((self.envs, *getattr(r, k).shape[1:]), getattr(r, k).dtype) for k in PER_ENV}
                       for r in piece.results]
        self.values = [np.lib.format.open_memmap(Path(self._folder.name) / f"values{c}.npy", "w+", VALUE,
                                                 (self.frames, len(SERIES), self.envs)) for c in range(self.cables)]

    def results(self) -> tuple[tuple[CableResult, ...], np.ndarray]:
        """Every cable's results over all environments, and the recorded environment's joints."""
        for piece in self.pieces:
            self._place(piece)
        self.pieces = []
        if self.whole is not None:
            return self.whole.results, self.whole.recorded_q
        try:
            out = []
            for c, first in enumerate(self.first.results):
                rec = self.recorded[c] or first
                out.append(replace(first, **self.fields[c], **_series(self.values[c]), recorded=rec.recorded,
                                   stride=rec.stride))
            return tuple(out), self.recorded_q
        finally:
            self.values = []
            if self._folder is not None:
                self._folder.cleanup()


def _series(values: np.ndarray) -> dict[str, Series]:
    """The spread of each quantity per frame over all environments, as one run takes it."""
    rows: dict[str, list] = {key: [] for key in SERIES}
    for lo in range(0, len(values), FRAME_BLOCK):
        block = np.asarray(values[lo:lo + FRAME_BLOCK], np.float64)
        for frame in block:
            for key, v in zip(SERIES, frame):
                rows[key].append(spread(v))
    return {key: Series.of(rows[key]) for key in SERIES}
