"""The placement batch as a job of the one batch engine (``sim.engine``): items are chunks of
candidate bases; a task solves every pose at each base of its chunks (``reach``) and checks the
bases that reach them all for collisions at each pose (``clear``), into a tally that merges exactly
in any order. So the same batch runs here on every core, on CUDA, or as tasks on a Ray cluster,
with the same bits."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...rsxml.cell import CellMesh
from ...sim.engine import Job
from ...sim.tool import Tool
from .clear import Clear, Clearance
from .poses import ProgramPoses
from .reach import Reach, empty, per_chunk, solve_into


@dataclass
class PlaceTally:
    """What the job's bases add up to: their reach, and their collisions."""

    reach: Reach
    clear: Clear

    def merge(self, other: "PlaceTally") -> None:
        self.reach.merge(other.reach)
        self.clear.merge(other.clear)


@dataclass(frozen=True)
class PlaceJob(Job):
    name = "place"
    unit = "base"

    bases: np.ndarray  # (C, 4, 4) the candidate frames in the world
    poses: ProgramPoses
    meshes: tuple[CellMesh, ...]  # checked at every pose, in the world
    tool: Tool | None
    rsxml: str
    per: int = 0  # bases a chunk, fixed on the driver: every task cuts the batch the same way

    def __post_init__(self):
        if not self.per:
            object.__setattr__(self, "per", per_chunk(len(self.poses.world)))

    @property
    def count(self) -> int:
        return -(-len(self.bases) // self.per)

    def task_items(self, cluster) -> int:
        return max(1, cluster.task_samples // (self.per * len(self.poses.world)))

    def size(self, span: range) -> float:
        return float(max(0, min(span.stop * self.per, len(self.bases)) - span.start * self.per))

    def local_spans(self) -> list[range]:
        return [range(k, k + 1) for k in range(self.count)]

    def files(self) -> tuple[str, ...]:
        return tuple(m.path for m in self.meshes)

    def tools_key(self) -> tuple:
        return tuple((m.name, m.path, m.pose.tobytes()) for m in self.meshes) + (self.tool,)

    def tools(self, model, device: str, threads: int | None):
        from ...kinematics.kinematics import Kinematics

        meshes = tuple(CellMesh(m.name, model.local(m.path), m.pose) for m in self.meshes)
        return Kinematics(model.mech, device, threads=threads), Clearance(model.mech, meshes, self.tool, device,
                                                                          self.rsxml)

    def empty(self) -> PlaceTally:
        count = len(self.poses.world)
        return PlaceTally(empty(len(self.bases), count), Clear(np.zeros(len(self.bases), bool),
                                                               np.zeros(count, np.int64)))

    def run(self, tools, acc: PlaceTally, span: range, tick) -> None:
        kin, clearance = tools

        def reached_all(rows: np.ndarray, q: np.ndarray) -> None:
            clearance.check(q, self.poses.bases(self.bases[rows]), rows, acc.clear)

        for k in span:
            rows = range(k * self.per, min((k + 1) * self.per, len(self.bases)))
            solve_into(kin, self.bases, rows, self.poses, acc.reach, reached_all)
            tick(float(len(rows)))
