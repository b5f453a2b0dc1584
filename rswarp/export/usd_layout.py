"""USD files from an authored stage: one flat layer, or the component layout Newton's
urdf-usd-converter uses (an interface layer payloading Contents.usda, which sublayers Physics.usda,
Materials.usda and Geometry.usdc), or a .usdz package of either. Written into a temporary folder
beside the target, then moved into place."""

from __future__ import annotations

import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from pxr import Sdf, Usd, UsdMedia, UsdPhysics, UsdUtils

from ..errors import InputError
from ..files import cleanup_on_terminate, commit
from ..outputs import merge_folder
from . import USD_SUFFIXES
from .physics import PhysicsOptions, RobotPhysics
from .usd import build_stage

LAYOUTS = ("flat", "component")

PHYSICS_PREFIXES = ("physics:", "newton:", "state:", "drive:")  # properties the component layout puts in Physics


@dataclass(frozen=True)
class AssetInfo:
    """What a library build adds to an exported asset: the default prim's ``assetInfo``, the root
    layer's ``customLayerData``, and a preview ``thumbnail`` (PNG bytes), the prim's default
    thumbnail (``UsdMediaAssetPreviewsAPI``) in a file beside the layer (inside a .usdz)."""

    info: dict = field(default_factory=dict)
    layer_data: dict = field(default_factory=dict)
    thumbnail: bytes | None = None


def to_usd(model, path: str | Path, *, layout: str = "flat", physics: PhysicsOptions | RobotPhysics | None = None,
           asset: AssetInfo | None = None, **options) -> list[str]:
    """Write ``model`` to ``path`` (.usda, .usdc, .usd or .usdz); returns warnings.

    ``layout="flat"`` writes one file; ``"component"`` writes an asset interface layer that
    payloads ``<stem>_Payload/Contents.usda``, built from geometry, materials and physics layers
    (as Newton's urdf-usd-converter lays assets out). ``physics`` (or its fields as keywords:
    ``density``, ``mass``, ``collision``, ``drive_hz``, ...) says how the robot simulates; ``asset``
    adds a library's metadata and preview. Files are
    written into a temporary folder beside the target and moved into place; in an existing payload
    folder only the export's own files are replaced.
    """
    path = Path(path)
    ext = path.suffix.lower()
    if ext not in USD_SUFFIXES:
        raise InputError(f"{path}: the USD file must end in .usda, .usdc, .usd or .usdz")
    if layout not in LAYOUTS:
        raise InputError(f"layout must be {' or '.join(LAYOUTS)}, not {layout!r}")
    physics = physics or PhysicsOptions(**options)
    folder = path.parent if str(path.parent) else Path(".")
    with cleanup_on_terminate(), tempfile.TemporaryDirectory(dir=folder, prefix=f".{path.stem}.") as tmp:
        tmp = Path(tmp)
        if layout == "flat":
            stage = Usd.Stage.CreateInMemory()
            warnings = build_stage(stage, model, physics)
            root = tmp / (f"{path.stem}.usdc" if ext == ".usdz" else path.name)
            stage.GetRootLayer().Export(str(root))
        else:
            warnings = _component(model, tmp, path, physics)
            root = tmp / (f"{path.stem}.usda" if ext == ".usdz" else path.name)
        thumbnail = _author_asset(root, asset, f"{path.stem}.thumbnail.png") if asset else None
        if ext == ".usdz":
            _usdz(root, tmp / path.name)
        else:
            if layout == "component":
                merge_folder(tmp / f"{path.stem}_Payload", folder / f"{path.stem}_Payload")
            if thumbnail:
                commit(thumbnail, folder / thumbnail.name)
        commit(tmp / path.name, path)
        return warnings


def _author_asset(root: Path, asset: AssetInfo, thumbnail_name: str) -> Path | None:
    """Write ``asset`` into the root layer file ``root`` (and its thumbnail beside it); returns the
    thumbnail's file, None without one."""
    layer = Sdf.Layer.FindOrOpen(str(root))
    stage = Usd.Stage.Open(layer)
    prim = stage.GetDefaultPrim()
    layer.customLayerData = {**layer.customLayerData, **asset.layer_data}
    for key, value in asset.info.items():
        prim.SetAssetInfoByKey(key, value)
    thumbnail = None
    if asset.thumbnail is not None:
        thumbnail = root.parent / thumbnail_name
        thumbnail.write_bytes(asset.thumbnail)
        UsdMedia.AssetPreviewsAPI.Apply(prim).SetDefaultThumbnails(
            UsdMedia.AssetPreviewsAPI.Thumbnails(Sdf.AssetPath(f"./{thumbnail_name}")))
    layer.Save()
    return thumbnail


ZIP_EPOCH_DATE = (0 << 9) | (1 << 5) | 1  # 1980-01-01, the earliest date a zip can hold, at 00:00


def _usdz(src: Path, dst: Path) -> None:
    if not UsdUtils.CreateNewUsdzPackage(str(src), str(dst)):
        raise OSError(f"could not package {dst}")
    _fix_zip_times(dst)


