"""USD files from an authored stage: one flat layer, or the component layout Newton's
urdf-usd-converter uses (an interface layer payloading Contents.usda, which sublayers Physics.usda,
Materials.usda and Geometry.usdc), or a .usdz package of either. Written into a temporary folder
beside the target, then moved into place."""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

from pxr import Sdf, Usd, UsdUtils

from ..errors import InputError
from ..geometry import DEFAULT_DENSITY
from . import USD_SUFFIXES
from .usd import build_stage

PHYSICS_PREFIXES = ("physics:", "newton:", "state:")  # properties the component layout puts in Physics


def to_usd(model, path: str | Path, *, density: float = DEFAULT_DENSITY, collision: str = "convexHull",
           layout: str = "flat") -> list[str]:
    """Write ``model`` to ``path`` (.usda, .usdc or .usdz); returns warnings.

    ``layout="flat"`` writes one file; ``"component"`` writes an asset interface layer that
    payloads ``<stem>_Payload/Contents.usda``, built from geometry, materials and physics layers
    (as Newton's urdf-usd-converter lays assets out). Written to temporary files first, then moved
    into place.
    """
    path = Path(path)
    ext = path.suffix.lower()
    if ext not in USD_SUFFIXES:
        raise InputError(f"{path}: the USD file must end in .usda, .usdc, .usd or .usdz")
    if layout not in ("flat", "component"):
        raise InputError("layout must be flat or component")
    folder = path.parent if str(path.parent) else Path(".")
    with tempfile.TemporaryDirectory(dir=folder, prefix=f".{path.stem}.") as tmp:
        tmp = Path(tmp)
        if layout == "flat":
            stage = Usd.Stage.CreateInMemory()
            warnings = build_stage(stage, model, density=density, collision=collision)
            if ext == ".usdz":
                stage.GetRootLayer().Export(str(tmp / f"{path.stem}.usdc"))
                _usdz(tmp / f"{path.stem}.usdc", tmp / path.name)
            else:
                stage.GetRootLayer().Export(str(tmp / path.name))
            os.replace(tmp / path.name, path)
            return warnings
        warnings = _component(model, tmp, path, density, collision)
        if ext == ".usdz":
            _usdz(tmp / f"{path.stem}.usda", tmp / path.name)
            os.replace(tmp / path.name, path)
            return warnings
        payload = tmp / f"{path.stem}_Payload"
        target = folder / f"{path.stem}_Payload"
        if target.exists():
            shutil.rmtree(target)
        os.replace(payload, target)
        os.replace(tmp / path.name, path)
        return warnings


def _usdz(src: Path, dst: Path) -> None:
    if not UsdUtils.CreateNewUsdzPackage(str(src), str(dst)):
        raise OSError(f"could not package {dst}")


def _component(model, tmp: Path, path: Path, density: float, collision: str) -> list[str]:
    """The component layout: interface layer -> payload Contents.usda -> sublayers
    Geometry.usda (meshes, frames, cables), Materials.usda (display colours) and Physics.usda
    (physics schemas, joints, mass); each layer holds only its own opinions."""
    stage = Usd.Stage.CreateInMemory()
    warnings = build_stage(stage, model, density=density, collision=collision)
    full = stage.GetRootLayer()
    root = stage.GetDefaultPrim()
    name = root.GetName()
    payload_dir = tmp / f"{path.stem}_Payload"
    payload_dir.mkdir()

    def new_layer(file: Path):
        """A layer with the stage's units, up axis and default prim."""
        layer = Sdf.Layer.CreateNew(str(file))
        layer.defaultPrim = name
        for key in ("metersPerUnit", "upAxis", "kilogramsPerUnit"):
            if full.pseudoRoot.HasInfo(key):
                layer.pseudoRoot.SetInfo(key, full.pseudoRoot.GetInfo(key))
        return layer

    # geometry as crate: large arrays load fast (the asset validator asks for it too)
    layers = {k: new_layer(payload_dir / f"{k}.{ext}")
              for k, ext in (("Geometry", "usdc"), ("Materials", "usda"), ("Physics", "usda"))}
    # Geometry gets everything, then physics and colours are moved out to their own layers
    Sdf.CopySpec(full, Sdf.Path.absoluteRootPath, layers["Geometry"], Sdf.Path.absoluteRootPath)
    geo = layers["Geometry"]
    for prim in list(stage.Traverse()):
        p = prim.GetPath()
        spec = geo.GetPrimAtPath(p)
        if spec is None:
            continue
        if "/joints" in str(p):
            continue
        schemas = list(prim.GetAppliedSchemas())
        phys = [s for s in schemas if s.startswith("Physics") or s.startswith("Newton")]
        if phys:
            ps = Sdf.CreatePrimInLayer(layers["Physics"], p)
            ps.specifier = Sdf.SpecifierOver
            ps.SetInfo("apiSchemas", Sdf.TokenListOp.Create(prependedItems=phys))
            spec.SetInfo("apiSchemas", Sdf.TokenListOp.Create(prependedItems=[s for s in schemas if s not in phys]))
        for attr in list(spec.attributes):
            target = ("Physics" if attr.name.startswith(PHYSICS_PREFIXES)
                      else "Materials" if attr.name == "primvars:displayColor" else None)
            if target:
                _ensure_over(layers[target], p)
                Sdf.CopySpec(geo, attr.path, layers[target], attr.path)
                spec.RemoveProperty(attr)
        for rel in list(spec.relationships):
            if rel.name.startswith(PHYSICS_PREFIXES):
                spec.RemoveProperty(rel)
    joints = geo.GetPrimAtPath(f"/{name}/joints")
    if joints is not None:
        Sdf.CopySpec(geo, joints.path, layers["Physics"], joints.path)
        del geo.GetPrimAtPath(f"/{name}").nameChildren["joints"]
    for layer in layers.values():
        layer.Save()
    contents = new_layer(payload_dir / "Contents.usda")
    contents.subLayerPaths = ["./Physics.usda", "./Materials.usda", "./Geometry.usdc"]
    contents.Save()
    iface = new_layer(tmp / f"{path.stem}.usda")
    spec = Sdf.CreatePrimInLayer(iface, f"/{name}")
    spec.specifier = Sdf.SpecifierDef
    spec.typeName = "Xform"
    spec.SetInfo("kind", "component")
    spec.SetInfo("displayName", root.GetDisplayName())
    spec.SetInfo("customData", root.GetCustomData())
    spec.SetInfo("payload", Sdf.PayloadListOp.Create(
        prependedItems=[Sdf.Payload(f"./{path.stem}_Payload/Contents.usda")]))
    iface.Save()
    if path.suffix.lower() in (".usdc", ".usd"):  # .usdz is packaged from the .usda by the caller
        Sdf.Layer.FindOrOpen(str(tmp / f"{path.stem}.usda")).Export(str(tmp / path.name))
    return warnings


def _ensure_over(layer, path) -> None:
    """An ``over`` for ``path`` in ``layer`` (parents too), unless a spec is already there."""
    if layer.GetPrimAtPath(path) is None:
        spec = Sdf.CreatePrimInLayer(layer, path)
        spec.specifier = Sdf.SpecifierOver
