"""The one batch engine. Every sweep and simulation is a ``Job`` over items (chunks of samples,
environments) cut into tasks by index. A task runs the job's kernels on its items into an
accumulator, and accumulators merge exactly, in any order: a job gives the same bits whether it
runs here (its tasks one after another, each spread over the launcher's thread pool) or as tasks
on a Ray cluster. Progress is one count of the job's unit, whichever way it runs.

A client (a workspace sweep, a collision sweep, a cable run) is a ``Job``: what every task needs
(picklable), the tools a task builds once per process (compiled kernels), an empty accumulator,
and how a task runs its items. Ray is used from this module only, and imported only when a
cluster is asked for (``pip install 'rswarp[ray]'``).
"""

from __future__ import annotations

import dataclasses
import logging
import os
import warnings
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any, Callable, ClassVar, Protocol, Sequence

import numpy as np

from ..errors import InputError
from ..rsxml.model import Mechanism
from .package import LocalModel, Package, package, unpack

INSTALL = "--ray needs Ray, an optional extra: pip install 'rswarp[ray]' (from a checkout: pip install -e '.[ray]')"
TASK_SAMPLES = 1 << 20  # sweep and collision samples per task: seconds of work, so scheduling costs little
TASK_ENVS = 64  # cable environments per task
RETRIES = 3  # a task whose worker died, or that raised, is run again up to this many times

Progress = Callable[[float, float], None]  # (done, total) in the job's unit


class Accumulator(Protocol):
    """What a task's items add up to. A job makes an empty one, its ``run`` adds items into it, and
    ``merge`` adds another accumulator's items: exactly, in any order."""

    def merge(self, other: "Accumulator") -> None: ...


class Job(ABC):
    """A batch of ``count`` items, as every task needs it (a frozen dataclass: it travels to Ray
    workers). ``unit`` names what progress counts (samples, environments)."""

    name: ClassVar[str]
    unit: ClassVar[str] = "item"

    @property
    @abstractmethod
    def count(self) -> int:
        """Items in the batch."""

    @abstractmethod
    def task_items(self, cluster: "Cluster") -> int:
        """Items per task on a cluster (a small batch is cut finer, see ``task_spans``)."""

    def size(self, span: range) -> float:
        """The progress units of the items ``span``."""
        return float(len(span))

    def local_spans(self) -> list[range]:
        """How a local run cuts the items: the progress steps of one process."""
        return [range(self.count)]

    def for_task(self, span: range) -> "Job":
        """What the task of items ``span`` needs (less than the whole job, where that is much)."""
        return self

    def files(self) -> Sequence[str]:
        """Files beside the model's own that tasks read (environment meshes), as given here."""
        return ()

    @abstractmethod
    def tools_key(self) -> tuple:
        """Tools with equal keys are the same (a worker builds them once for every task)."""

    @abstractmethod
    def tools(self, model: LocalModel, device: str, threads: int | None) -> Any:
        """What tasks run with (compiled kernels, bodies), built from ``model`` on ``device``."""

    @abstractmethod
    def empty(self) -> Accumulator:
        """An accumulator with no items."""

    @abstractmethod
    def run(self, tools, acc: Accumulator, span: range, tick: Callable[[float], None]) -> None:
        """The items ``span`` into ``acc``; ``tick(units)`` may report progress along the way."""


def run_batch(job: Job, mech: Mechanism, *, tools=None, device: str = "cpu", threads: int | None = None,
              cluster=None, progress: Progress | None = None) -> Accumulator:
    """The job's accumulator over all its items: here, with ``tools`` (or those the job builds on
    ``device``), or on ``cluster`` (a ``Cluster`` or a Ray address) as tasks."""
    acc = job.empty()
    ticks = _Ticks(progress, job.size(range(job.count)))
    if cluster is None:
        tools = tools if tools is not None else job.tools(LocalModel(mech), device, threads)
        ticks.set(0.0)
        for span in job.local_spans():
            start = ticks.done
            job.run(tools, acc, span, ticks.within(job.size(span)))
            ticks.set(start + job.size(span))
        return acc
    c = as_cluster(cluster)
    pkg, blobs = package(mech, job.files())
    spans = task_spans(c, job.count, job.task_items(c))
    run_tasks(c, job, pkg, blobs, spans, lambda span, part: (acc.merge(part), ticks.add(job.size(span))),
              started=lambda: ticks.set(0.0))
    return acc


