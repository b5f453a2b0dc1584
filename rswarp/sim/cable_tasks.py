"""Cable runs on a Ray cluster: the environments cut into tasks of ``Cluster.task_envs``, each
task a run of its environments (the same kernels, each environment stepped as in one run), and
their per-environment results put back in place. The spread over environments per frame needs
every environment's value, so tasks return those (float32, exact) and the driver keeps them in a
file-backed array while the tasks come in, then takes the spread frame by frame as one run does.
"""

from __future__ import annotations

import dataclasses
import tempfile
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..rsxml.model import Mechanism
from .cable import CableStepper
from .cable_results import PER_ENV, SERIES, CableResult, Series, spread
from .cables import CableOptions, make_stepper, simulate
from .trajectory import Trajectory

MAX_VALUES_BYTES = 16 << 30  # the driver's file of per-frame values: 16 GiB at most
FRAME_BLOCK = 1024  # frames read back at a time to take their spread


def on_cluster(mech: Mechanism, trajectories: list[Trajectory], who: list[int], frames: int,
               options: CableOptions, progress, cluster) -> tuple[tuple[CableResult, ...], np.ndarray]:
    """The run of environments ``who`` as Ray tasks: its cables' results and the recorded joints."""
    from . import cluster as ray

    c = ray.as_cluster(cluster)
    need = frames * len(SERIES) * len(who) * 4 * len(mech.cables)
    if need > MAX_VALUES_BYTES:
        raise InputError(f"a cluster run keeps each environment's value per frame for the spread plots: "
                         f"{need / 2**30:.1f} GiB for {len(who)} environments x {frames} frames, over the cap "
                         f"of {MAX_VALUES_BYTES >> 30} GiB; split the run (fewer environments or seconds)")
    pkg, blobs = ray.package(mech)
    spans = ray.task_spans(c, len(who), c.task_envs)
    jobs = [_job(s, trajectories, who, frames, options, c) for s in spans]
    with tempfile.TemporaryDirectory(prefix="rswarp-cables-") as folder:
        merged = _Merged(len(mech.cables), len(who), frames, Path(folder))
        ray.run(c, _cable_task, pkg, blobs, jobs, [len(s) for s in spans], merged.add, progress)
        return merged.results(), merged.recorded_q


def _job(span: range, trajectories: list[Trajectory], who: list[int], frames: int, options: CableOptions, c):
    """One task: its environments' trajectories (only those it follows), renumbered."""
    used = sorted({who[e] for e in span})
    renumber = {k: n for n, k in enumerate(used)}
    record = options.record - span.start if span.start <= options.record < span.stop else -1
    task_options = dataclasses.replace(options, record=record, device=c.device, threads=c.threads)
    return (span.start, [trajectories[k] for k in used], [renumber[who[e]] for e in span], frames, task_options)


def _cable_task(shipped, job):
    """A Ray task: a run of some environments; steppers and link meshes built once per worker."""
    from .cable import link_meshes

    start, trajectories, who, frames, options = job
    mech = shipped.mech
    meshes = shipped.cached(("meshes",), lambda: link_meshes(mech)) if options.contact else None

    def stepper(model) -> CableStepper:
        key = ("stepper", model.name, options.density, options.substeps, options.iterations, options.floor,
               options.contact, options.device)
        return shipped.cached(key, lambda: make_stepper(mech, model, options, meshes))

    runs, recorded_q = simulate(mech, trajectories, who, frames, options, meshes, values=True, stepper=stepper)
    return start, [r.result() for r in runs], [r.tally.values for r in runs], recorded_q


class _Merged:
    """Tasks' results put in place: per-environment arrays at their offsets, per-frame values in a
    file-backed (frames, 3, envs) array per cable, the recorded environment from its task."""

    def __init__(self, cables: int, envs: int, frames: int, folder: Path):
        self.envs = envs
        self.first: list[CableResult | None] = [None] * cables
        self.fields: list[dict[str, np.ndarray]] = [{} for _ in range(cables)]
        self.values = [np.lib.format.open_memmap(folder / f"values{c}.npy", "w+", np.float32,
                                                 (frames, len(SERIES), envs)) for c in range(cables)]
        self.recorded: list[CableResult | None] = [None] * cables
        self.recorded_q = np.zeros((0,))

    def add(self, part) -> None:
        start, results, values, recorded_q = part
        for c, (r, v) in enumerate(zip(results, values)):
            if self.first[c] is None:
                self.first[c] = r
                self.fields[c] = {k: _like(getattr(r, k), self.envs) for k in PER_ENV}
            for k in PER_ENV:
                self.fields[c][k][start:start + r.envs] = getattr(r, k)
            self.values[c][:, :, start:start + r.envs] = v
            if len(r.recorded):
                self.recorded[c], self.recorded_q = r, recorded_q

    def results(self) -> tuple[CableResult, ...]:
        out = []
        for c, first in enumerate(self.first):
            series = _series(self.values[c])
            rec = self.recorded[c] or first
            out.append(dataclasses.replace(first, **self.fields[c], **series, recorded=rec.recorded,
                                           stride=rec.stride))
        return tuple(out)


def _like(a: np.ndarray, envs: int) -> np.ndarray:
    """An array for all environments shaped and typed like one task's ``a``."""
    return np.empty((envs, *a.shape[1:]), a.dtype)


def _series(values: np.ndarray) -> dict[str, Series]:
    """The spread of each quantity per frame over all environments, as one run takes it."""
    rows: dict[str, list] = {key: [] for key in SERIES}
    for lo in range(0, len(values), FRAME_BLOCK):
        block = np.asarray(values[lo:lo + FRAME_BLOCK], np.float64)
        for frame in block:
            for key, v in zip(SERIES, frame):
                rows[key].append(spread(v))
    return {key: Series.of(rows[key]) for key in SERIES}
