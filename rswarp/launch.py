"""The one launcher: Warp initialized quietly, a device picked, a batch cut into chunks and run.

Warp runs a CPU launch on one core, so on a CPU a batch is cut into chunks launched from a thread
pool (the launch releases the GIL), at least one chunk per core. On a GPU a chunk is large. Inputs
and outputs are host arrays the caller owns (copied across on a GPU, outputs filled in place), or
Warp arrays already on the device, which stay there: state kept across launches (a cable run's)
never crosses the bus. Each item of the batch is computed by one thread the same way whatever
the chunking, so results are bit-identical on one core or many.

A small batch on the CPU (``SMALL`` items at most, host arrays) runs as a recorded launch
(``_Recorded``): made once per kernel and shape, it copies the arrays in and out and calls the
compiled kernel, a call of one item costing microseconds rather than the tens a Warp launch's
argument packing takes (what an interpreter or a placement search calling per target pays).
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import tempfile
import threading
import weakref
from concurrent.futures import ThreadPoolExecutor, wait
from typing import Sequence

import numpy as np

from .errors import InputError
from .files import HELD_SIGNALS, signals_held, stop_if_interrupted

DEFAULT_CHUNK = 16384  # items per CPU launch: per-thread scratch stays in cache, chunks balance well
WIDE_CHUNK = 1 << 18  # items a CPU launch may hold when it needs no scratch: fewer launches, each set up in Python
MIN_SPLIT = 512  # items a CPU chunk holds at least: a smaller batch costs less on one thread than handed out
GPU_CHUNK = 1 << 20
SMALL = 64  # items a CPU batch holds at most to run as a recorded launch (``_Recorded``): a call's fixed cost
RECORDED = 32  # recorded launches a launcher keeps (each holds its arrays), the oldest dropped first


CUDA_DRIVER_WARNING = b"Warp CUDA warning: Could not find or load the NVIDIA CUDA driver"


def init_warp():
    """Warp, initialized once and quietly: its banner would corrupt ``--json`` output on stdout, and
    on a machine without a GPU its native "no CUDA driver" line is noise (asking for ``cuda`` there
    is answered by the launcher); any other line Warp's native code prints is passed on."""
    import warp as wp

    if not getattr(init_warp, "ready", False):
        wp.config.quiet = True
        if hasattr(wp.config, "log_level"):
            wp.config.log_level = getattr(wp, "LOG_ERROR", 40)
        with _native_stderr() as said, signals_held():
            wp.init()
        for line in said():
            if not line.startswith(CUDA_DRIVER_WARNING):
                sys.stderr.write(line.decode(errors="replace"))
        init_warp.ready = True
    return wp


def _hold_signals() -> None:
    """A worker thread never takes Ctrl-C or SIGTERM: the main thread does, between launches."""
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_BLOCK, HELD_SIGNALS)


def warp_device(name: str):
    """The Warp device ``name``, or an InputError saying it is not here. Warp's native code prints
    its CUDA driver errors while it looks; the one-line error says it all, so they are dropped."""
    wp = init_warp()
    with _native_stderr():
        try:
            return wp.get_device(name)
        except (RuntimeError, ValueError) as exc:
            failed = exc
    raise InputError(f"device '{name}' is not available here ({failed})")


@contextlib.contextmanager
def _native_stderr():
    """Capture what native code writes to file descriptor 2 during the block (lines, as bytes)."""
    lines: list[bytes] = []
    try:
        saved = os.dup(2)
    except OSError:  # no stderr at all: nothing to capture
        yield lambda: lines
        return
    with tempfile.TemporaryFile() as tmp:
        sys.stderr.flush()
        os.dup2(tmp.fileno(), 2)
        try:
            yield lambda: lines
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            tmp.seek(0)
            lines.extend(tmp.read().splitlines(keepends=True))


def driver_device(device: str, on_cluster: bool) -> tuple[str, str | None]:
    """The device of this machine's share of a run (MoveIt's rounds, clearances, refining extremes),
    and a warning when it differs from ``device``: ``device`` itself, as on a cluster's workers, so
    a Ray run equals a local one; the CPU where this machine lacks it and the run is on a cluster
    (alone, a missing device is the user's error)."""
    if not on_cluster or device == "cpu":
        return device, None
    try:
        warp_device(device)
        return device, None
    except InputError:
        return "cpu", (f"this machine has no '{device}': its share of the run goes on the CPU, so the results may "
                       f"differ in the last digits from a run all on '{device}'")


_LAUNCHERS: "weakref.WeakSet[Launcher]" = weakref.WeakSet()  # every launcher with a worker pool


def stop_workers() -> None:
    """Every launcher's idle workers told to end, and pending work dropped: a command's last step,
    so that no worker outlives it however a Ctrl-C cut a launch short (Python waits for each at
    exit). A launcher used again makes a new pool."""
    for launcher in list(_LAUNCHERS):
        pool, launcher._pool = launcher._pool, None
        if pool is not None:
            pool.shutdown(wait=False, cancel_futures=True)


