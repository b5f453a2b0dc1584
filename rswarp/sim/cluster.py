"""Batches on a Ray cluster: a sweep, a collision sweep or a cable run cut into tasks, each task
running the same Warp kernels on its worker, the partial results merged on the driver.

A model travels as its RSXML file's bytes plus every mesh file it uses, each put into Ray's object
store once under its content hash (``Package``); a worker writes them into a folder of its own,
reads the model there like any file, and keeps it (and the kernels it compiled) for every later
task of the same model. Nothing that holds Warp arrays is pickled.

Ray is optional (``pip install 'rswarp[ray]'``) and imported only when a cluster is asked for.
"""

from __future__ import annotations

import atexit
import dataclasses
import hashlib
import json
import logging
import os
import re
import shutil
import tempfile
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

from ..errors import InputError
from ..files import read_regular
from ..rsxml.model import Mechanism

INSTALL = "--ray needs Ray, an optional extra: pip install 'rswarp[ray]' (from a checkout: pip install -e '.[ray]')"
TASK_SAMPLES = 1 << 20  # sweep and collision samples per task: seconds of work, so scheduling costs little
TASK_ENVS = 64  # cable environments per task
RETRIES = 3  # a task whose worker died, or that raised, is run again up to this many times


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


# -- what a worker gets: files by content hash -------------------------------------------------------


@dataclass(frozen=True)
class Package:
    """A model's files as workers rebuild them: paths relative to a common folder, each with the
    SHA-256 of its bytes (``key`` hashes them all, naming the model on every worker)."""

    key: str
    model: str  # the RSXML file
    files: tuple[tuple[str, str], ...]  # (relative path, sha256), the RSXML file among them
    extra: dict[str, str] = field(default_factory=dict, compare=False)  # a driver path -> its relative path


def package(mech: Mechanism, extra: Sequence[str | Path] = ()) -> tuple[Package, dict[str, bytes]]:
    """The package of ``mech`` (its file and every mesh its parts use) plus ``extra`` files
    (environment meshes), and the bytes of each hash."""
    if not mech.path:
        raise InputError(f"mechanism '{mech.name}' was not read from a file: a Ray run ships the RSXML file "
                         "its workers read")
    paths = [_absolute(mech.path), *_mesh_files(mech), *(_absolute(p) for p in extra)]
    paths = [p for p in dict.fromkeys(_with_sidecars(paths))]
    root = Path(os.path.commonpath([str(p.parent) for p in paths]))
    blobs: dict[str, bytes] = {}
    files = []
    for p in paths:
        data = read_regular(p)
        digest = hashlib.sha256(data).hexdigest()
        blobs[digest] = data
        files.append((p.relative_to(root).as_posix(), digest))
    key = hashlib.sha256(json.dumps(files).encode()).hexdigest()[:16]
    extra_rel = {str(e): _absolute(e).relative_to(root).as_posix() for e in extra}
    return Package(key, files[0][0], tuple(files), extra_rel), blobs


def _mesh_files(mech: Mechanism) -> list[Path]:
    from ..geometry.meshes import part_mesh_path

    out = []
    for link in mech.link_names:
        for part, _ in mech.parts(link):
            found = part_mesh_path(mech, part)
            if found is not None:
                out.append(_absolute(found))
    return out


def _absolute(path: str | Path) -> Path:
    """An absolute path, symbolic links kept: a mesh reached through a linked folder must lie at
    the same place relative to the model on a worker as here."""
    return Path(os.path.abspath(path))


def _with_sidecars(paths: list[Path]) -> list[Path]:
    """The files plus those a glTF or OBJ file names beside it (buffers, textures, materials)."""
    out = []
    for p in paths:
        out.append(p)
        try:
            if p.suffix.lower() == ".gltf":
                doc = json.loads(read_regular(p))
                names = [b.get("uri", "") for key in ("buffers", "images") for b in doc.get(key, [])]
            elif p.suffix.lower() == ".obj":
                names = re.findall(rb"^mtllib\s+(.+?)\s*$", read_regular(p), re.M)
                names = [n.decode(errors="replace") for n in names]
            else:
                continue
        except (OSError, ValueError, AttributeError):
            continue  # the mesh reader says what is wrong with the file itself
        for n in names:
            side = _absolute(p.parent / n)
            if n and not n.startswith("data:") and side.is_file():
                out.append(side)
    return out


