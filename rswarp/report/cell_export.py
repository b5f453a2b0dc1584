"""``rswarp export CELL.toml -o cell.usda``: the whole cell as one USD stage. Each mechanism (the
robot, each external unit) is exported as ``rswarp export`` exports it alone, with its robot-data
physics, to its own layer in ``<stem>_parts/`` beside the output; the stage references each under
``/World/<name>`` with its place in the cell as the prim's transform. A robot standing on a unit
is placed on the carrier link at that unit's home, and its root fixed joint is re-targeted (an
override on the cell's stage) from the world to the carrier's body, so that moving the track or
the positioner in a simulation carries the robot with it. The part layers stay untouched."""

from __future__ import annotations

import os
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..export import export
from ..export.names import PrimNames
from ..export.physics import DRIVE_HZ
from ..files import new_folders, output_error
from ..kinematics.cell import CellKinematics
from ..rsxml.cell import read_cell
from .output import Output, Warn, ignore

CELL_SUFFIXES = (".usda", ".usdc", ".usd")  # a .usdz cannot hold the parts as separate layers
ONE_ROBOT = ("--mass", "--limits", "--payload", "--collision-matrix", "--collision-samples")


def run_cell_export(path: str, output: str, layout: str | None = None, mesh_paths: str | None = None,
                    one_robot: tuple = (), warn: Warn = ignore, *, data_physics, **physics) -> Output:
    """Export the cell at ``path`` to the USD stage ``output``; ``physics`` (density, collision,
    drive_hz, armature, effort, velocity) applies to every mechanism, ``one_robot`` holds the
    values of the options that only one robot's file takes (each must be None). ``data_physics``
    is ``exports.data_physics`` (given by its caller, so that neither module imports the other)."""
    out = Path(output)
    if out.suffix.lower() not in CELL_SUFFIXES:
        raise InputError(f"{output}: a cell exports to one USD stage: .usda, .usdc or .usd")
    if layout not in (None, "flat") or mesh_paths is not None:
        raise InputError("--layout and --mesh-paths apply to one mechanism's export, not a cell's")
    if any(v is not None for v in one_robot):
        raise InputError(f"{', '.join(ONE_ROBOT)} apply to one robot's file, not a cell: its units' robot-data "
                         "files give their masses and limits")
    cell = read_cell(path)
    for w in cell.warnings:
        warn(w)
    names = PrimNames()
    units = {e.name: names(e.name) for e in cell.externals}
    robot_name = names(cell.robot.mechanism.name or "robot")
    mechs = [(robot_name, cell.robot.rsxml, cell.robot.mechanism)] + [
        (units[e.name], e.rsxml, e.mechanism) for e in cell.externals]
    try:
        with new_folders(out):
            results = _export_parts(mechs, out, data_physics, physics, warn)
            write_cell_stage(cell, out, {n: r.output for n, r in results.items()}, robot_name, units,
                             {n: r.physics for n, r in results.items()})
    except OSError as exc:
        raise output_error(out, exc) from None
    doc = {"output": str(out), "warnings": list(cell.warnings), "parts": {
        n: {"output": str(r.output), "total_mass": r.physics.total_mass, "joints": list(r.physics.joints),
            "warnings": list(r.warnings)} for n, r in results.items()}}
    text = [f"{n}: {r.physics.total_mass:.3f} kg, {len(r.physics.joints)} joints, {r.output}"
            for n, r in results.items()]
    count = f"{len(results)} mechanism{'s' * (len(results) > 1)}"
    return Output(doc, "\n".join([*text, f"wrote {out} (the cell: {count})"]))


def _export_parts(mechs, out: Path, data_physics, physics: dict, warn: Warn) -> dict:
    """Each mechanism (prim name, RSXML path, mechanism) exported alone to ``<stem>_parts/``, with
    its robot-data physics and the options given (``drive_hz`` 0: no drives); returns the exports by prim name."""
    parts = out.parent / f"{out.stem}_parts"
    results = {}
    for name, rsxml, mech in mechs:
        given = {k: v for k, v in physics.items() if v is not None and k != "drive_hz"}
        opts = replace(data_physics(rsxml, mech), **given, drive_hz=physics.get("drive_hz", DRIVE_HZ) or None)
        results[name] = export(mech, parts / f"{name}{out.suffix}", physics=opts)
        for w in results[name].warnings:
            warn(f"{name}: {w}")
    return results