class _Ticks:
    """Progress of one batch in the job's unit, reported as it grows."""

    def __init__(self, progress: Progress | None, total: float):
        self.progress, self.total, self.done = progress, total, 0.0

    def set(self, done: float) -> None:
        self.done = min(done, self.total)
        if self.progress is not None:
            self.progress(self.done, self.total)

    def add(self, units: float) -> None:
        self.set(self.done + units)

    def within(self, size: float) -> Callable[[float], None]:
        """``tick(units)`` for a span of ``size`` units starting now: it never passes the span."""
        end = self.done + size
        return lambda units: self.set(min(self.done + units, end))


# -- Ray ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Cluster:
    """Where and how a batch runs on Ray.

    ``address``: None starts a local Ray instance on this machine (``cpus`` of its cores, default
    all); "auto" joins the cluster this machine belongs to; "ray://host:10001" a remote one. A
    Ray already initialized in this process is used as it is. ``device`` is the Warp device of the
    workers: "cpu" (each task takes ``cpus_per_task`` cores) or "cuda" (each task takes one GPU)."""

    address: str | None = None
    cpus: int | None = None
    device: str = "cpu"
    cpus_per_task: int = 1
    task_samples: int = TASK_SAMPLES
    task_envs: int = TASK_ENVS
    retries: int = RETRIES

    def __post_init__(self):
        if self.device.split(":")[0] not in ("cpu", "cuda"):
            raise InputError(f"device '{self.device}' on a Ray cluster: use cpu or cuda")
        for name in ("cpus_per_task", "task_samples", "task_envs"):
            if getattr(self, name) < 1:
                raise InputError(f"Cluster.{name} must be at least 1")
        if self.cpus is not None and self.cpus < 1:
            raise InputError("Cluster.cpus must be at least 1")

    @property
    def threads(self) -> int:
        """Warp launch threads of a task on a CPU worker: the cores Ray gave it."""
        return self.cpus_per_task


def as_cluster(cluster: Cluster | str | None) -> Cluster | None:
    """``cluster=`` as given to the library: a Cluster, an address ("local" or "" for a local
    instance), or None (no cluster: run here)."""
    if cluster is None or isinstance(cluster, Cluster):
        return cluster
    if isinstance(cluster, str):
        return Cluster(address=None if cluster in ("", "local") else cluster)
    raise InputError(f"cluster= takes a rswarp.Cluster or a Ray address, not {type(cluster).__name__}")


def cluster_for(address: str | None, device: str = "cpu") -> Cluster | None:
    """A command's ``--ray [ADDRESS]`` as a Cluster of workers on ``device`` ("local": a local
    instance; None: no cluster). Ray missing is said now, before anything is read or run."""
    if address is None:
        return None
    ray_module()
    return Cluster(address=None if address == "local" else address, device=device)


def ray_module():
    """Ray, or an InputError saying how to install it."""
    try:
        import ray
    except ImportError:
        raise InputError(INSTALL) from None
    return ray


def connect(cluster: Cluster):
    """Ray initialized for ``cluster`` (a Ray already initialized here is kept)."""
    ray = ray_module()
    if not ray.is_initialized():
        os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")  # no telemetry leaves the machine unasked
        quiet = dict(include_dashboard=False, logging_level=logging.ERROR, log_to_driver=False)
        if cluster.address is None:
            ray.init(address="local", num_cpus=cluster.cpus or os.cpu_count(), **quiet)
        else:
            _reachable(cluster.address)
            try:
                with warnings.catch_warnings():  # Ray's own warning would repeat the one line below
                    warnings.simplefilter("ignore")
                    ray.init(address=cluster.address, **quiet)
            except (ConnectionError, RuntimeError, ValueError) as exc:
                said = next((line.strip() for line in str(exc).splitlines() if line.strip()), type(exc).__name__)
                raise InputError(f"cannot reach the Ray cluster at '{cluster.address}': {said}") from None
    return ray


def _reachable(address: str) -> None:
    """A head node's ``host:port`` answers, or an InputError now (Ray itself would retry for
    minutes). Other forms ("auto", "ray://...") are left to Ray."""
    import socket

    host, _, port = address.rpartition(":")
    if "://" in address or not host or not port.isdigit():
        return
    try:
        socket.create_connection((host, int(port)), timeout=5).close()
    except OSError as exc:
        raise InputError(f"cannot reach the Ray cluster at '{address}': {exc.strerror or exc}") from None


class TaskFailed(RuntimeError):
    """A task failed on every try: an internal error, not the user's."""


