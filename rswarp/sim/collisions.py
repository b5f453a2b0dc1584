"""Self-collision sweeps over the joint limits, and the collision matrix MoveIt Setup Assistant
computes (``compute_default_collisions.cpp``), step by step:

1. links without geometry are contracted away; pairs joined by a joint are **Adjacent**;
2. pairs colliding at the default state are **Default** (MoveIt uses 0 or mid-range; rswarp uses the
   RSXML ``HomePosition``, the robot's own default);
3. rounds of 200 random states: a pair colliding in at least 191 of a round is **Always**; rounds
   repeat until one disables nothing;
4. the sweep: a pair never seen colliding in any sample (nor in those rounds) is **Never**.

Verdicts are exact (``rswarp.kernels.collide``). Samples are drawn chunk by chunk from the seed and
the chunk's index, so a sweep gives the same numbers on one core or many, and memory is one chunk.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import Callable

import numpy as np

from ..errors import InputError, model_error
from ..kernels.types import WITNESSES
from ..kinematics import quick
from ..kinematics.chain import loops_close, mechanism_chain
from ..kinematics.kinematics import Kinematics
from ..launch import Launcher, init_warp
from ..options import checked
from ..rsxml.model import Mechanism
from .bodies import CollisionBodies, DeviceBodies, Environment, collision_bodies
from .certified_cells import CERTIFIED_PAY, certified_grid
from .engine import Job, run_batch
from .tool import tool_body
from .witness import usual_crossings, witness_grid
from .workspace import sample_chunks

ROUND = 200  # MoveIt's SMALL_TRIAL_COUNT
ALWAYS_FRACTION = 0.95  # MoveIt's min_collision_fraction: more than int(200 * 0.95) = 190 of a round
EXAMPLES = 3  # colliding configurations kept per pair
CANDIDATES = 32  # nearest samples (by bounding volumes) whose exact clearance is measured per free pair
CHUNK = 1 << 16
NONE = np.iinfo(np.int64).max  # the sample index of an unfilled slot
REASONS = ("Adjacent", "Default", "Always", "Never")


@dataclass(frozen=True)
class PairResult:
    """What the sweep found for one pair (SI units)."""

    body1: str
    body2: str
    environment: bool  # body2 is an environment mesh
    collisions: int  # samples of the sweep in which the pair collides
    examples: tuple[tuple[float, ...], ...]  # a few colliding configurations, first found first
    clearance: float | None  # pairs that never collide: the smallest exact clearance found
    clearance_q: tuple[float, ...] | None  # where it was found
    clearance_floor: float | None  # every sample is at least this far apart (bounding volumes)
    reason: str | None  # why the matrix disables the pair (REASONS), None: checked
    tool: bool = False  # one body is the tool on the flange (not a link of the robot's SRDF)


@dataclass(frozen=True)
class Collisions:
    """A sweep's results and its collision matrix."""

    mechanism: str
    samples: int
    seed: int
    padding: float
    links: tuple[str, ...]  # links with geometry, the matrix's rows
    pairs: tuple[PairResult, ...]  # every pair tested (non-adjacent links, environment x links)
    adjacent: tuple[tuple[str, str], ...]
    default_q: tuple[float, ...]
    always_rounds: int
    free_samples: int  # samples where no pair the matrix keeps checking collides
    warnings: tuple[str, ...]
    unreachable: int = 0  # samples skipped (not in ``samples``): a loop cannot close there

    @property
    def free_fraction(self) -> float:
        return self.free_samples / max(self.samples, 1)

    def disabled(self) -> list[tuple[str, str, str]]:
        """(link1, link2, reason) of every disabled pair of links, adjacent first, in link order."""
        out = [(a, b, "Adjacent") for a, b in self.adjacent]
        out += [(p.body1, p.body2, p.reason) for p in self.pairs if p.reason and not p.environment and not p.tool]
        return out

    def reason_counts(self) -> dict[str, int]:
        """How many pairs of links the matrix disables, per reason (in REASONS' order)."""
        disabled = [r for *_, r in self.disabled()]
        return {r: disabled.count(r) for r in REASONS}

    def report(self) -> dict:
        """A JSON-ready summary (metres, radians, snake_case)."""
        return {
            "mechanism": self.mechanism, "samples": self.samples, "seed": self.seed, "padding": self.padding,
            "links": list(self.links), "default_q": list(self.default_q), "always_rounds": self.always_rounds,
            "collision_free_fraction": self.free_fraction, "unreachable_samples": self.unreachable,
            "pairs": [{"body1": p.body1, "body2": p.body2, "environment": p.environment,
                       "collisions": p.collisions, "rate": p.collisions / max(self.samples, 1),
                       "examples": [list(q) for q in p.examples], "clearance": p.clearance,
                       "clearance_q": None if p.clearance_q is None else list(p.clearance_q),
                       "clearance_floor": p.clearance_floor, "disabled": p.reason} for p in self.pairs],
            "disabled": [{"link1": a, "link2": b, "reason": r} for a, b, r in self.disabled()],
            "warnings": list(self.warnings),
        }


