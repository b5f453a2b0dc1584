"""What inverse kinematics is given, checked before any solve: flange poses as rigid transforms
(``rigid_poses``: a rotation and a translation, every number finite, named by its index when it is
not; the arm's kernel checks the rest on the device where the host leaves it, ``NOT_RIGID``), and
configuration data as whole numbers of the right shape (``checked_conf``), never broadcast,
truncated or rounded: an ``InputError`` saying what is wrong instead."""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from ..kernels.ik import RIGID_TOL


def checked_conf(conf, n: int) -> np.ndarray:
    """``conf`` as whole numbers of the shape (4,) or (n, 4) (cf1, cf4, cf6, cfx of n poses), or
    an ``InputError`` saying what it is instead: never broadcast, truncated or rounded."""
    a = np.asarray(conf)
    if a.shape not in ((4,), (n, 4)):
        raise InputError(f"conf must have the shape (4,) or ({n}, 4) for {n} pose{'s' * (n != 1)}, not {a.shape}")
    if a.dtype.kind == "O":  # Python ints past int64 (10**30), or anything else: as numbers, if they are
        try:
            a = a.astype(np.float64)
        except (TypeError, ValueError, OverflowError):
            pass
    if a.dtype.kind not in "fiu":
        raise InputError(f"conf must hold whole numbers, not {a.dtype}")
    whole = np.isfinite(a) & (a == np.round(np.where(np.isfinite(a), a, 0)))
    if not whole.all():
        raise InputError(f"conf must hold whole numbers (quadrants and cfx), not {a[~whole].flat[0]:g}")
    if (np.abs(a) > 1000).any():
        raise InputError(f"conf {a[np.abs(a) > 1000].flat[0]:g} is no quadrant: cf1, cf4, cf6 are a joint's turn "
                         "in quarters, cfx 0..7")
    return a.astype(np.int64)


def rigid_poses(poses, dtype, checked: bool = True, offset: int = 0, total: int | None = None) -> np.ndarray:
    """``poses`` as a C-contiguous (N, 4, 4) array of ``dtype``; ``InputError`` for a shape other
    than (4, 4) or (N, 4, 4) and, ``checked``, naming the first that is not a rigid transform (a
    rotation scaled, sheared or mirrored, a bottom row other than [0, 0, 0, 1], a number not
    finite; counted from ``offset`` of ``total``). Not ``checked``, only the numbers are checked
    finite: the arm's IK kernel checks the rest on the device (``NOT_RIGID``), for free."""
    if (not checked and dtype == np.float64 and type(poses) is np.ndarray and poses.dtype == np.float64
            and poses.ndim in (2, 3) and poses.shape[-2:] == (4, 4) and poses.flags.c_contiguous
            and math.isfinite(poses.sum())):  # a small call's usual pose: one pass (a NaN or inf makes the sum so)
        return poses.reshape(-1, 4, 4)
    a = np.asarray(poses)
    if a.ndim not in (2, 3) or a.shape[-2:] != (4, 4):
        raise InputError(f"poses must have the shape (4, 4) or (N, 4, 4), not {a.shape}")
    if a.dtype.kind not in "fiuO":
        raise InputError(f"poses must hold real numbers, not {a.dtype}")
    try:
        a = np.ascontiguousarray(a, np.float64).reshape(-1, 4, 4)
    except (TypeError, ValueError) as exc:
        raise InputError(f"poses must hold real numbers: {exc}") from None
    if not checked and len(a) and np.abs(a).max() <= 1e30:  # the usual poses: finite, within float32, one pass
        return np.ascontiguousarray(a, dtype)
    with np.errstate(over="ignore", invalid="ignore"):  # a number beyond float32 is said so below, not warned of
        if dtype != np.float64 and not (np.abs(a[:, :3, 3]) <= 1e30).all():
            far = np.isfinite(a[:, :3, 3]) & (np.abs(a[:, :3, 3]) > 1e30)  # beyond float32: out of reach all the same
            a = a.copy()
            a[:, :3, 3] = np.where(far, np.clip(a[:, :3, 3], -1e30, 1e30), a[:, :3, 3])
        a = np.ascontiguousarray(a, dtype)
        if not checked:
            if not np.isfinite(a.sum()):  # one pass; the pose's reasons only when some number is not finite
                bad = ~np.isfinite(a).all(axis=(1, 2))
                if bad.any():
                    k = int(np.argmax(bad))
                    rigid_poses(a[k:k + 1], np.float64, offset=offset + k, total=total or len(a))
            return a
        return _rigid_checked(a, offset, total)


def _rigid_checked(a: np.ndarray, offset: int, total: int | None) -> np.ndarray:
    """``a`` (N, 4, 4), or an InputError naming its first pose that is not a rigid transform."""
    x, y, z = (a[:, :3, k] for k in range(3))  # the rotation's columns
    dot = lambda u, v: np.einsum("ni,ni->n", u, v)  # noqa: E731
    skew = np.maximum.reduce([abs(dot(x, x) - 1), abs(dot(y, y) - 1), abs(dot(z, z) - 1), abs(dot(x, y)),
                              abs(dot(x, z)), abs(dot(y, z))])
    det = x[:, 0] * (y[:, 1] * z[:, 2] - y[:, 2] * z[:, 1]) - x[:, 1] * (y[:, 0] * z[:, 2] - y[:, 2] * z[:, 0]) \
        + x[:, 2] * (y[:, 0] * z[:, 1] - y[:, 1] * z[:, 0])
    bottom = np.maximum.reduce([abs(a[:, 3, 0]), abs(a[:, 3, 1]), abs(a[:, 3, 2]), abs(a[:, 3, 3] - 1)])
    errors = {
        "holds a number that is not finite": ~np.isfinite(a).all(axis=(1, 2)),
        "has a bottom row other than [0, 0, 0, 1]": bottom > RIGID_TOL,
        "has a rotation that is not orthonormal (scaled or sheared)": skew > RIGID_TOL,
        "has a mirror, not a rotation (determinant -1)": det < 0,
    }
    for why, bad in errors.items():
        if bad.any():
            k = int(np.argmax(bad))
            raise InputError(f"pose {offset + k} of {total or len(a)} {why}")
    return a