class Launcher:
    """Runs kernels over a batch of ``n`` items on one device.

    A kernel's parameters are, in order: ``params`` (model constants, passed as given), then the
    batch ``inputs`` and ``outputs`` whose first axis is the batch, each cut per chunk: host NumPy
    arrays (typed as the kernel declares), Warp arrays on the launcher's device, or a Warp struct
    of such Warp arrays (a group, as a cable model's state: each array cut alike). Per-item
    ``scratch`` arrays go between them when the kernel needs them (``scratch`` is a width, or one
    per array; their types are the kernel's). ``chunk``: items a CPU launch holds (``DEFAULT_CHUNK``
    when not given, and then larger for a kernel without scratch: ``_spread``)."""

    def __init__(self, device: str = "cpu", chunk: int | None = None, threads: int | None = None):
        self.device = warp_device(device)
        self.chunk = DEFAULT_CHUNK if chunk is None else max(1, int(chunk))
        self._wide = chunk is None  # chunks grown for kernels without scratch (``_spread``)
        self.threads = max(1, threads or (os.cpu_count() or 1)) if self.device.is_cpu else 1
        self._pool: ThreadPoolExecutor | None = None
        self._local = threading.local()
        self._records: dict = {}  # the small batches' recorded launches (``_Recorded``), oldest first
        self._small = threading.Lock()  # one small call at a time: a recorded launch's arrays are shared
        self._chunks = weakref.WeakKeyDictionary()  # a struct batch -> its chunks' structs (``_rows``)
        self._chunks_lock = threading.Lock()
        self._quick: dict = {}  # ``quick``'s recorded launches, by kernel and count

    def load(self, kernel) -> None:
        """Compile (or load from Warp's cache) the kernel's module before any thread launches it."""
        with signals_held():
            init_warp().load_module(kernel.module, device=self.device)

    def launch(self, kernel, n: int, params: Sequence = (), inputs: Sequence = (), outputs: Sequence = (),
               scratch: int | Sequence[int] | None = None, lanes: int = 1, overwrites: bool = False,
               whole: Sequence = ()) -> None:
        """Run ``kernel`` once per item (``wp.tid()`` is the item's index within its chunk), or once
        per ``lanes`` items (``wp.tid() * lanes`` the first; the kernel bounds the last block).
        ``overwrites``: the kernel writes its outputs whole and reads none of them (a small batch
        then skips copying them in). ``whole``: Warp arrays the kernel writes at places it finds
        itself (not an item's row), passed as they are after the scratch and before the outputs."""
        stop_if_interrupted()
        key = _small_key(kernel, n, params, inputs, outputs, scratch, lanes) if 0 < n <= SMALL and \
            self.device.is_cpu and not whole else None
        if key is not None:
            with self._small:
                recorded = self._recorded(key, kernel, n, params, inputs, outputs, scratch, lanes)
                return recorded.run(params, inputs, outputs, overwrites)
        args = kernel.adj.args
        first = len(params)
        in_types = [_dtype(args[first + k]) for k in range(len(inputs))]
        widths = () if scratch is None else (scratch,) if isinstance(scratch, int) else tuple(scratch)
        last = first + len(inputs) + len(widths) + len(whole)
        scratch_types = [args[first + len(inputs) + k].type.dtype for k in range(len(widths))]
        out_types = [_dtype(args[last + k]) for k in range(len(outputs))]

        def run(lo: int, hi: int) -> None:
            ins = [self._view(self._rows(a, lo, hi, n), t) for a, t in zip(inputs, in_types)]
            outs = [self._target(self._rows(a, lo, hi, n), t) for a, t in zip(outputs, out_types)]
            extra = [self._scratch(hi - lo, w, t, k) for k, (w, t) in enumerate(zip(widths, scratch_types))]
            with signals_held():
                init_warp().launch(kernel, dim=-(-(hi - lo) // lanes), inputs=[*params, *ins, *extra, *whole],
                                   outputs=outs, device=self.device)
            if not self.device.is_cpu:
                for host, dev in zip(outputs, outs):
                    if isinstance(host, np.ndarray):
                        host[lo:hi] = dev.numpy().reshape(host[lo:hi].shape)

        self._spread(n, run, wide=self._wide and scratch is None and not whole)

    def quick(self, kernel, n: int, inputs: Sequence, outputs: Sequence, lanes: int = 1,
              params: Sequence = ()) -> "_Recorded | None":
        """The recorded launch of ``kernel`` over ``n`` items shaped as these host arrays (no scratch;
        ``params`` the model objects it keeps, fixed), made once and kept, for a caller that checks
        its own arrays and calls it directly (``_Recorded.once``, under ``small_lock``); None on a GPU."""
        if not self.device.is_cpu:
            return None
        key = (kernel, n)
        found = self._quick.get(key)
        if found is None:
            with self._small:
                found = self._quick[key] = _Recorded(self, kernel, n, params, inputs, outputs, None, lanes)
        return found

    @property
    def small_lock(self) -> threading.Lock:
        """Held while a recorded launch runs: its arrays are shared."""
        return self._small

    def _recorded(self, key: tuple, kernel, n: int, params, inputs, outputs, scratch, lanes: int) -> "_Recorded":
        """The recorded launch of ``kernel`` over ``n`` items with arrays shaped as these, made once."""
        recorded = self._records
        found = recorded.pop(key, None)  # and put back last: the most recently used
        if found is None:
            if len(recorded) >= RECORDED:
                recorded.pop(next(iter(recorded)))
            found = _Recorded(self, kernel, n, params, inputs, outputs, scratch, lanes)
        recorded[key] = found
        return found

    def _rows(self, batch, lo: int, hi: int, n: int):
        """Items ``lo`` to ``hi`` of a batch of ``n``: an array's rows, or a Warp struct whose every
        array has the batch first, as a struct of their rows (the struct itself for the whole
        batch). A struct's chunks are made once while its fields stay the same objects (a cable
        model's state, launched frame after frame), and go with it."""
        struct = getattr(batch, "_cls", None)  # a Warp struct instance's type
        if struct is None:
            return batch[lo:hi]
        if lo == 0 and hi == n:
            return batch
        fields = [getattr(batch, name) for name in struct.vars]
        with self._chunks_lock:
            chunks = self._chunks.setdefault(batch, {})
            found = chunks.get((lo, hi))
        if found is not None and all(a is b for a, b in zip(found[0], fields)):
            return found[1]
        part = struct()
        for name, value in zip(struct.vars, fields):
            setattr(part, name, value[lo:hi] if hasattr(value, "shape") else value)
        with self._chunks_lock:
            chunks[(lo, hi)] = (fields, part)
        return part

    def _view(self, host, dtype):
        """A zero-copy Warp view of a host array on the CPU, a device copy on a GPU; a Warp array
        (a chunk of one on this device), or a struct of them, as it is."""
        wp = init_warp()
        if isinstance(host, wp.array) or dtype is None:
            return host
        return wp.array(host, dtype=dtype, device=self.device, copy=not self.device.is_cpu)

    def _target(self, host, dtype):
        """An output: the host array itself on the CPU; on a GPU a copy of it, so a kernel may also
        read what it updates, copied back after the launch; a Warp array on this device as it is."""
        return self._view(host, dtype)

    def _scratch(self, n: int, width: int, dtype, slot: int = 0):
        """A per-thread (n, width) work array, grown as needed and reused."""
        have = getattr(self._local, "scratch", {})
        arr = have.get((dtype, slot))
        if arr is None or arr.shape[0] < n or arr.shape[1] != width:
            arr = init_warp().empty((max(n, 1), max(width, 1)), dtype=dtype, device=self.device)
            have[(dtype, slot)] = arr
            self._local.scratch = have
        return arr

    def _spread(self, n: int, run, wide: bool = False) -> None:
        """``run(lo, hi)`` over the batch's chunks, on the pool's threads. ``wide``: a kernel with no
        per-thread scratch to keep in cache takes chunks up to ``WIDE_CHUNK``, four a thread at
        least, so a cheap kernel's launches (a lanes FK's 10⁶ configurations took 61) cost little."""
        size = self.chunk
        if wide:
            size = max(size, min(WIDE_CHUNK, -(-n // (4 * self.threads))))
        if self.device.is_cpu:  # at least one chunk per thread, so small batches use every core too
            chunk = max(1, min(size, max(-(-n // self.threads), MIN_SPLIT)))
        else:
            chunk = max(self.chunk, GPU_CHUNK)
        spans = [(lo, min(lo + chunk, n)) for lo in range(0, n, chunk)]
        if self.threads == 1 or len(spans) <= 1:
            for lo, hi in spans:
                run(lo, hi)
            return
        # Ctrl-C held while workers start and take work: one landing between a worker's start and
        # its pool noting it leaves a thread the pool never stops, and Python waits for it at exit
        with signals_held():
            if self._pool is None:
                self._pool = ThreadPoolExecutor(self.threads, initializer=_hold_signals)
                _LAUNCHERS.add(self)
            futures = [self._pool.submit(run, lo, hi) for lo, hi in spans]
        try:
            for f in futures:
                f.result()
        except BaseException:
            # Ctrl-C or an error: no chunk may still run native code while Python unwinds and exits
            for f in futures:
                f.cancel()
            wait(futures)
            raise

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass


def _dtype(arg):
    """The element type of a kernel's array parameter; None for a struct (a group of arrays)."""
    return getattr(arg.type, "dtype", None)


def _small_key(kernel, n: int, params, inputs, outputs, scratch, lanes: int) -> tuple | None:
    """What a recorded launch is made for (the kernel, the count, the arrays' shapes and types), in
    one pass; None where an input or output is not a host array (a Warp array: the usual launch)."""
    key = [kernel, n, len(params), lanes, scratch if scratch is None or isinstance(scratch, int) else tuple(scratch)]
    for group in (inputs, outputs):
        key.append(len(group))
        for a in group:
            if type(a) is not np.ndarray:
                return None
            key.append(a.shape)
            key.append(a.dtype.num)
    return tuple(key)


class _Recorded:
    """One small CPU batch's launch, recorded once with arrays of its own (Warp's ``Launch``): a call
    copies its inputs and outputs in, runs the compiled kernel and copies its outputs out, with no
    Warp arrays made, no arguments packed and no thread handed work, so a call of a few items costs
    microseconds. The model's ``params`` are set again only where a call passes other objects than
    the last (they are kept, so an object's id is never another's)."""

    def __init__(self, launcher: Launcher, kernel, n: int, params, inputs, outputs, scratch, lanes: int = 1):
        wp = init_warp()
        args = kernel.adj.args
        first = len(params)
        widths = () if scratch is None else (scratch,) if isinstance(scratch, int) else tuple(scratch)
        dev = launcher.device
        # shaped as a host array is viewed (a matrix or vector type takes its trailing axes)
        self.ins = [wp.array(np.zeros_like(a), dtype=args[first + k].type.dtype, device=dev)
                    for k, a in enumerate(inputs)]
        extra = [wp.zeros((max(n, 1), max(w, 1)), dtype=args[first + len(inputs) + k].type.dtype, device=dev)
                 for k, w in enumerate(widths)]
        last = first + len(inputs) + len(widths)
        self.outs = [wp.array(np.zeros_like(a), dtype=args[last + k].type.dtype, device=dev)
                     for k, a in enumerate(outputs)]
        self.in_views = [a.numpy().reshape(h.shape) for a, h in zip(self.ins, inputs)]
        self.out_views = [a.numpy().reshape(h.shape) for a, h in zip(self.outs, outputs)]
        with signals_held():
            self.cmd = wp.launch(kernel, dim=-(-n // lanes), inputs=[*params, *self.ins, *extra], outputs=self.outs,
                                 device=dev, record_cmd=True)
        self.params = list(params)
        self._direct()

    def _direct(self) -> None:
        """The compiled entry point and its argument struct, packed once (what Warp's ``invoke``
        packs again at every call); ``self.call`` None where this Warp keeps them otherwise."""
        import ctypes

        self.call = None
        cmd = self.cmd
        hooks, cache = getattr(cmd, "hooks", None), getattr(cmd.kernel, "_invoke_cache", None)
        if hooks is None or cache is None or cmd.adjoint or getattr(cmd, "block_dim", 1) > 1:
            return
        cmd.launch()  # fills the kernel's struct cache (the arrays are this record's own: harmless)
        found = cache.get((tuple(type(p) for p in cmd.params[1:]), False))
        if found is None:
            return
        struct, fields = found
        self.args = struct()
        for i, field in enumerate(fields):
            setattr(self.args, field[0], cmd.params[1 + i])
        self.fields = fields
        self.call = (hooks.forward, ctypes.byref(cmd.params[0]), ctypes.byref(self.args))

    def run(self, params, inputs, outputs, overwrites: bool = False) -> None:
        for k, (was, now) in enumerate(zip(self.params, params)):
            if was is not now:  # another model object (or a number): set it, and keep it alive
                self.cmd.set_param_at_index(k, now)
                self.params[k] = now
                if self.call is not None:
                    setattr(self.args, self.fields[k][0], self.cmd.params[1 + k])
        for view, host in zip(self.in_views, inputs):
            view[...] = host
        if not overwrites:
            for view, host in zip(self.out_views, outputs):  # as the caller's: a kernel may read what it updates
                view[...] = host
        self._fire()
        for view, host in zip(self.out_views, outputs):
            host[...] = view

    def once(self, inputs) -> list[np.ndarray]:
        """Run with ``inputs`` (host arrays of the recorded shapes; the kernel writes its outputs whole)
        and return fresh copies of the outputs."""
        for view, host in zip(self.in_views, inputs):
            view[...] = host
        self._fire()
        return [view.copy() for view in self.out_views]

    def _fire(self) -> None:
        """The compiled kernel on the recorded arrays: its entry point called directly, or the
        recorded launch where this Warp keeps its entry point otherwise."""
        if self.call is None:
            self.cmd.launch()
        else:
            forward, bounds, args = self.call
            forward(bounds, args)