def write_cell_stage(cell, out: Path, files: dict, robot_name: str, units: dict, physics: dict) -> None:
    """The cell's stage at ``out``: /World (default prim, Z up, metres, kilograms) with each part
    referenced at its frame; the robot at its base's world pose at home, fixed to its carrier."""
    from pxr import Sdf, Usd, UsdGeom, UsdPhysics

    for file in files.values():  # a part this process opened before is read again as just written
        if (part := Sdf.Layer.Find(str(file))) is not None:
            part.Reload()
    staged = out.parent / f".{out.stem}.partial{out.suffix}"  # written whole, then renamed to ``out``
    layer = Sdf.Layer.Find(str(staged))  # one this process staged before is written again
    if layer is not None:
        layer.Clear()
    stage = Usd.Stage.Open(layer) if layer is not None else Usd.Stage.CreateNew(str(staged))
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdPhysics.SetStageKilogramsPerUnit(stage, 1.0)
    world = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(world.GetPrim())
    kin = CellKinematics(cell)
    home = {e.name: e.mechanism.home_position()[None] for e in cell.externals}
    frames = {units[e.name]: e.frame for e in cell.externals}
    frames[robot_name] = kin.robot_base(home)[0]
    for name, file in files.items():
        prim = stage.DefinePrim(f"/World/{name}", "Xform")
        rel = Path(file).relative_to(out.parent).as_posix()
        prim.GetReferences().AddReference(f"./{rel}")
        UsdGeom.Xformable(prim).AddTransformOp().Set(gf_matrix(frames[name]))
    robot = cell.robot.mechanism
    base_origin = physics[robot_name].bodies[robot.graph.base].origin
    anchor = frames[robot_name] @ _translation(base_origin)  # the robot's base body in the world
    body0 = None
    if cell.carrier is not None:
        carrier = cell.carrier
        link = kin.units[carrier.name].graph.link_index(carrier.carrier_link)
        origin = physics[units[carrier.name]].bodies[carrier.carrier_link].origin
        carried = kin.unit_links(carrier.name, home[carrier.name])[0, link] @ _translation(origin)
        body0 = _link_prim(stage, f"/World/{units[carrier.name]}", carrier.carrier_link)
        anchor = np.linalg.inv(carried) @ anchor
    _retarget_root(stage, f"/World/{robot_name}", anchor, body0)
    stage.GetRootLayer().customLayerData = {"rsxmlCell": Path(cell.path).name}
    try:
        stage.Save()
        os.replace(staged, out)
    finally:
        staged.unlink(missing_ok=True)


def _retarget_root(stage, robot: str, anchor: np.ndarray, body0: str | None) -> None:
    """Override the robot's root fixed joint: its body0 the carrier's body (None: the world) and
    its frame there ``anchor`` (the base body's pose in body0's frame), as Newton and PhysX read it."""
    from pxr import Gf, UsdPhysics

    joint = next(p for p in stage.GetPrimAtPath(robot).GetAllChildren() if p.GetName() == "joints")
    fixed = UsdPhysics.FixedJoint(next(p for p in joint.GetChildren() if p.IsA(UsdPhysics.FixedJoint)))
    if body0 is not None:  # one articulation with the carrier's: the robot's own root is removed
        fixed.CreateBody0Rel().SetTargets([body0])
        for schema in ("PhysicsArticulationRootAPI", "NewtonArticulationRootAPI"):
            stage.GetPrimAtPath(robot).RemoveAppliedSchema(schema)
    fixed.CreateLocalPos0Attr().Set(Gf.Vec3f(*anchor[:3, 3].tolist()))
    q = Gf.Matrix4d(*anchor.T.flatten().tolist()).ExtractRotationQuat()
    fixed.CreateLocalRot0Attr().Set(Gf.Quatf(q.GetReal(), *q.GetImaginary()))


def _link_prim(stage, root: str, link: str) -> str:
    """The path of the rigid body prim of ``link`` (its displayName) under ``root``."""
    for prim in stage.GetPrimAtPath(root).GetChildren():
        if prim.GetDisplayName() == link or prim.GetName() == link:
            return str(prim.GetPath())
    raise InputError(f"{root}: no link prim '{link}' in the exported unit")


def _translation(v) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = v
    return m


def gf_matrix(m: np.ndarray):
    """A 4x4 pose (column vectors) as Gf.Matrix4d (USD's row vectors)."""
    from pxr import Gf

    return Gf.Matrix4d(*np.asarray(m, float).T.flatten().tolist())
