"""Links as USD rigid bodies: visual meshes, explicit convex collision meshes, mass, and the
filtered collision pairs. Mesh arrays go to USD through NumPy, so a large mesh costs seconds and
about its own size in memory."""

from __future__ import annotations

import numpy as np
from pxr import Gf, UsdGeom, UsdPhysics, Vt

from ..geometry.inertia import BodyPhysics
from ..geometry.meshes import GRAPHITE_WHITE, mesh_color
from ..transforms import matrix_quat
from .names import PrimNames
from .physics import RobotPhysics

VISUALS, COLLISIONS = "visuals", "collisions"  # the scopes under each link


def author_mesh(stage, path, vertices: np.ndarray, faces: np.ndarray, color, normals: np.ndarray | None = None):
    """A triangle mesh prim from NumPy arrays (points relative to the link frame). With no
    ``normals`` (per vertex), flat face normals are authored: a convex piece has sharp edges."""
    m = UsdGeom.Mesh.Define(stage, path)
    pts = np.ascontiguousarray(vertices, np.float32)
    m.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(pts))
    m.CreateFaceVertexCountsAttr(Vt.IntArray.FromNumpy(np.full(len(faces), 3, np.int32)))
    m.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(np.ascontiguousarray(faces, np.int32).ravel()))
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    m.CreateExtentAttr(Vt.Vec3fArray.FromNumpy(np.stack([lo, hi])))
    m.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    m.CreateDisplayColorAttr(Vt.Vec3fArray([Gf.Vec3f(*color)]))
    if normals is not None:
        m.CreateNormalsAttr(Vt.Vec3fArray.FromNumpy(np.ascontiguousarray(normals, np.float32)))
        m.SetNormalsInterpolation(UsdGeom.Tokens.vertex)
    else:
        m.CreateNormalsAttr(Vt.Vec3fArray.FromNumpy(np.repeat(_face_normals(pts, faces), 3, axis=0)))
        m.SetNormalsInterpolation(UsdGeom.Tokens.faceVarying)
    return m


def _face_normals(pts: np.ndarray, faces: np.ndarray) -> np.ndarray:
    tri = pts[np.asarray(faces)]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    return np.ascontiguousarray(n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30), np.float32)


def author_links(stage, mech, root: str, physics: RobotPhysics, names) -> dict[str, str]:
    """A rigid body per link (graph order) with its meshes and mass; returns the link paths."""
    graph = mech.graph
    link_path: dict[str, str] = {}
    for k in graph.order:
        link = graph.links[k]
        body = physics.bodies[link]
        path = link_path[link] = f"{root}/{names(link, what='link')}"
        x = UsdGeom.Xform.Define(stage, path)
        x.GetPrim().SetDisplayName(link)
        x.AddTranslateOp().Set(Gf.Vec3d(*body.origin))
        UsdPhysics.RigidBodyAPI.Apply(x.GetPrim())
        _author_parts(stage, path, body, physics.collision)
        if body.mass > 0:
            _author_mass(x.GetPrim(), body)
    return link_path


def _author_parts(stage, path: str, body: BodyPhysics, approximation: str) -> None:
    """Visual meshes under ``visuals``; the convex pieces, guide purpose, under ``collisions``."""
    if not body.parts:
        return
    UsdGeom.Scope.Define(stage, f"{path}/{VISUALS}")
    UsdGeom.Scope.Define(stage, f"{path}/{COLLISIONS}")
    visual_names, collision_names = PrimNames(), PrimNames()
    for part in body.parts:
        mesh = part.mesh
        visual = author_mesh(stage, f"{path}/{VISUALS}/{visual_names(part.name)}",
                             np.asarray(mesh.vertices) - body.origin, np.asarray(mesh.faces), mesh_color(mesh),
                             np.asarray(mesh.vertex_normals))
        visual.GetPrim().SetDisplayName(part.name)
        for i, piece in enumerate(part.pieces):
            name = collision_names(part.name if len(part.pieces) == 1 else f"{part.name}_{i}")
            col = author_mesh(stage, f"{path}/{COLLISIONS}/{name}", piece.vertices - body.origin, piece.faces,
                              GRAPHITE_WHITE)
            col.GetPrim().SetDisplayName(part.name)
            col.CreatePurposeAttr(UsdGeom.Tokens.guide)
            UsdPhysics.CollisionAPI.Apply(col.GetPrim())
            # the mesh is convex already: a loader's hull of it is itself, so nothing is recomputed
            UsdPhysics.MeshCollisionAPI.Apply(col.GetPrim()).CreateApproximationAttr("convexHull")
            col.GetPrim().SetCustomDataByKey("rsxml", {"collision": approximation})


def _author_mass(prim, body: BodyPhysics) -> None:
    """Mass, centre of mass and principal inertia (UsdPhysics.MassAPI)."""
    values, vectors = np.linalg.eigh(body.inertia)
    if np.linalg.det(vectors) < 0:
        vectors[:, 2] *= -1
    api = UsdPhysics.MassAPI.Apply(prim)
    api.CreateMassAttr(float(body.mass))
    api.CreateCenterOfMassAttr(Gf.Vec3f(*body.com))
    api.CreateDiagonalInertiaAttr(Gf.Vec3f(*np.maximum(values, 0.0)))
    api.CreatePrincipalAxesAttr(Gf.Quatf(*matrix_quat(vectors)))


def author_filtered_pairs(stage, physics: RobotPhysics, link_path: dict[str, str]) -> None:
    """``UsdPhysics.FilteredPairsAPI`` on the first link of each filtered pair, with the reasons
    kept in custom data."""
    for a, b, reason in physics.filtered:
        if a not in link_path or b not in link_path:
            continue
        prim = stage.GetPrimAtPath(link_path[a])
        UsdPhysics.FilteredPairsAPI.Apply(prim).CreateFilteredPairsRel().AddTarget(link_path[b])
        reasons = dict(prim.GetCustomDataByKey("rsxml:filteredPairs") or {})
        reasons[b] = reason
        prim.SetCustomDataByKey("rsxml:filteredPairs", reasons)
