"""A time-sampled USD stage to play a cable run back in usdview: each link's mesh under an Xform
whose transform is sampled per frame, and each cable a BasisCurves whose points are. Metres, Z up,
``timeCodesPerSecond`` the run's frame rate. Playback only: no physics is authored."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pxr import Gf, Sdf, Usd, UsdGeom, Vt

from .names import PrimNames
from .usd_bodies import author_mesh


@dataclass(frozen=True)
class PlaybackLink:
    """A link's mesh in its zero-position frame and its poses (frames, 4, 4), zero frame to world."""

    name: str
    vertices: np.ndarray
    faces: np.ndarray
    color: tuple[float, float, float]
    poses: np.ndarray


@dataclass(frozen=True)
class PlaybackCable:
    """A cable's points (frames, N, 3) and radius, in metres."""

    name: str
    points: np.ndarray
    radius: float
    color: tuple[float, float, float]


def write_playback(path, name: str, links: list[PlaybackLink], cables: list[PlaybackCable], fps: float) -> None:
    """Write the stage to ``path`` (.usda, .usdc or .usd)."""
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    frames = max([len(c.points) for c in cables] + [len(k.poses) for k in links] + [1])
    stage.SetStartTimeCode(0)
    stage.SetEndTimeCode(frames - 1)
    stage.SetTimeCodesPerSecond(fps)
    stage.SetFramesPerSecond(fps)
    root = UsdGeom.Xform.Define(stage, "/" + PrimNames()(name))
    stage.SetDefaultPrim(root.GetPrim())
    base, names = root.GetPath(), PrimNames()  # names that collide once made valid get suffixes
    for link in links:
        _link(stage, base.AppendChild(names(link.name)), link)
    for cable in cables:
        _cable(stage, base.AppendChild(names("cable_" + cable.name)), cable)
    stage.GetRootLayer().Save()


def _link(stage, path: Sdf.Path, link: PlaybackLink) -> None:
    xf = UsdGeom.Xform.Define(stage, path)
    op = xf.AddTransformOp()
    for f, m in enumerate(link.poses):
        if np.isfinite(m).all():
            op.Set(Gf.Matrix4d(np.asarray(m, np.float64).T.tolist()), Usd.TimeCode(f))  # USD: row vectors
    author_mesh(stage, path.AppendChild("mesh"), link.vertices, link.faces, link.color)


def _cable(stage, path: Sdf.Path, cable: PlaybackCable) -> None:
    curve = UsdGeom.BasisCurves.Define(stage, path)
    curve.CreateTypeAttr(UsdGeom.Tokens.linear)
    n = cable.points.shape[1]
    curve.CreateCurveVertexCountsAttr(Vt.IntArray([n]))
    curve.CreateWidthsAttr(Vt.FloatArray([2 * cable.radius]))
    curve.SetWidthsInterpolation(UsdGeom.Tokens.constant)
    curve.CreateDisplayColorAttr(Vt.Vec3fArray([Gf.Vec3f(*cable.color)]))
    points, extent = curve.CreatePointsAttr(), curve.CreateExtentAttr()
    for f, p in enumerate(cable.points):
        pts = np.ascontiguousarray(p, np.float32)
        points.Set(Vt.Vec3fArray.FromNumpy(pts), Usd.TimeCode(f))
        lo, hi = pts.min(axis=0) - cable.radius, pts.max(axis=0) + cable.radius
        extent.Set(Vt.Vec3fArray.FromNumpy(np.stack([lo, hi]).astype(np.float32)), Usd.TimeCode(f))