def _fix_zip_times(path: Path) -> None:
    """Set every entry's time in a zip to the zip epoch, in place (the packager stamps the time of
    packaging): the same asset gives the same bytes, and USDZ's 64-byte data alignment stays."""
    import struct
    import zipfile

    with zipfile.ZipFile(path) as z:
        infos, start = z.infolist(), z.start_dir
    stamp = struct.pack("<HH", 0, ZIP_EPOCH_DATE)
    with open(path, "r+b") as f:
        for info in infos:
            f.seek(info.header_offset + 10)  # local header: time, date
            f.write(stamp)
        offset = start
        for _ in infos:
            f.seek(offset)
            header = f.read(46)
            f.seek(offset + 12)  # central directory entry: time, date
            f.write(stamp)
            name, extra, comment = struct.unpack("<HHH", header[28:34])
            offset += 46 + name + extra + comment


def _component(model, tmp: Path, path: Path, physics) -> list[str]:
    """The component layout: interface layer -> payload Contents.usda -> sublayers
    Geometry.usdc (meshes, frames, cables), Materials.usda (display colours) and Physics.usda
    (physics schemas, joints, mass); each layer holds only its own opinions."""
    stage = Usd.Stage.CreateInMemory()
    warnings = build_stage(stage, model, physics)
    full = stage.GetRootLayer()
    payload_dir = tmp / f"{path.stem}_Payload"
    payload_dir.mkdir()
    # geometry as crate: large arrays load fast (the asset validator asks for it too)
    layers = {k: _new_layer(payload_dir / f"{k}.{ext}", full)
              for k, ext in (("Geometry", "usdc"), ("Materials", "usda"), ("Physics", "usda"))}
    Sdf.CopySpec(full, Sdf.Path.absoluteRootPath, layers["Geometry"], Sdf.Path.absoluteRootPath)
    _split(stage.GetDefaultPrim(), layers)
    for layer in layers.values():
        layer.Save()
    contents = _new_layer(payload_dir / "Contents.usda", full)
    contents.subLayerPaths = ["./Physics.usda", "./Materials.usda", "./Geometry.usdc"]
    contents.Save()
    _interface(_new_layer(tmp / f"{path.stem}.usda", full), stage.GetDefaultPrim(), path)
    if path.suffix.lower() in (".usdc", ".usd"):  # .usdz is packaged from the .usda by the caller
        Sdf.Layer.FindOrOpen(str(tmp / f"{path.stem}.usda")).Export(str(tmp / path.name))
    return warnings


def _new_layer(file: Path, like):
    """A layer with the units, up axis and default prim of the layer ``like``."""
    layer = Sdf.Layer.CreateNew(str(file))
    layer.defaultPrim = like.defaultPrim
    for key in ("metersPerUnit", "upAxis", "kilogramsPerUnit"):
        if like.pseudoRoot.HasInfo(key):
            layer.pseudoRoot.SetInfo(key, like.pseudoRoot.GetInfo(key))
    return layer


def _physics_only(prim) -> bool:
    """A joint, or a scope holding nothing but joints: it belongs wholly to the physics layer."""
    if prim.IsA(UsdPhysics.Joint):
        return True
    kids = prim.GetChildren()
    return prim.GetTypeName() == "Scope" and bool(kids) and all(_physics_only(k) for k in kids)


def _split(prim, layers: dict) -> None:
    """Move physics and colour opinions out of the Geometry layer (which starts with everything),
    prim by prim from ``prim`` down."""
    geo = layers["Geometry"]
    spec = geo.GetPrimAtPath(prim.GetPath())
    if spec is None:
        return
    if _physics_only(prim):
        Sdf.CopySpec(geo, spec.path, layers["Physics"], spec.path)
        del geo.GetPrimAtPath(spec.path.GetParentPath()).nameChildren[spec.name]
        return
    _move_opinions(prim, spec, layers)
    for child in prim.GetChildren():
        _split(child, layers)


def _move_opinions(prim, spec, layers: dict) -> None:
    """A prim's physics schemas and attributes to Physics, its display colour to Materials."""
    geo, p = layers["Geometry"], prim.GetPath()
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
            _ensure_over(layers["Physics"], p)
            Sdf.CopySpec(geo, rel.path, layers["Physics"], rel.path)
            spec.RemoveProperty(rel)


def _interface(iface, root, path: Path) -> None:
    """The asset's interface layer: the robot prim with its kind, name and metadata, payloading
    the contents."""
    spec = Sdf.CreatePrimInLayer(iface, root.GetPath())
    spec.specifier = Sdf.SpecifierDef
    spec.typeName = "Xform"
    spec.SetInfo("kind", "component")
    spec.SetInfo("displayName", root.GetDisplayName())
    spec.SetInfo("customData", root.GetCustomData())
    spec.SetInfo("payload", Sdf.PayloadListOp.Create(
        prependedItems=[Sdf.Payload(f"./{path.stem}_Payload/Contents.usda")]))
    iface.Save()


def _ensure_over(layer, path) -> None:
    """An ``over`` for ``path`` in ``layer`` (parents too), unless a spec is already there."""
    if layer.GetPrimAtPath(path) is None:
        spec = Sdf.CreatePrimInLayer(layer, path)
        spec.specifier = Sdf.SpecifierOver