class Checker:
    """The compiled collision kernels of one mechanism's bodies on a device: ``verdicts(q)`` for
    batches, ``distances(q, pairs)`` for exact clearances (float64). ``witnesses``: build the
    witness grids (``rswarp.sim.witness``) that spare walks, and with ``certified_cells`` the
    certified grids (``rswarp.sim.certified_cells``), which pay for their setup only in large sweeps
    (``CERTIFIED_PAY``); verdicts and gaps are the same without."""

    def __init__(self, mech: Mechanism, bodies: CollisionBodies, padding: float = 0.0, device: str = "cpu",
                 threads: int | None = None, witnesses: bool = True, certified_cells: bool = False):
        wp = init_warp()
        from ..kernels.collide import collision_kernels

        self.bodies = bodies
        self.dof = len(mech.graph.active)  # the columns of a configuration
        self.chain = chain = mechanism_chain(mech)
        # the per-configuration flag of closed loops: on the host, or the device for Newton-solved ones
        self.loops_close = Kinematics(mech, device).loops_close if len(chain.newton_rows) else \
            partial(loops_close, chain)
        # each launch carries the whole struct from Python: few, large chunks
        self.launcher = Launcher(device, chunk=8192, threads=threads)
        self._device = DeviceBodies(bodies, padding, self.launcher.device)
        self._collide, _, self._witness, self._first, self._apart, _ = collision_kernels(
            chain, bodies.links, len(bodies.bodies), wp.float32)
        _, self._distance, _, _, _, self._cross = collision_kernels(chain, bodies.links, len(bodies.bodies),
                                                                    wp.float64)
        self.launcher.load(self._collide)
        self._quick: dict = {}  # per count of states: ``verdicts``' recorded launch (``_quick_launch``)
        self.witnesses = self.certified = None
        lower, upper = mech.bounds()
        if witnesses:
            self.witnesses = witness_grid(self._sample, chain, bodies, lower, upper)
            self._device.set_witnesses(self.witnesses, wp.float32)
        if witnesses and certified_cells:
            self.certified = certified_grid(self._apart_at, self._crossing_at, chain, bodies, self.witnesses,
                                            lower, upper, padding)
            self._device.set_certified(self.certified, wp.float32)
            self.witnesses = usual_crossings(self.witnesses, self._hits, self._first_at, lower, upper)
            self._device.set_witnesses(self.witnesses, wp.float32)

    @property
    def pair_count(self) -> int:
        return len(self.bodies.pairs)

    def _sample(self, q: np.ndarray, pairs: np.ndarray) -> np.ndarray:
        """Crossing triangle pairs of pair ``pairs[i]`` at ``q[i]``, spread over all that cross."""
        out = np.empty((len(q), 2 * WITNESSES), np.int32)
        self.launcher.launch(self._witness, len(q), params=[self._device.struct(init_warp().float32)],
                             inputs=[np.ascontiguousarray(q, np.float32), np.ascontiguousarray(pairs, np.int32)],
                             outputs=[out])
        return out

    def _hits(self, q: np.ndarray) -> np.ndarray:
        """The sweep's (N, pairs) verdicts at ``q`` (every row finite)."""
        hit = np.empty((len(q), self.pair_count), np.uint8)
        self.launcher.launch(self._collide, len(q), params=[self._device.struct(init_warp().float32)],
                             inputs=[np.ascontiguousarray(q, np.float32)],
                             outputs=[hit, np.empty((len(q), self.pair_count), np.float32)])
        return hit.astype(bool)

    def _first_at(self, q: np.ndarray, pairs: np.ndarray) -> np.ndarray:
        """(N, 2) triangles at which the walk of pair ``pairs[i]`` at ``q[i]`` first finds a crossing."""
        out = np.empty((len(q), 2), np.int32)
        self.launcher.launch(self._first, len(q), params=[self._device.struct(init_warp().float32)],
                             inputs=[np.ascontiguousarray(q, np.float32), np.ascontiguousarray(pairs, np.int32)],
                             outputs=[out])
        return out

    def _apart_at(self, q: np.ndarray, pairs: np.ndarray, limit: np.ndarray, contain: bool) -> np.ndarray:
        """1 where the surfaces of pair ``pairs[i]`` at ``q[i]`` are further apart than ``limit[i]``
        (and with ``contain``, neither body contains the other), in the sweep's precision."""
        out = np.empty(len(q), np.uint8)
        self.launcher.launch(self._apart, len(q), params=[self._device.struct(init_warp().float32), int(contain)],
                             inputs=[np.ascontiguousarray(q, np.float32), np.ascontiguousarray(pairs, np.int32),
                                     np.ascontiguousarray(limit, np.float32)], outputs=[out])
        return out

    def _crossing_at(self, q: np.ndarray, pairs: np.ndarray, tris: np.ndarray, move: np.ndarray,
                     a_moves: np.ndarray) -> np.ndarray:
        """1 where one of the triangle pairs ``tris[i]`` of pair ``pairs[i]`` at ``q[i]`` crosses so
        that it still does when the moving body's points move by ``move[i]`` (float64)."""
        out = np.empty(len(q), np.uint8)
        c = np.ascontiguousarray
        self.launcher.launch(self._cross, len(q), params=[self._device.struct(init_warp().float64)],
                             inputs=[c(q, np.float64), c(pairs, np.int32), c(tris, np.int32), c(move, np.float64),
                                     c(a_moves, np.int32)], outputs=[out])
        return out

    def verdicts(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(hit, gap)``: (N, pairs) booleans, and float32 lower bounds of free pairs' distances.
        A row holding a NaN or an infinity has no pose: every pair is reported colliding there (a
        verdict never clears what it could not check), its gaps NaN."""
        n = quick.count(q, (self.dof,), quick.F32, quick.F64)
        rec = (self._quick[n] if n in self._quick else self._quick_launch(n)) if n else None
        if rec is not None:  # one to a few states (a planner's, a script's): the recorded launch called directly
            with self.launcher.small_lock:
                hit, gap = rec.once((q,))
            return hit.astype(bool), gap
        q = np.ascontiguousarray(np.atleast_2d(q), np.float32)
        if q.ndim != 2 or q.shape[1] != self.dof:
            raise ValueError(f"q must have shape (N, {self.dof}), got {q.shape}")
        hit = np.empty((len(q), self.pair_count), np.uint8)
        gap = np.empty((len(q), self.pair_count), np.float32)
        self.launcher.launch(self._collide, len(q), params=[self._device.struct(init_warp().float32)], inputs=[q],
                             outputs=[hit, gap])
        return hit.astype(bool), gap

    def _quick_launch(self, n: int):
        """The recorded sweep launch for ``n`` states (``verdicts``), made once; None on a GPU."""
        self._quick[n] = self.launcher.quick(
            self._collide, n, [np.zeros((n, self.dof), np.float32)],
            [np.empty((n, self.pair_count), np.uint8), np.empty((n, self.pair_count), np.float32)],
            params=[self._device.struct(init_warp().float32)])
        return self._quick[n]

    def distances(self, q: np.ndarray, pairs: np.ndarray) -> np.ndarray:
        """Exact distances (float64) of pair ``pairs[i]`` at ``q[i]``; -1 where one body contains the other."""
        if np.ndim(q) != 2 or np.shape(q)[1] != self.dof or len(q) != len(pairs):
            raise ValueError(f"q must have shape (N, {self.dof}) and pairs (N,), got {np.shape(q)}, {np.shape(pairs)}")
        out = np.empty(len(q), np.float64)
        self.launcher.launch(self._distance, len(q), params=[self._device.struct(init_warp().float64)],
                             inputs=[np.ascontiguousarray(q, np.float64), np.ascontiguousarray(pairs, np.int32)],
                             outputs=[out])
        return out


def collisions(mech: Mechanism, samples: int = 100_000, seed: int = 0, padding: float = 0.0,
               environment: tuple[Environment, ...] = (), device: str = "cpu", threads: int | None = None,
               progress: Callable[[float, float], None] | None = None, cluster=None, tool=None) -> Collisions:
    """Sweep ``samples`` random configurations within the joint limits for collisions between the
    links (and with the environment meshes and the ``tool``, a ``sim.tool.Tool`` on the flange),
    and compute the collision matrix; ``cluster`` (a ``rswarp.Cluster`` or a Ray address) runs the
    sweep's samples as tasks on Ray."""
    checked("samples", samples)
    checked("padding", padding)
    lower, upper = _limits(mech)
    bodies = collision_bodies(mech, tuple(environment), tool=tool_body(mech, tool))
    checker = Checker(mech, bodies, padding, device, threads, certified_cells=samples >= CERTIFIED_PAY)
    home = mech.home_position()
    default = checker.verdicts(home[None])[0][0]
    always, rounds, seen = _always(checker, lower, upper, seed, default)
    job = CollisionJob(lower, upper, samples, seed, padding, tuple(environment), ~(default | always), CHUNK, tool)
    tally = run_batch(job, mech, tools=checker, cluster=cluster, progress=progress)
    if not tally.done:
        raise model_error(mech, f"none of the {samples} samples closes the loops of '{mech.name}': every one lies "
                                "past a dead point")
    clear = _clearances(checker, tally, seen)
    return _result(mech, bodies, tally, clear, default, always, seen, rounds, home, padding, seed)


@dataclass(frozen=True)
class CollisionJob(Job):
    """What every task of a sweep needs: the samples' box, count and seed, the bodies, and which
    pairs the matrix still checks; its items are chunks of samples."""

    name = "collisions"
    unit = "sample"

    lower: np.ndarray
    upper: np.ndarray
    samples: int
    seed: int
    padding: float
    environment: tuple[Environment, ...]
    checked: np.ndarray
    chunk: int  # samples per chunk: with the seed, it decides which samples a sweep draws
    tool: object = None  # a sim.tool.Tool on the flange

    @property
    def count(self) -> int:
        return -(-self.samples // self.chunk)

    def task_items(self, cluster) -> int:
        return max(1, cluster.task_samples // self.chunk)

    def size(self, span: range) -> float:
        return float(max(0, min(span.stop * self.chunk, self.samples) - span.start * self.chunk))

    def local_spans(self) -> list[range]:
        return [range(k, k + 1) for k in range(self.count)]

    def files(self) -> tuple[str, ...]:
        return tuple(e.path for e in self.environment)

    def tools_key(self) -> tuple:
        return (self.padding, tuple((e.name, e.path, e.pose.tobytes()) for e in self.environment), self.tool)

    def tools(self, model, device: str, threads: int | None) -> Checker:
        env = tuple(Environment(e.name, model.local(e.path), e.pose) for e in self.environment)
        bodies = collision_bodies(model.mech, env, tool=tool_body(model.mech, self.tool))
        return Checker(model.mech, bodies, self.padding, device, threads, certified_cells=self.samples >= CERTIFIED_PAY)

    def empty(self) -> "CollisionTally":
        return CollisionTally.empty(len(self.checked), len(self.lower))

    def run(self, checker: Checker, tally: "CollisionTally", span: range, tick) -> None:
        """The samples of chunks ``span`` into ``tally``."""
        for k, q in zip(span, sample_chunks(self.lower, self.upper, self.samples, "random", self.seed, self.chunk,
                                            span)):
            ok = checker.loops_close(q)  # past a dead point there is no pose to check: skipped, counted
            tally.skipped += int((~ok).sum())
            if ok.any():
                index = k * self.chunk + np.nonzero(ok)[0]
                tally.add(q[ok], index, *checker.verdicts(q[ok]), self.checked)


def _limits(mech: Mechanism) -> tuple[np.ndarray, np.ndarray]:
    if not mech.graph.active:
        raise model_error(mech, f"mechanism '{mech.name}' has no active joints: there is nothing to sweep")
    lower, upper = mech.bounds()
    if not (np.all(np.isfinite(lower)) and np.all(np.isfinite(upper))):
        raise InputError("every active joint needs finite limits for a collision sweep")
    return lower, upper


def _always(checker: Checker, lower, upper, seed: int, default: np.ndarray):
    """MoveIt's rounds: pairs colliding in more than 190 of 200 random states are Always; rounds go
    on until one disables nothing. Returns (always, rounds, pairs seen colliding)."""
    always = np.zeros(checker.pair_count, bool)
    seen = np.zeros(checker.pair_count, bool)
    limit = int(ROUND * ALWAYS_FRACTION)
    rounds = 0
    while True:
        rng = np.random.default_rng([seed, 0x5EED, rounds])  # apart from the sweep's chunk streams
        q = lower + (upper - lower) * rng.random((ROUND, len(lower)))
        q = q[checker.loops_close(q)]
        hit = checker.verdicts(q)[0] & ~(default | always)  # disabled pairs are not checked (MoveIt's ACM)
        seen |= hit.any(axis=0)
        rounds += 1
        found = hit.sum(axis=0) > limit * len(q) / ROUND
        if not found.any():
            return always, rounds, seen
        always |= found


@dataclass
class CollisionTally:
    """Counts, examples and the nearest samples of free pairs, gathered chunk by chunk. Examples
    are the earliest samples, and of equal gaps the earliest sample is nearer, so sweeps of parts
    of the samples merge (in any order) into the sweep of all of them."""

    done: int
    skipped: int
    counts: np.ndarray
    free: int
    examples: list[list[tuple[int, np.ndarray]]]  # per pair: (sample index, q), earliest first
    near_gap: np.ndarray  # (pairs, CANDIDATES + 1): smallest lower bounds seen, ascending
    near_index: np.ndarray  # (pairs, CANDIDATES + 1): their sample indices (NONE: not filled)
    near_q: np.ndarray  # (pairs, CANDIDATES + 1, dof)

    @classmethod
    def empty(cls, pairs: int, dof: int) -> "CollisionTally":
        return cls(0, 0, np.zeros(pairs, np.int64), 0, [[] for _ in range(pairs)],
                   np.full((pairs, CANDIDATES + 1), np.inf), np.full((pairs, CANDIDATES + 1), NONE),
                   np.zeros((pairs, CANDIDATES + 1, dof)))

    def add(self, q: np.ndarray, index: np.ndarray, hit: np.ndarray, gap: np.ndarray, checked: np.ndarray) -> None:
        self.done += len(q)
        self.counts += hit.sum(axis=0)
        self.free += int((~hit[:, checked].any(axis=1)).sum())
        for p in np.nonzero(hit.any(axis=0))[0]:
            ex = self.examples[p]
            if len(ex) < EXAMPLES or index[0] < ex[-1][0]:
                rows = np.nonzero(hit[:, p])[0][:EXAMPLES]
                self.examples[p] = sorted(ex + [(int(index[r]), q[r]) for r in rows], key=lambda e: e[0])[:EXAMPLES]
        for p in np.nonzero(self.counts == 0)[0]:
            k = min(CANDIDATES + 1, len(q))
            take = np.nonzero(gap[:, p] <= np.partition(gap[:, p], k - 1)[k - 1])[0]  # ties at the k-th too
            self._nearest(p, gap[take, p], index[take], q[take])

    def _nearest(self, p: int, gap: np.ndarray, index: np.ndarray, q: np.ndarray) -> None:
        g = np.concatenate([self.near_gap[p], gap])
        i = np.concatenate([self.near_index[p], index])
        keep = np.lexsort((i, g))[:CANDIDATES + 1]
        self.near_gap[p], self.near_index[p] = g[keep], i[keep]
        self.near_q[p] = np.concatenate([self.near_q[p], q])[keep]

    def merge(self, other: "CollisionTally") -> None:
        """Add a sweep of other samples: exact in any order."""
        self.done += other.done
        self.skipped += other.skipped
        self.counts += other.counts
        self.free += other.free
        for p, ex in enumerate(other.examples):
            if ex:
                self.examples[p] = sorted(self.examples[p] + ex, key=lambda e: e[0])[:EXAMPLES]
        for p in np.nonzero(self.counts == 0)[0]:
            self._nearest(p, other.near_gap[p], other.near_index[p], other.near_q[p])


def _clearances(checker: Checker, sweep: CollisionTally,
                seen: np.ndarray) -> dict[int, tuple[float, np.ndarray, float]]:
    """For each pair never seen colliding: (smallest exact clearance among its nearest samples, where,
    a floor below which no sample comes: the exact values and the bound of the samples not measured)."""
    free = [p for p in range(checker.pair_count) if sweep.counts[p] == 0 and not seen[p]]
    if not free:
        return {}
    n = min(CANDIDATES, sweep.done)
    q = np.concatenate([sweep.near_q[p, :n] for p in free])
    pairs = np.repeat(np.asarray(free, np.int32), n)
    d = checker.distances(q, pairs).reshape(len(free), n)
    out = {}
    for row, p in enumerate(free):
        k = int(np.argmin(d[row]))
        rest = float(sweep.near_gap[p, n]) if sweep.done > n else np.inf
        out[p] = (float(d[row, k]), sweep.near_q[p, k], min(float(d[row, k]), rest))
    return out


def _result(mech, bodies: CollisionBodies, sweep: CollisionTally, clear: dict, default, always, seen, rounds, home,
            padding, seed) -> Collisions:
    pairs = []
    for p, (a, b) in enumerate(bodies.pairs):
        reason = "Default" if default[p] else "Always" if always[p] else \
            "Never" if sweep.counts[p] == 0 and not seen[p] else None
        c = clear.get(p)
        pairs.append(PairResult(
            body1=bodies.bodies[a].name, body2=bodies.bodies[b].name, environment=bodies.bodies[b].link < 0,
            collisions=int(sweep.counts[p]), examples=tuple(tuple(float(v) for v in q) for _, q in sweep.examples[p]),
            clearance=None if c is None else c[0], clearance_q=None if c is None else tuple(float(v) for v in c[1]),
            clearance_floor=None if c is None else c[2], reason=reason,
            tool=bodies.bodies[a].tool or bodies.bodies[b].tool))
    links = tuple(b.name for b in bodies.bodies if b.link >= 0)
    adjacent = sorted((tuple(sorted(p, key=links.index)) for p in bodies.adjacent),
                      key=lambda ab: (links.index(ab[0]), links.index(ab[1])))
    return Collisions(mechanism=mech.name, samples=sweep.done, seed=seed, padding=padding, links=links,
                      pairs=tuple(pairs), adjacent=tuple(adjacent), default_q=tuple(float(v) for v in home),
                      always_rounds=rounds, free_samples=sweep.free, warnings=bodies.warnings,
                      unreachable=sweep.skipped)
