"""One to a few poses or configurations a call, on the CPU: the batch kernels' recorded launches
called directly, with none of a batch's layers (host checks it does not need, chunks, lookups by
shape), for the script, planner or ROS node that calls IK or FK one pose at a time. The numbers
are the batch's bit for bit: the same kernel on the same inputs. Anything else (another shape or
type, a pose the kernel refuses, a GPU) goes the batch's way, which says what is wrong."""

from __future__ import annotations

import math

import numpy as np

from ..kernels import fk_lanes
from ..kernels.ik import NOT_RIGID
from . import ik

QUICK = 8  # poses (configurations) a call holds at most to take the quick path
F64, F32 = np.dtype(np.float64), np.dtype(np.float32)
_NEW = object.__new__


class Quick:
    """The quick calls of one ``Kinematics``: each recorded launch made on first use, per count."""

    def __init__(self, kin):
        self.kin = kin
        self._made: dict = {}  # (what, count) -> its recorded launch, or None where it has none
        self._ik: list = [None] * (QUICK + 1)  # per count: the IK launch's input, entry point and outputs

    def ik64(self, poses) -> ik.IKSolutions | None:
        """Every branch of ``poses`` ((4, 4) or (n, 4, 4) float64, n <= QUICK), or None. The
        path a script's one-pose call takes: each step here is a part of its cost."""
        if type(poses) is not np.ndarray or poses.dtype is not F64 or not poses.flags.c_contiguous:
            return None
        shape = poses.shape
        n = 1 if shape == (4, 4) else shape[0] if len(shape) == 3 and shape[1:] == (4, 4) and shape[0] <= QUICK else 0
        call = self._ik[n] if n else None
        if call is None:
            call = self._ik_call(n) if n else None
            if call is None:
                return None
        # a NaN or inf makes the sum so (as the batch's check, which then says where)
        if not math.isfinite(sum(poses.reshape(-1).tolist())):
            return None
        put, forward, bounds, args, vq, vc, vs = call
        with self.kin.launcher.small_lock:
            put[...] = poses
            forward(bounds, args)
            q, conf, status = vq.copy(), vc.copy(), vs.copy()
        if NOT_RIGID in status[:, 0].tolist():  # the batch's way names the pose and why
            return None
        sol = _NEW(ik.IKSolutions)  # its fields set as its __init__ would, without the frozen class's setattr
        sol.__dict__.update(q=q, conf=conf, status=status, numerical=False)
        return sol

    def _ik_call(self, n: int) -> tuple | None:
        """The pieces of the recorded IK launch for ``n`` poses (made once), or None where there is
        none or this Warp keeps its entry point otherwise."""
        rec = self._recorded("ik", n)
        if rec is None or rec.call is None:
            return None
        self._ik[n] = (*rec.in_views, *rec.call, *rec.out_views)
        return self._ik[n]

    def fk64(self, q) -> np.ndarray | None:
        """Every link's pose of ``q`` ((dof,) or (n, dof) float64), or None."""
        return self._fk("fk64", q)

    def flange(self, q) -> np.ndarray | None:
        """The first flange's pose (float32) of ``q`` ((dof,) or (n, dof) float64), or None."""
        return self._fk("flange", q)

    def _fk(self, what: str, q) -> np.ndarray | None:
        n = count(q, (self.kin.dof,), F64)
        rec = self._recorded(what, n) if n else None
        if rec is None:
            return None
        with self.kin.launcher.small_lock:
            return rec.once((q,))[0]

    def _recorded(self, what: str, n: int):
        key = (what, n)
        if key not in self._made:
            self._made[key] = self._make(what, n)
        return self._made[key]

    def _make(self, what: str, n: int):
        kin = self.kin
        launcher = kin.launcher
        dof, links = kin.dof, len(kin.links)
        if what == "ik":
            form = kin._ik_form()
            if not isinstance(form, ik.ArmConstants):
                return None
            kernel = kin._arm_kernel(form, np.float64)
            outputs = [np.empty((n, ik.BRANCHES, 6)), np.empty((n, ik.BRANCHES, ik.CONF), np.int8),
                       np.empty((n, ik.BRANCHES), np.int8)]
            return launcher.quick(kernel, n, [np.zeros((n, 4, 4))], outputs)
        if not kin.unrolled:
            return None
        if what == "fk64":
            kernel = kin._kernels_for(np.float64)[0]
            return launcher.quick(kernel, n, [np.zeros((n, dof))], [np.empty((n, links, 4, 4))])
        lanes = kin._lanes()
        if lanes is None:
            return None
        kernel = lanes[1][0]
        kin._load(kernel)
        return launcher.quick(kernel, n, [np.zeros((n, dof), np.float32)], [np.empty((n, 4, 4), np.float32)],
                              lanes=fk_lanes.LANES)


def count(a, item: tuple, dtype: np.dtype, also: np.dtype | None = None) -> int:
    """How many items ``a`` holds where it is a C-contiguous array of ``dtype`` (or ``also``;
    native byte order) of one item (shape
    ``item``) or of at most QUICK of them; else 0."""
    if type(a) is not np.ndarray or (a.dtype is not dtype and a.dtype is not also) or not a.flags.c_contiguous:
        return 0
    shape = a.shape
    if shape == item:
        return 1
    if len(shape) == len(item) + 1 and shape[1:] == item and 0 < shape[0] <= QUICK:
        return shape[0]
    return 0
