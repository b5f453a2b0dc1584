"""Where a RAPID move puts the flange: its target is the TCP pose in the work object, the TCP the
tool's frame on the flange, the work object (uframe x oframe) in the world the RSXML BaseFrame
places the robot in. With a stationary tool (robhold FALSE) the tool's frame is in the world and
the robot holds the work object (its uframe on the flange), and the target is the fixed TCP in
the object's frame. ``Frames`` turns target poses into flange poses and back, in batches."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..rapid import data as rd


@dataclass(frozen=True)
class Frames:
    """The fixed frames of one move: the robot's base in the world, the tool and the work object
    (and their inverses, computed once)."""

    base: np.ndarray  # 4x4, the robot in the world
    tool: np.ndarray  # 4x4, tframe
    wobj: np.ndarray  # 4x4, uframe x oframe
    stationary: bool  # the tool stands in the world; the robot holds the work object

    def __post_init__(self):
        inv = {k: rigid_inverse(getattr(self, k)) for k in ("base", "tool", "wobj")}
        object.__setattr__(self, "_inv", inv)

    def flange(self, relative: np.ndarray) -> np.ndarray:
        """Flange poses (N, 4, 4) in the robot's frame for target poses in the work object."""
        i = self._inv
        if self.stationary:
            return i["base"] @ self.tool @ rigid_inverse(relative) @ i["wobj"]
        return (i["base"] @ self.wobj) @ relative @ i["tool"]

    def relative(self, flange: np.ndarray) -> np.ndarray:
        """The TCP poses in the work object of flange poses (N, 4, 4)."""
        i = self._inv
        if self.stationary:
            return i["wobj"] @ rigid_inverse(flange) @ i["base"] @ self.tool
        return (i["wobj"] @ self.base) @ flange @ self.tool

    def world(self, flange: np.ndarray) -> np.ndarray:
        """The TCP poses in the world (a stationary tool's TCP stays where it stands)."""
        if self.stationary:
            return np.broadcast_to(self.tool, flange.shape).copy()
        return self.base @ flange @ self.tool


def rigid_inverse(m: np.ndarray) -> np.ndarray:
    """The inverse of rigid transforms (..., 4, 4): the rotation transposed."""
    out = np.zeros_like(m)
    rt = np.swapaxes(m[..., :3, :3], -1, -2)
    out[..., :3, :3] = rt
    out[..., :3, 3] = -(rt @ m[..., :3, 3:4])[..., 0]
    out[..., 3, 3] = 1.0
    return out


def frames(mech, tool: rd.Tool, wobj: rd.WorkObject) -> Frames:
    """The frames of a move with ``tool`` and ``wobj``; ValueError for a pair no robot can move
    (both held by the robot, or neither)."""
    if tool.robhold == wobj.robhold:
        raise ValueError("the robot holds both the tool and the work object" if tool.robhold else
                         "neither the tool nor the work object is held by the robot (robhold)")
    base = mech.base_frame.matrix() if mech.base_frame is not None else np.eye(4)
    return Frames(base, tool.tframe.matrix(), wobj.matrix(), not tool.robhold)


def pose_of(matrix: np.ndarray) -> rd.Pose:
    """A 4x4 matrix as a RAPID pose (metres, unit quaternion w, x, y, z with w >= 0)."""
    from scipy.spatial.transform import Rotation

    x, y, z, w = Rotation.from_matrix(matrix[:3, :3]).as_quat()
    q = np.array([w, x, y, z])
    q = -q if w < 0 else q
    return rd.Pose(tuple(float(v) for v in matrix[:3, 3]), tuple(float(v) for v in q))


def flange_poses(kin, q: np.ndarray) -> np.ndarray:
    """Flange poses (N, 4, 4) in float64 of joint values (N, dof), in one launch: the flange's own
    kernel where the chain is unrolled (every link's poses are seven times the memory to write)."""
    q = kin._q(q, np.float64)
    if kin.unrolled and len(q):
        out = np.empty((len(q), 4, 4))
        kin.launcher.launch(kin._kernels_for(np.float64)[1][0], len(q), inputs=[q], outputs=[out])
        return out
    link, m = kin.flange_frame()
    return kin.fk64(q)[:, link] @ m