def _task(job: Job, span: range, pkg: Package, blobs: dict, device: str, threads: int):
    """What a worker runs: the model rebuilt (or found), the job's tools built once, the task's
    items into an empty accumulator. Bad input is returned, not raised, so Ray does not retry what
    cannot succeed."""
    import ray

    try:
        model = unpack(pkg, lambda digest: ray.get(blobs[digest]))
        tools = model.cached((job.name, job.tools_key(), device), lambda: job.tools(model, device, threads))
        part = job.empty()
        job.run(tools, part, span, lambda units: None)
        return ("ok", part)
    except InputError as exc:
        return ("input", str(exc))


def run_tasks(cluster: Cluster, job: Job, pkg: Package, blobs: dict[str, bytes], spans: list[range],
              merge: Callable[[range, Any], None], started: Callable[[], None] = lambda: None) -> None:
    """Run the task of each span on the cluster, handing each task's accumulator to
    ``merge(span, part)`` as it arrives; ``started()`` once every task is scheduled."""
    ray = connect(cluster)
    gpu = cluster.device.startswith("cuda")
    _check_resources(ray, cluster, gpu)
    refs = {digest: ray.put(data) for digest, data in blobs.items()}
    remote = ray.remote(_task).options(
        name=f"rswarp-{job.name}", num_cpus=cluster.cpus_per_task, num_gpus=1 if gpu else 0,
        max_retries=cluster.retries, retry_exceptions=True)
    pending = {remote.remote(job.for_task(s), s, pkg, refs, cluster.device, cluster.threads): s for s in spans}
    started()
    try:
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            for ref in ready:
                span = pending.pop(ref)  # finished: never cancelled (Ray aborts on cancelling a failed task)
                kind, value = _result(ray, ref, cluster)
                if kind == "input":
                    raise InputError(value)
                merge(span, value)
    finally:
        _cancel(ray, list(pending))


def _cancel(ray, refs: list) -> None:
    """An error or Ctrl-C: the tasks not yet finished are not wanted."""
    if refs:
        _, waiting = ray.wait(refs, num_returns=len(refs), timeout=0)
        for ref in waiting:
            ray.cancel(ref)


def _check_resources(ray, cluster: Cluster, gpu: bool) -> None:
    """A task no node can take would wait forever: say so instead."""
    have = ray.cluster_resources()
    if gpu and have.get("GPU", 0) < 1:
        raise InputError("device 'cuda' on the Ray cluster: it has no GPU (use --device cpu)")
    if have.get("CPU", 0) < cluster.cpus_per_task:
        raise InputError(f"the Ray cluster has {have.get('CPU', 0):g} CPUs, a task asks for {cluster.cpus_per_task}")


def _result(ray, ref, cluster: Cluster):
    try:
        return ray.get(ref)
    except ray.exceptions.RayError as exc:
        first = str(exc).strip().splitlines()[-1] if str(exc).strip() else type(exc).__name__
        raise TaskFailed(f"a Ray task failed {cluster.retries + 1} times: {first}") from exc


def task_spans(cluster: Cluster, count: int, per: int) -> list[range]:
    """``count`` items cut into tasks of ``per``, or smaller so that a small batch still gives every
    worker of the cluster two tasks (the results are the same either way)."""
    have = connect(cluster).cluster_resources()
    workers = have.get("GPU", 0) if cluster.device.startswith("cuda") else have.get("CPU", 1) // cluster.cpus_per_task
    return spans(count, max(1, min(per, -(-count // max(1, int(2 * workers))))))


def spans(count: int, per: int) -> list[range]:
    """``range(count)`` cut into consecutive spans of ``per``."""
    return [range(lo, min(lo + per, count)) for lo in range(0, count, per)]


def identical(a, b) -> bool:
    """Whether two results are equal bit for bit (NaN equal to NaN), through dataclasses, arrays,
    tuples and lists: the engine's guarantee, checked by the tests, the benchmark and the demo."""
    if dataclasses.is_dataclass(a):
        return type(a) is type(b) and all(identical(getattr(a, f.name), getattr(b, f.name))
                                          for f in dataclasses.fields(a))
    if isinstance(a, np.ndarray):
        return isinstance(b, np.ndarray) and a.shape == b.shape and a.dtype == b.dtype and \
            np.array_equal(a, b, equal_nan=a.dtype.kind in "fc")
    if isinstance(a, (tuple, list)):
        return type(a) is type(b) and len(a) == len(b) and all(identical(x, y) for x, y in zip(a, b))
    if isinstance(a, float) and isinstance(b, float) and a != a and b != b:
        return True
    return a == b
