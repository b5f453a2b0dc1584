"""Collisions at each pose of the bases that reach every pose: the robot in the configuration the
reach batch chose, against itself (every pair but those touching at home, as ``rswarp program``
checks) and against the cell's environment meshes where that base puts the robot among them, in
one exact batch each (``sim.collisions.Checker``, ``sim.cell_check.CellChecker``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...kinematics.cell import CellKinematics
from ...rsxml.cell import Cell, CellMesh, PlacedRobot
from ...sim.cell_check import CellChecker, cell_pairs
from ...sim.program_check import checked_pairs, program_tools
from ...sim.tool import tool_body

FAR_AWAY = 1e6  # m: where the home check puts the robot, so that no mesh of the cell counts as its build


@dataclass
class Clear:
    """Per base (C,): whether nothing collides at any of its poses (False where it was not
    checked: it misses a pose); per pose (P,): the bases it collides at; per pose and pair (P,
    pairs): how often that pair collides there (``names`` the pairs)."""

    free: np.ndarray
    hits: np.ndarray
    counts: np.ndarray | None = None
    names: list | None = None

    @property
    def pair(self) -> list:
        """Per pose the pair that collides most often there (``Link3``, ``column``), or None."""
        if self.counts is None:
            return [None] * len(self.hits)
        return [tuple(self.names[int(np.argmax(c))][:2]) if c.any() else None for c in self.counts]

    def merge(self, other: "Clear") -> None:
        """Another chunk's bases (the bases each checks are its own)."""
        self.free |= other.free
        self.hits += other.hits
        if other.counts is not None:
            self.counts = other.counts.copy() if self.counts is None else self.counts + other.counts
            self.names = other.names


class Clearance:
    """The checkers of one robot (with its ``tool``) and the cell's meshes (``meshes``: ``CellMesh``
    in the world), compiled once for every chunk of bases."""

    def __init__(self, mech, meshes: tuple[CellMesh, ...], tool, device: str, rsxml: str):
        self.mech, self.device = mech, device
        self.tools = program_tools(mech, (), device, tool=tool)
        self.self_pairs = checked_pairs(mech, self.tools)
        self.env = None
        if meshes:
            ck = CellKinematics(Cell(rsxml, PlacedRobot(rsxml, mech), (), None, tuple(meshes)), device)
            found = cell_pairs(ck, tool_body(mech, tool) if tool is not None else None)
            far = np.eye(4)
            far[:3, 3] = FAR_AWAY
            self._frames = far[None]  # the rows' bases, set by each check; the home check's is far away
            self._found = found
            self.env = found, CellChecker(ck, found, device, poses=self._poses,
                                          home=(mech.home_position(), np.zeros(1)))

    def check(self, q: np.ndarray, bases: np.ndarray, rows: np.ndarray, out: Clear) -> None:
        """The bases ``rows`` checked into ``out``: their chosen configurations ``q`` (n, P, 6) and
        the robot's base at each pose (n, P, 4, 4)."""
        n, count = q.shape[:2]
        flat = q.reshape(n * count, -1)
        names: list[tuple[str, str]] = []
        pairs = np.zeros((n * count, 0), bool)
        if self.tools.checker is not None:
            pairs, names = self.tools.checker.verdicts(flat)[0] & self.self_pairs, \
                list(self.tools.checker.bodies.pair_names())
        if self.env is not None:
            more = self._environment(flat, np.ascontiguousarray(bases).reshape(-1, 4, 4))
            pairs = np.concatenate([pairs, more], axis=1)
            names += self.env[0].pair_names()
        per_pose = pairs.any(axis=1).reshape(n, count)
        out.free[rows] = ~per_pose.any(axis=1)
        out.hits += per_pose.sum(axis=0)
        counts = pairs.reshape(n, count, -1).sum(axis=0)
        out.counts = counts if out.counts is None else out.counts + counts
        out.names = names

    def _poses(self, q: np.ndarray, rest: np.ndarray) -> np.ndarray:
        """Every body's pose (N, bodies, 4, 4): the robot's links on the row's base (``rest[:, 0]``
        its index in ``_frames``), the meshes where they stand."""
        found = self._found
        links = self._frames[rest[:, 0].astype(np.int64)][:, None] @ self.tools.kinematics.fk64(q)
        return np.stack([links[:, w[0]] if who == "robot" else
                         np.broadcast_to(found.bodies.bodies[b].pose, (len(q), 4, 4))
                         for b, (who, *w) in enumerate(found.owner)], axis=1)

    def _environment(self, q: np.ndarray, bases: np.ndarray) -> np.ndarray:
        """(N, pairs) robot links against the meshes, the robot at ``bases`` (N, 4, 4)."""
        found, checker = self.env
        self._frames = bases
        return checker.hits(q, np.arange(len(q), dtype=float)[:, None]) & checker.checked
