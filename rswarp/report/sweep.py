"""``rswarp sweep``: a workspace sweep of a file, what it leaves in its output folder (the voxel
grids ``workspace.npz``, the work-range figures ``side.png`` and ``top.png``, ``report.json``) and
the summary it prints."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Callable

import numpy as np

from ..files import atomic_write
from ..kinematics.kinematics import Kinematics
from ..launch import driver_device
from ..motion.cells import robot_of
from ..outputs import atomic_folder, check_replaceable
from ..rsxml.model import Mechanism
from ..rsxml.units import format_number
from ..sim.engine import cluster_for
from ..sim.workspace import Workspace, workspace
from .cell_sweeps import cell_reach, cell_reach_text, flange_box
from .output import Output, Warn, ignore, json_bytes, json_safe

DEFAULT_RESOLUTION = 0.025  # m: voxel size of a sweep


def run_sweep(path: str, out: str, samples: int, method: str = "random", seed: int = 0,
              resolution: float | None = None, device: str = "cpu", ray: str | None = None,
              progress: Callable[[float, float], None] | None = None, warn: Warn = ignore) -> Output:
    """``rswarp sweep``: the sweep of ``path`` written into ``out``; ``resolution`` in the file's
    length unit (default 25 mm); ``ray``: a Ray address ("local" for a local instance), or None."""
    mech, cell = robot_of(path)
    check_sweep_folder(out)
    cluster = cluster_for(ray, device)
    here, why = driver_device(device, cluster is not None)
    if why:
        warn(f"rswarp: warning: {why}")
    ws = workspace(mech, samples=samples, seed=seed, method=method,
                   resolution=DEFAULT_RESOLUTION if resolution is None else mech.si_length(resolution),
                   kinematics=Kinematics(mech, device=here), progress=progress, cluster=cluster)
    extra = {"cell": cell_reach(cell, ws)} if cell is not None else {}
    doc = write_sweep(ws, mech, out, extra)
    text = sweep_text(ws, mech, doc["files"])
    if cell is not None:
        lines = text.splitlines()
        text = "\n".join(lines[:-1] + cell_reach_text(extra["cell"], lambda v: _length(mech, v)) + lines[-1:])
    return Output(doc, text)




def check_sweep_folder(out: str | Path) -> None:
    """Refuse an output folder the sweep could not replace, before any sampling is done."""
    check_replaceable(Path(out))


def write_sweep(ws: Workspace, mech: Mechanism, out: str | Path, extra: dict | None = None) -> dict:
    """Write the sweep's files into ``out`` as one set: written into a temporary folder that then
    replaces ``out`` (a folder holding an earlier sweep's files only, or none), so an interrupted
    run never leaves new voxels beside an old report. The report as a dict, its files under ``files``."""
    out = Path(out)
    files = {"voxels": out / "workspace.npz", "report": out / "report.json", "side_view": out / "side.png",
             "top_view": out / "top.png"}
    doc = json_safe(ws.report() | (extra or {})) | {"files": {k: str(v) for k, v in files.items()}}
    with atomic_folder(out) as tmp:
        from .figures import work_range_figures

        save_voxels(ws, tmp / files["voxels"].name)
        work_range_figures(ws, mech, tmp / "side.png", tmp / "top.png")
        atomic_write(tmp / files["report"].name, json_bytes(doc))
    return doc


def save_voxels(ws: Workspace, path) -> None:
    """The occupancy grids as .npz (written to a temporary file, then renamed)."""
    buf = io.BytesIO()
    arrays = {"flange": ws.flange_voxels, "origin": np.array(ws.origin), "resolution": np.array(ws.resolution)}
    if ws.wrist_voxels is not None:
        arrays["wrist"] = ws.wrist_voxels
    np.savez_compressed(buf, **arrays)
    atomic_write(path, buf.getvalue())


def _length(mech: Mechanism, v: float) -> str:
    """A length (m) in the file's unit, rounded as the sweep's lines are."""
    lf, unit = mech.length_factor, mech.length_unit or "m"
    return f"{format_number(round(v / lf, 1 if lf < 0.01 else 4) * lf, lf)} {unit}"


def sweep_text(ws: Workspace, mech: Mechanism, files: dict) -> str:
    """The sweep's figures in the file's length unit, and the files written."""

    def length(v):
        return _length(mech, v)

    lines = [f"{mech.name}: {ws.samples} {ws.method} samples (seed {ws.seed}) within the joint limits"]
    if ws.reach is not None:
        lines.append(f"  reach (J1 axis to wrist centre): {length(ws.reach.value)}  "
                     f"(best sample {length(ws.reach.sampled)})")
        lines.append(f"  wrist centre height: {length(ws.wrist_low.value)} to {length(ws.wrist_high.value)}")
    if mech.type == "Robot":
        flange = "  flange reach" if ws.reach is not None else \
            "  reach (J1 axis to flange centre; no wrist centre below five axes)"
        lines.append(f"{flange}: {length(ws.flange_reach.value)}")
    else:  # a track or a positioner has no J1 axis to measure a reach from: where its flange goes
        lo, hi = flange_box(ws)
        lines.append(f"  flange travel (to its {length(ws.resolution)} voxels): "
                     + ", ".join(f"{a} {length(u)} to {length(v)}" for a, u, v in zip("xyz", lo, hi)))
    lines.append(f"  flange height: {length(ws.flange_low.value)} to {length(ws.flange_high.value)}")
    if ws.unreachable:
        lines.append(f"  skipped {ws.unreachable} samples ({ws.unreachable / ws.samples:.1%}) where a loop cannot "
                     "close "
                     "(past a dead point)")
    lines.append("  wrote " + ", ".join(str(p) for p in files.values()))
    return "\n".join(lines)
