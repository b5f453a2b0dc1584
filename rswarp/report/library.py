"""``rswarp build``: a LibraryCompiler XML to packaged USD assets, as RobotStudio's Library Compiler
builds .rslib files: one asset per ``Library`` (one per ``Variant`` where it has variants), named by
``fileName`` or its source's name (``.rslib`` becomes ``.usdz``), holding the exported component
with its meshes and convex collision pieces, its metadata and its preview image (also written
beside it as ``<name>.png``).

Each asset is built on its own: a library that fails is reported (``file:line: message``) and the
others still build; every file is written whole or not at all.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from ..errors import InputError, MeshError, RsxmlError, one_line
from ..files import atomic_write, new_folders, output_error, read_regular
from ..options import checked
from ..outputs import atomic_folder, claim, record
from ..rsxml.documents import Report, check
from ..rsxml.library import DocumentProperties, LibraryCompiler, LibraryResource, resolve_relative
from .output import Output

LAYOUTS = ("usdz", "component")
PREVIEW_SIZE = 512


@dataclass(frozen=True)
class Target:
    """One asset to build: a Library, or one Variant of it."""

    name: str  # the asset's file stem
    entry: object  # rswarp.rsxml.library.LibraryEntry
    properties: DocumentProperties
    variant: object | None = None  # rswarp.rsxml.library.Variant


@dataclass(frozen=True)
class Built:
    """What became of one target."""

    library: str  # the Library's fileName, and the variant's name after a colon
    title: str | None
    output: str | None  # the file (usdz) or folder (component) written
    size: int  # bytes written
    seconds: float
    status: str  # "built" or "failed"
    message: str = ""  # why it failed (file:line: message)
    warnings: tuple[str, ...] = ()


@dataclass(frozen=True)
class LibraryBuild:
    path: str
    out: str
    layout: str
    results: tuple[Built, ...] = field(default_factory=tuple)

    @property
    def ok(self) -> bool:
        return all(r.status == "built" for r in self.results)

    def report(self) -> dict:
        return {"library": self.path, "out": self.out, "layout": self.layout, "ok": self.ok,
                "assets": [r.__dict__ | {"warnings": list(r.warnings)} for r in self.results]}


def build_library(path: str | Path, out: str | Path | None = None, layout: str = "usdz", size: int = PREVIEW_SIZE,
                  device: str = "cpu", progress: Callable[[int, int], None] | None = None) -> LibraryBuild:
    """Build every asset of the LibraryCompiler file ``path`` into ``out`` (default: beside it)."""
    if layout not in LAYOUTS:
        raise InputError(f"layout must be {' or '.join(LAYOUTS)}, not {layout!r}")
    checked("size", size)
    report = check(path)
    if report.kind != "LibraryCompiler" or not isinstance(report.model, LibraryCompiler):
        raise RsxmlError(report.errors or [_not_library(report)])
    lib = report.model
    _raise_file_errors(report, lib)
    out = Path(out) if out is not None else Path(lib.path).parent
    targets = library_targets(lib)
    clashes = output_clashes(report.path, targets)
    results, existed = [], out.exists()
    with new_folders(out / "asset"):
        if progress:
            progress(0, len(targets))
        for k, target in enumerate(targets):
            results.append(_build_one(report, target, out, layout, size, device, clashes.get(k)))
            if progress:
                progress(k + 1, len(targets))
    if not existed and not any(r.status == "built" for r in results):
        out.rmdir()  # made for this build, and nothing was built into it
    return LibraryBuild(path=str(path), out=str(out), layout=layout, results=tuple(results))


def run_build(path: str, out: str | None = None, layout: str = "usdz", size: int = PREVIEW_SIZE, device: str = "cpu",
              progress: Callable[[float, float], None] | None = None) -> Output:
    """``rswarp build``: every asset of a LibraryCompiler file; exit 1 if any failed."""
    build = build_library(path, out, layout=layout, size=size, device=device, progress=progress)
    return Output(build.report(), build_text(build), 0 if build.ok else 1)


def output_clashes(path: str, targets: list[Target]) -> dict[int, str]:
    """Why a target cannot be built, where its output is no file name or lands on an earlier
    target's (names that differ as text but name the same file: ``a.rslib``, ``A.usdz``,
    ``sub\\a.rslib``): by the target's index. Its output is its name's asset and its preview."""
    out, first = {}, {}
    for k, t in enumerate(targets):
        line = getattr(t.variant, "line", 0) or t.entry.line
        key = t.name.casefold()
        if t.name in ("", ".", "..") or "/" in t.name or "\\" in t.name:
            out[k] = f"{path}:{line}: fileName '{t.name}' names no file"
        elif key in first:
            kind, at = first[key]
            out[k] = f"{path}:{line}: its asset '{t.name}' is the asset of the {kind} at line {at} too"
        else:
            first[key] = ("Variant" if t.variant is not None else "Library", line)
    return out


def library_targets(lib: LibraryCompiler) -> list[Target]:
    """The assets a library file builds, in its order: each Library, then each of its Variants
    (named by the variant's ``fileName``, else the library's name and the variant's)."""
    targets = []
    for entry in lib.libraries:
        stem = _stem(entry.file_name) or "component"
        targets.append(Target(stem, entry, entry.properties))
        for v in entry.variants:
            name = _stem(dict(v.options).get("fileName", "")) or f"{stem}_{v.name or len(targets)}"
            targets.append(Target(name, entry, v.properties, v))
    return targets


def _stem(file_name: str) -> str:
    """``dir\\IRB1_1_1__01.rslib`` -> ``IRB1_1_1__01`` (the .rslib becomes a .usdz)."""
    return Path(file_name.replace("\\", "/")).stem if file_name else ""


def _not_library(report: Report):
    from ..errors import Diagnostic

    return Diagnostic(report.path, 1, f"this is a {report.kind} file, not a LibraryCompiler file")


def _raise_file_errors(report: Report, lib: LibraryCompiler) -> None:
    """Errors of the library file that no one Library owns (its XML, its defaults) stop the build."""
    lines = {e.line for e in lib.libraries}
    own = [d for d in report.diagnostics if d.severity == "error" and d.line not in lines]
    if own:
        raise RsxmlError(own)


def _target_diagnostics(report: Report, target: Target) -> list:
    """The diagnostics of one Library: those at its line, and those of its source file."""
    entry = target.entry
    source = str(Path(entry.source_path).resolve()) if entry.source_path else None
    mine = [d for d in report.diagnostics if d.line in (entry.line, getattr(target.variant, "line", -1))]
    for child in report.children:
        if source and str(Path(child.path).resolve()) == source:
            mine += child.all_diagnostics
    return mine


def _model(report: Report, target: Target):
    entry = target.entry
    if entry.source_path:
        source = str(Path(entry.source_path).resolve())
        for child in report.children:
            if str(Path(child.path).resolve()) == source:
                return child.model
        return check(entry.source_path).model  # built twice: the report holds its first check only
    return entry.component


def _build_one(report: Report, target: Target, out: Path, layout: str, size: int, device: str,
               clash: str | None = None) -> Built:
    started = time.perf_counter()
    label = target.entry.file_name + (f":{target.variant.name or target.name}" if target.variant else "")
    title = target.properties.title
    diags = _target_diagnostics(report, target)
    errors = [str(d) for d in diags if d.severity == "error"] + ([clash] if clash else [])
    warnings = [str(d) for d in diags if d.severity == "warning"]
    if errors:
        return Built(label, title, None, 0, time.perf_counter() - started, "failed", errors[0], tuple(warnings))
    try:
        output, written, more = _write_asset(report, target, out, layout, size, device)
    except OSError as exc:  # the asset's own output cannot be written: this asset fails, not the build
        exc = output_error(getattr(exc, "filename", None) or out, exc)
        return Built(label, title, None, 0, time.perf_counter() - started, "failed",
                     one_line(f"{report.path}:{target.entry.line}: {exc}"), tuple(warnings))
    except (RsxmlError, InputError, MeshError, ValueError) as exc:
        where = f"{report.path}:{target.entry.line}: " if not str(exc).startswith(report.path) else ""
        return Built(label, title, None, 0, time.perf_counter() - started, "failed", one_line(f"{where}{exc}"),
                     tuple(warnings))
    return Built(label, title, str(output), written, time.perf_counter() - started, "built", "",
                 tuple(warnings + more))


def _write_asset(report: Report, target: Target, out: Path, layout: str, size: int, device: str):
    """Export the target's component with its metadata and preview; (output, bytes, warnings)."""
    from ..export.frames import mechanism_of
    from ..export.usd_layout import AssetInfo, to_usd

    model = _model(report, target)
    mech, _ = mechanism_of(model)
    warnings: list[str] = []
    thumbnail = _thumbnail(report, target, mech, size, device, warnings)
    file = f"{target.name}.usdz" if layout == "usdz" else f"{target.name}.usda"
    asset = AssetInfo(info=_asset_info(target, file), layer_data={"rswarp:library": _metadata(report, target, model)},
                      thumbnail=thumbnail)
    if layout == "usdz":
        output, preview = out / f"{target.name}.usdz", out / f"{target.name}.png"
        for path in (output, preview):
            claim(path)  # a file of the user's in the way fails this asset, and is left alone
        warnings += to_usd(model, output, layout="flat", asset=asset)
        if thumbnail is not None:  # the preview inside the package, and beside it to look at
            atomic_write(preview, thumbnail)
        record(out, [p.name for p in (output, preview) if p.exists()])
        return output, output.stat().st_size, warnings
    output = out / target.name
    with atomic_folder(output) as tmp:
        warnings += to_usd(model, tmp / f"{target.name}.usda", layout="component", asset=asset)
    written = sum(p.stat().st_size for p in output.rglob("*") if p.is_file())
    return output, written, warnings


def _asset_info(target: Target, file: str) -> dict:
    """The default prim's assetInfo: USD's own keys (name, version, identifier)."""
    from pxr import Sdf

    info = {"name": target.properties.title or target.name, "identifier": Sdf.AssetPath(f"./{file}")}
    if target.properties.revision:
        info["version"] = target.properties.revision
    return info


def _metadata(report: Report, target: Target, model) -> dict:
    """The library's properties (DocumentProperties over DefaultProperties), its variant, and the
    component's localized descriptions (``<Name>.<language>.xml`` beside its source)."""
    p = target.properties
    data = {"fileName": target.entry.file_name, "source": target.entry.source or "",
            "title": p.title or "", "author": p.author or "", "revision": p.revision or "",
            "properties": {k: v for k, v in p.extra}}
    if target.variant is not None:
        data["variant"] = {"name": target.variant.name or "", "options": dict(target.variant.options)}
    folder = Path(target.entry.source_path).parent if target.entry.source_path else Path(report.path).parent
    descriptions = _descriptions(folder, getattr(model, "name", ""))
    if descriptions:
        data["descriptions"] = descriptions
    return data


def _descriptions(folder: Path, name: str) -> dict[str, str]:
    """The component's description in each language a LibraryResource file beside it gives."""
    out = {}
    try:
        files = sorted(p for p in folder.iterdir() if p.name.startswith(f"{name}.") and p.suffix.lower() == ".xml"
                       and len(p.suffixes) >= 2)
    except OSError:
        return out
    for f in files:
        res = check(f).model
        if isinstance(res, LibraryResource) and res.language:
            text = res.descriptions(name).get("")
            if text:
                out[res.language] = text
    return out


def _thumbnail(report: Report, target: Target, mech, size: int, device: str, warnings: list[str]) -> bytes | None:
    """The preview: rendered at home (``generate``), the given picture (``source``), or none."""
    image = target.properties.image
    if image is None:
        return None
    if image.source:
        return _given_picture(report, target, image.source, size)
    if not image.generate:
        return None
    from ..sim.preview import View, home_scene, png, render

    try:
        view = View.of(image)
    except ValueError as exc:
        raise InputError(f"{report.path}:{target.entry.line}: {exc}") from None
    scene = home_scene(mech, _home_poses(mech, warnings))
    if len(scene.faces) == 0:
        warnings.append(f"{mech.path or mech.name}: no preview: no part has a mesh "
                        f"({', '.join(part for part, _ in scene.missing) or 'no part has a source'})")
        return None
    warnings += [f"preview without part {part}: {why}" for part, why in scene.missing]
    return png(render(scene, view, size, device))


def _home_poses(mech, warnings: list[str]):
    """Every link's pose at home; the zero position where the kinematics cannot be solved."""
    from ..kinematics.kinematics import Kinematics

    try:
        return Kinematics(mech).fk64(mech.home_position()[None])[0]
    except RsxmlError as exc:
        warnings.append(f"preview at the zero position: {exc}")
        return None


MAX_PICTURE_PIXELS = 64 << 20  # an Image source larger than this (8192 x 8192) is refused before decoding


def _given_picture(report: Report, target: Target, source: str, size: int) -> bytes:
    """``Image source``: the picture beside the library file, read as every input is, scaled to fit
    the preview size, as PNG. A picture of more than MAX_PICTURE_PIXELS is refused before it is
    decoded (a small file can hold a decompression bomb)."""
    import io
    import warnings

    from PIL import Image, UnidentifiedImageError

    where = f"{report.path}:{target.entry.line}: Image source '{source}'"
    path = resolve_relative(Path(report.path).parent, source)
    if path is None:
        raise InputError(f"{where} not found")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)  # our cap speaks first, once
            with Image.open(io.BytesIO(read_regular(path))) as im:
                if im.width * im.height > MAX_PICTURE_PIXELS:
                    raise InputError(f"{where}: {im.width} x {im.height} pixels, over the {MAX_PICTURE_PIXELS:,} a "
                                     "preview takes")
                im.thumbnail((size, size))
                buf = io.BytesIO()
                im.convert("RGBA").save(buf, format="PNG")
    except (OSError, UnidentifiedImageError, Image.DecompressionBombError, Image.DecompressionBombWarning) as exc:
        raise InputError(f"{where}: not a picture rswarp takes ({one_line(str(exc))})") from None
    return buf.getvalue()


