"""What a sweep leaves in its output folder, and the summary it prints: the voxel grids
(``workspace.npz``), the work-range figures (``side.png``, ``top.png``) and ``report.json``."""

from __future__ import annotations

import io
import json
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..files import atomic_write
from ..rsxml.model import Mechanism
from ..rsxml.units import format_number
from ..sim.workspace import Workspace

DEFAULT_RESOLUTION = 0.025  # m: voxel size of a sweep


def sweep_resolution(mech: Mechanism, resolution: float | None) -> float:
    """A voxel size given in the file's length unit, in metres (the default when None)."""
    if resolution is None:
        return DEFAULT_RESOLUTION
    if not resolution > 0:
        raise InputError("--resolution must be positive")
    return resolution * mech.length_factor


def write_sweep(ws: Workspace, mech: Mechanism, out: str | Path) -> dict:
    """Write the sweep's files into ``out`` (created if needed); the report as a dict, with the
    files it wrote under ``files``."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"{out}: not a folder")
    out.mkdir(parents=True, exist_ok=True)
    files = {"voxels": out / "workspace.npz", "report": out / "report.json"}
    save_voxels(ws, files["voxels"])
    if ws.reach is not None:
        from .figures import work_range_figures

        files["side_view"], files["top_view"] = out / "side.png", out / "top.png"
        work_range_figures(ws, mech, files["side_view"], files["top_view"])
    doc = ws.report() | {"files": {k: str(v) for k, v in files.items()}}
    atomic_write(files["report"], (json.dumps(doc, indent=2, allow_nan=False) + "\n").encode())
    return doc


def save_voxels(ws: Workspace, path) -> None:
    """The occupancy grids as .npz (written to a temporary file, then renamed)."""
    buf = io.BytesIO()
    arrays = {"flange": ws.flange_voxels, "origin": np.array(ws.origin), "resolution": np.array(ws.resolution)}
    if ws.wrist_voxels is not None:
        arrays["wrist"] = ws.wrist_voxels
    np.savez_compressed(buf, **arrays)
    atomic_write(path, buf.getvalue())


def sweep_text(ws: Workspace, mech: Mechanism, files: dict) -> str:
    """The sweep's figures in the file's length unit, and the files written."""
    lf, unit = mech.length_factor, mech.length_unit or "m"

    def length(v):
        return f"{format_number(round(v / lf, 1 if lf < 0.01 else 4) * lf, lf)} {unit}"

    lines = [f"{mech.name}: {ws.samples} {ws.method} samples (seed {ws.seed}) within the joint limits"]
    if ws.reach is not None:
        lines.append(f"  reach (J1 axis to wrist centre): {length(ws.reach.value)}  (best sample {length(ws.reach.sampled)})")
        lines.append(f"  wrist centre height: {length(ws.wrist_low.value)} to {length(ws.wrist_high.value)}")
    lines.append(f"  flange reach: {length(ws.flange_reach.value)}")
    lines.append(f"  flange height: {length(ws.flange_low.value)} to {length(ws.flange_high.value)}")
    lines.append("  wrote " + ", ".join(str(p) for p in files.values()))
    return "\n".join(lines)