class Shipped:
    """A model rebuilt on a worker: its mechanism, its files, and what tasks built from it."""

    def __init__(self, pkg: Package, folder: Path):
        from ..rsxml.documents import load_mechanism

        self.key, self.folder = pkg.key, folder
        self.extra = {driver: str(folder / rel) for driver, rel in pkg.extra.items()}
        self.mech, _ = load_mechanism(folder / pkg.model)
        self._built: dict[Any, Any] = {}

    def local(self, driver_path: str) -> str:
        """Where an extra file given on the driver lies on this worker."""
        return self.extra[str(driver_path)]

    def cached(self, key, build: Callable[[], Any]):
        """``build()`` once per worker process for this model and ``key`` (kernels, bodies)."""
        if key not in self._built:
            self._built[key] = build()
        return self._built[key]


_SHIPPED: dict[str, Shipped] = {}  # per worker process: models by key


def unpack(pkg: Package, blobs: dict) -> Shipped:
    """The model on this worker, written out and read on the first task that needs it."""
    if pkg.key not in _SHIPPED:
        import ray

        folder = Path(tempfile.mkdtemp(prefix=f"rswarp-{pkg.key}-"))
        atexit.register(shutil.rmtree, folder, True)  # the worker's copy goes with the worker
        for rel, digest in pkg.files:
            data = ray.get(blobs[digest])
            if hashlib.sha256(data).hexdigest() != digest:
                raise RuntimeError(f"the object store returned other bytes for {rel}")
            target = folder / rel
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(data)
        _SHIPPED[pkg.key] = Shipped(pkg, folder)
    return _SHIPPED[pkg.key]


# -- running tasks -----------------------------------------------------------------------------------


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
                raise InputError(f"cannot reach the Ray cluster at '{cluster.address}': {exc}") from None
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


def _task(fn, pkg: Package, blobs: dict, job):
    """What a worker runs: the model rebuilt (or found), then ``fn(shipped, job)``. Bad input is
    returned, not raised, so Ray does not retry what cannot succeed."""
    try:
        return ("ok", fn(unpack(pkg, blobs), job))
    except InputError as exc:
        return ("input", str(exc))


def run(cluster: Cluster, fn: Callable, pkg: Package, blobs: dict[str, bytes], jobs: list, sizes: list[int],
        merge: Callable[[Any], None], progress: Callable[[int, int], None] | None = None) -> None:
    """Run ``fn(shipped, job)`` for every job on the cluster, handing each result to ``merge`` as it
    arrives (merges are exact in any order); ``progress(done, total)`` counts the jobs' sizes."""
    ray = connect(cluster)
    gpu = cluster.device.startswith("cuda")
    _check_resources(ray, cluster, gpu)
    refs = {digest: ray.put(data) for digest, data in blobs.items()}
    remote = ray.remote(_task).options(
        name=f"rswarp-{fn.__name__.strip('_')}", num_cpus=cluster.cpus_per_task,
        num_gpus=1 if gpu else 0, max_retries=cluster.retries, retry_exceptions=True)
    pending = {remote.remote(fn, pkg, refs, job): size for job, size in zip(jobs, sizes)}
    total, done = sum(sizes), 0
    if progress is not None:
        progress(0, total)
    try:
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            for ref in ready:
                size = pending.pop(ref)  # finished: never cancelled (Ray aborts on cancelling a failed task)
                kind, value = _result(ray, ref, cluster)
                if kind == "input":
                    raise InputError(value)
                merge(value)
                done += size
                if progress is not None:
                    progress(done, total)
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


def identical(a, b) -> bool:
    """Whether two results are equal bit for bit (NaN equal to NaN), through dataclasses, arrays,
    tuples and lists: a cluster run checked against a local one."""
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


def spans(count: int, per: int) -> list[range]:
    """``range(count)`` cut into consecutive spans of ``per``."""
    return [range(lo, min(lo + per, count)) for lo in range(0, count, per)]


def span_size(span: range, per: int, total: int) -> int:
    """Items in the chunks numbered ``span``, chunks of ``per`` out of ``total`` items."""
    return max(0, min(span.stop * per, total) - span.start * per)


def task_spans(cluster: Cluster, count: int, per: int) -> list[range]:
    """``count`` items (chunks, environments) cut into tasks of ``per``, or smaller so that a small
    batch still gives every worker of the cluster two tasks (the results are the same either way)."""
    have = connect(cluster).cluster_resources()
    workers = have.get("GPU", 0) if cluster.device.startswith("cuda") else have.get("CPU", 1) // cluster.cpus_per_task
    return spans(count, max(1, min(per, -(-count // max(1, int(2 * workers))))))
