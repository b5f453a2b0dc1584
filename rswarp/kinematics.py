"""Batched forward kinematics on Warp: compiled once per mechanism, reused for any batch size.

Warp runs a CPU launch on one core, so large batches are cut into chunks launched from a thread
pool (the launch releases the GIL) and every core works. Results do not depend on the number of
threads: each configuration is computed by one thread, the same way.
"""

from __future__ import annotations

import os
import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from .compile import KinematicTree, compile_tree, fk64
from .model import Mechanism

DEFAULT_CHUNK = 16384  # configurations per launch: scratch stays in cache, chunks balance well


def _wp():
    """Warp, initialized quietly: its banner would corrupt --json output on stdout."""
    import warp as wp

    if not getattr(_wp, "done", False):
        if hasattr(wp.config, "log_level"):
            wp.config.log_level = getattr(wp, "LOG_ERROR", 40)
        wp.config.quiet = True
        _wp.done = True
    return wp


class Kinematics:
    """Forward kinematics of one mechanism on a Warp device.

    ``fk(q)`` gives every link's pose, ``flange(q)`` the flange's, ``wrist_flange(q)`` the wrist
    centre and flange positions; ``q`` is ``(N, dof)`` active-joint values in SI (rad, m).
    """

    def __init__(self, mech: Mechanism, device: str = "cpu", chunk: int = DEFAULT_CHUNK, threads: int | None = None):
        wp = _wp()
        from .kernels import fk as kernels
        from .kernels import fk_codegen

        self.mech = mech
        self.tree: KinematicTree = compile_tree(mech)
        try:
            self.device = wp.get_device(device)
        except RuntimeError as exc:
            raise ValueError(f"device '{device}' is not available here ({exc})") from None
        self.chunk = int(chunk)
        self.threads = max(1, threads or (os.cpu_count() or 1)) if self.device.is_cpu else 1
        self._k = kernels
        t, d = self.tree, self.device
        self._parent = wp.array(t.parent, dtype=wp.int32, device=d)
        self._jtype = wp.array(t.jtype, dtype=wp.int32, device=d)
        self._qidx = wp.array(t.qidx, dtype=wp.int32, device=d)
        self._axis = wp.array(t.axis.astype(np.float32), dtype=wp.vec3, device=d)
        self._point = wp.array(t.point.astype(np.float32), dtype=wp.vec3, device=d)
        self._base = wp.transform_identity()
        self._local = threading.local()
        self._pool = ThreadPoolExecutor(self.threads) if self.threads > 1 else None
        flanges = [(t.index(f.link), f.pose.matrix()) for f in mech.flanges]
        plain = fk_codegen.Tree(t.parent, t.jtype, t.qidx, t.axis, t.point)
        slots = [mech.link_names.index(link) for link in t.links]  # fk's columns follow the file's order
        self._gen = fk_codegen.load(fk_codegen.source(plain, flanges, self.wrist_axes() if t.dof >= 5 else None, slots))
        wp.load_module(self._gen, device=d)  # compile (or load from cache) before any thread launches

    # -- public ------------------------------------------------------------------------------------
    @property
    def links(self) -> tuple[str, ...]:
        """Link names in the order of ``fk``'s second axis: the file's order (``mech.link_names``)."""
        return self.mech.link_names

    @property
    def dof(self) -> int:
        return self.tree.dof

    def fk(self, q, links: list[str] | None = None, out: np.ndarray | None = None) -> np.ndarray:
        """``(N, n_links, 4, 4)`` float32 link poses in metres (only ``links`` when given).

        ``out`` (C-contiguous float32 of that shape) is filled in place: reusing one buffer in a loop
        saves the page faults of a fresh array."""
        if links is not None:
            return self.frames(q, [(self.tree.index(n), np.eye(4)) for n in links], out)
        q = self._q(q)
        out = self._out(out, (q.shape[0], len(self.tree.links), 4, 4))
        self._launch(self._gen.fk_all, q, [out])
        return out

    def flange(self, q, name: str | None = None, out: np.ndarray | None = None) -> np.ndarray:
        """``(N, 4, 4)`` float32 flange poses (the first flange, or the one named)."""
        q = self._q(q)
        out = self._out(out, (q.shape[0], 4, 4))
        self._launch(getattr(self._gen, f"fk_flange{self._flange_index(name)}"), q, [out])
        return out

    def frames(self, q, outputs: list[tuple[int, np.ndarray]], out: np.ndarray | None = None) -> np.ndarray:
        """``(N, len(outputs), 4, 4)``: pose of link index ``k`` times a 4x4 ``offset``, per output
        (the generic tree-walking kernel)."""
        wp = _wp()
        q = self._q(q)
        out = self._out(out, (q.shape[0], len(outputs), 4, 4))
        d = self.device
        links = wp.array(np.array([k for k, _ in outputs], np.int32), dtype=wp.int32, device=d)
        offsets = wp.array([_transform(m) for _, m in outputs], dtype=wp.transform, device=d)
        wp.load_module(self._k, device=d)  # on first use, and before any thread launches it
        self._launch(self._k.fk_frames, q, [out], tree_inputs=[links, offsets])
        return out

    def wrist_flange(self, q, flange: str | None = None, wrist: bool = True) -> tuple[np.ndarray | None, np.ndarray]:
        """``(N, 3)`` wrist-centre positions (the point of the J5 axis nearest the J4 axis) and
        ``(N, 3)`` flange positions, float32 metres. The wrist needs five active joints or more;
        with ``wrist=False`` only the flange is computed and the first result is None."""
        if wrist and self.dof < 5:
            self.wrist_axes()  # raises the clear error
        q = self._q(q)
        wpos, fpos = np.empty((q.shape[0], 3), np.float32), np.empty((q.shape[0], 3), np.float32)
        self._launch(getattr(self._gen, f"wrist_flange{self._flange_index(flange)}"), q, [wpos, fpos])
        return (wpos if wrist else None), fpos

    def wrist_axes(self) -> list[tuple[int, np.ndarray, np.ndarray]]:
        """(parent link index, point, unit axis) of the 4th and 5th active joints (J4, J5)."""
        if self.dof < 5:
            raise ValueError(f"'{self.mech.name}' has {self.dof} axes: a wrist centre needs J4 and J5")
        out = []
        for name in self.tree.active[3:5]:
            j = self.mech.joint(name)
            out.append((self.tree.index(j.parent), np.asarray(j.point1, float), np.asarray(j.axis, float)))
        return out

    def fk64(self, q) -> np.ndarray:
        """Float64 NumPy forward kinematics (slow; for checks and refinement)."""
        return fk64(self.tree, q)

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None

    # -- plumbing ----------------------------------------------------------------------------------
    def _out(self, out: np.ndarray | None, shape: tuple[int, ...]) -> np.ndarray:
        if out is None:
            return np.empty(shape, np.float32)
        if out.shape != shape or out.dtype != np.float32 or not out.flags.c_contiguous:
            raise ValueError(f"out must be a C-contiguous float32 array of shape {shape}")
        return out

    def _launch(self, kernel, q: np.ndarray, outputs: list[np.ndarray], tree_inputs: list | None = None) -> None:
        """Launch ``kernel`` over q in chunks (one thread per configuration) writing ``outputs``
        (host arrays of 4x4 matrices or 3-vectors). A generated kernel takes (q, *outputs); the
        generic one, when ``tree_inputs`` is given, (q, tree arrays, *tree_inputs, scratch, *outputs)."""
        wp = _wp()

        def launch(lo: int, hi: int) -> None:
            qa, scratch = self._inputs(q, lo, hi, scratch=tree_inputs is not None)
            res = [self._output(host, lo, hi, wp.mat44 if host.shape[-2:] == (4, 4) else wp.vec3) for host in outputs]
            head = [qa]
            if tree_inputs is not None:
                head += [self._parent, self._jtype, self._qidx, self._axis, self._point, self._base, *tree_inputs, scratch]
            wp.launch(kernel, dim=hi - lo, device=self.device, inputs=[*head, *(r[0] for r in res)])
            for r, host in zip(res, outputs):
                self._finish(r, host, lo, hi)

        self._run(q.shape[0], launch)

    def _flange_index(self, name: str | None) -> int:
        names = [f.name for f in self.mech.flanges]
        if not names:
            raise ValueError(f"'{self.mech.name}' has no flange (a Flanges/Flange element names one)")
        if name is None:
            return 0
        if name not in names:
            raise KeyError(f"no flange '{name}' (flanges: {', '.join(names)})")
        return names.index(name)

    def flange_frame(self, name: str | None = None) -> tuple[int, np.ndarray]:
        """(link index, 4x4 zero-position pose) of a flange (the first when ``name`` is None)."""
        fl = self.mech.flanges[self._flange_index(name)]
        return self.tree.index(fl.link), fl.pose.matrix()

    def _q(self, q) -> np.ndarray:
        q = np.ascontiguousarray(np.atleast_2d(q), dtype=np.float32)
        if q.ndim != 2 or q.shape[1] != self.dof:
            raise ValueError(f"q must have shape (N, {self.dof}), got {q.shape}")
        return q

    def _scratch(self, n: int):
        wp = _wp()
        s = getattr(self._local, "scratch", None)
        if s is None or s.shape[0] < n:
            s = wp.empty((max(n, 1), len(self.tree.links)), dtype=wp.transform, device=self.device)
            self._local.scratch = s
        return s

    def _inputs(self, q: np.ndarray, lo: int, hi: int, scratch: bool = True):
        wp = _wp()
        if self.device.is_cpu:
            qa = wp.array(q[lo:hi], dtype=wp.float32, device=self.device, copy=False)
        else:
            qa = wp.array(q[lo:hi], dtype=wp.float32, device=self.device)
        return qa, (self._scratch(hi - lo) if scratch else None)

    def _output(self, host: np.ndarray, lo: int, hi: int, dtype):
        """A Warp view of ``host[lo:hi]`` on the CPU; a device array to copy back on a GPU."""
        wp = _wp()
        if self.device.is_cpu:
            return (wp.array(host[lo:hi], dtype=dtype, device=self.device, copy=False), False)
        shape = host[lo:hi].shape[: host.ndim - (2 if dtype is wp.mat44 else 1)]
        return (wp.empty(shape, dtype=dtype, device=self.device), True)

    def _finish(self, res, host: np.ndarray, lo: int, hi: int) -> None:
        arr, copy_back = res
        if copy_back:
            host[lo:hi] = arr.numpy().reshape(host[lo:hi].shape)

    def _run(self, n: int, launch) -> None:
        if self.device.is_cpu:  # at least one chunk per thread, so small batches use every core too
            chunk = max(1, min(self.chunk, -(-n // self.threads)))
        else:
            chunk = max(self.chunk, 1 << 20)
        spans = [(lo, min(lo + chunk, n)) for lo in range(0, n, chunk)]
        if self._pool is None or len(spans) == 1:
            for lo, hi in spans:
                launch(lo, hi)
        else:
            for f in [self._pool.submit(launch, lo, hi) for lo, hi in spans]:
                f.result()

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass


def _transform(m: np.ndarray):
    """A 4x4 rigid transform as a Warp transform (float32)."""
    wp = _wp()
    r = m[:3, :3]
    return wp.transform(wp.vec3(*m[:3, 3]), wp.quat_from_matrix(wp.mat33(*r.flatten())))