def build_text(build: LibraryBuild) -> str:
    """The summary table, then each failure and warning on its own line."""
    rows = [("library", "title", "output", "size", "time", "status")]
    for r in build.results:
        rows.append((_cut(r.library, 48), (r.title or "")[:40], _cut(r.output or "-", 64),
                     size_text(r.size) if r.output else "-", f"{r.seconds:.1f} s", r.status))
    widths = [max(len(row[i]) for row in rows) for i in range(6)]
    lines = ["  ".join(c.ljust(w) for c, w in zip(row, widths)).rstrip() for row in rows]
    for r in build.results:
        lines += [f"error: {r.message}"] if r.message else []
        lines += [w if ": warning: " in w else f"warning: {w}" for w in r.warnings]
    built = sum(r.status == "built" for r in build.results)
    lines.append(f"{built} of {len(build.results)} built into {build.out}")
    return "\n".join(lines)


def _cut(text: str, width: int) -> str:
    """``text`` within ``width`` characters, its middle left out (a table column stays readable)."""
    return text if len(text) <= width else f"{text[:width // 2 - 1]}...{text[-(width - width // 2 - 2):]}"


def size_text(n: int) -> str:
    return f"{n / 1e6:.1f} MB" if n >= 1e5 else f"{n / 1e3:.1f} kB"
