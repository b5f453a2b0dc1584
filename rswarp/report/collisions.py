"""``rswarp collisions``: a collision sweep of a file, what it leaves in its output folder
(``collision_matrix.srdf``, ``report.json``, ``heatmap.png``) and the summary it prints, in the
file's units."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Callable

import numpy as np

from ..export.srdf import srdf_text
from ..files import atomic_write
from ..launch import driver_device
from ..motion.cells import robot_of, tool_spec
from ..outputs import atomic_folder, check_replaceable
from ..rsxml.model import Mechanism
from ..rsxml.units import format_number
from ..sim.bodies import placed_environments
from ..sim.collisions import CANDIDATES, REASONS, Collisions, collisions
from ..sim.engine import cluster_for
from ..sim.tool import load_tool
from .cell_sweeps import cell_collisions, cell_collisions_text
from .output import Output, Warn, ignore, json_bytes, json_safe

COLLISION_FILES = ("collision_matrix.srdf", "report.json", "heatmap.png")


def run_collisions(path: str, out: str, samples: int, seed: int = 0, padding: float = 0.0, env: list[str] = (),
                   device: str = "cpu", ray: str | None = None, progress: Callable[[float, float], None] | None = None,
                   tool: str | None = None, warn: Warn = ignore) -> Output:
    """``rswarp collisions``: the sweep of ``path`` and its matrix written into ``out``; ``padding``
    and the ``env`` meshes' positions (``MESH@x,y,z``) in the file's length unit; ``tool`` on the
    flange (``MESH[@x,y,z,rx,ry,rz]`` or a Tool RSXML)."""
    mech, cell = robot_of(path)
    tool = tool_spec(cell, tool)
    mounted = load_tool(mech, tool)
    check_collisions_folder(out)
    cluster = cluster_for(ray, device)
    here, why = driver_device(device, cluster is not None)
    if why:
        warn(f"rswarp: warning: {why}")
    result = collisions(mech, samples=samples, seed=seed, padding=mech.si_length(padding),
                        environment=placed_environments(mech, env), device=here, progress=progress, cluster=cluster,
                        tool=mounted)
    for w in result.warnings:
        warn(w)
    extra = {"cell": cell_collisions(cell, samples, seed, mounted, here)} if cell is not None else {}
    doc = write_collisions(result, out, extra)
    text = collisions_text(result, mech, doc["files"])
    if cell is not None:
        lines = text.splitlines()
        text = "\n".join(lines[:-1] + cell_collisions_text(extra["cell"]) + lines[-1:])
    return Output(doc, text)


def check_collisions_folder(out: str | Path) -> None:
    """Refuse an output folder the sweep could not replace, before any sampling is done."""
    check_replaceable(Path(out))


def collisions_srdf(c: Collisions) -> str:
    return srdf_text(c.mechanism, c.disabled(),
                     f"rswarp collision matrix: {c.samples} random samples (seed {c.seed}), padding "
                     f"{c.padding:g} m; Default = colliding at the RSXML HomePosition")


def write_collisions(c: Collisions, out: str | Path, extra: dict | None = None) -> dict:
    """Write the SRDF, the JSON report and the heat map into ``out`` as one set (an interrupted run
    leaves the folder as it was); the report, its files under ``files``."""
    out = Path(out)
    files = {name.split(".")[0]: out / name for name in COLLISION_FILES}
    doc = json_safe(c.report() | (extra or {})) | {"files": {k: str(v) for k, v in files.items()}}
    with atomic_folder(out) as tmp:
        atomic_write(tmp / "collision_matrix.srdf", collisions_srdf(c).encode())
        atomic_write(tmp / "heatmap.png", heatmap_png(c))
        atomic_write(tmp / "report.json", json_bytes(doc))
    return doc


def rate_matrix(c: Collisions) -> tuple[list[str], np.ndarray, np.ndarray]:
    """Bodies (links, then environment meshes), collision rates (NaN: not tested), and the matrix
    of reasons' codes (0 checked, then 1 + the index in REASONS)."""
    names = list(c.links) + [p.body2 for p in c.pairs if p.environment and p.body2 not in c.links]
    names = list(dict.fromkeys(names))
    idx = {n: i for i, n in enumerate(names)}
    rate = np.full((len(names), len(names)), np.nan)
    code = np.zeros((len(names), len(names)), int)
    for a, b in c.adjacent:
        code[idx[a], idx[b]] = code[idx[b], idx[a]] = 1
    for p in c.pairs:
        i, j = idx[p.body1], idx[p.body2]
        rate[i, j] = rate[j, i] = p.collisions / max(c.samples, 1)
        code[i, j] = code[j, i] = 0 if p.reason is None else REASONS.index(p.reason) + 1
    return names, rate, code


def heatmap_png(c: Collisions) -> bytes:
    """A labelled lower-triangle matrix of pair collision rates; each cell says the rate and why the
    matrix disables the pair."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names, rate, code = rate_matrix(c)
    n = len(names)
    shown = np.where(np.tril(np.ones((n, n), bool), -1), rate, np.nan)
    fig, ax = plt.subplots(figsize=(1.1 * n + 2.5, 1.0 * n + 1.5), dpi=100)
    im = ax.imshow(np.ma.masked_invalid(shown * 100), cmap="magma_r", vmin=0, vmax=100)
    tags = ("", *(r.lower() for r in REASONS))
    for i in range(n):
        for j in range(i):
            text = tags[code[i, j]] if np.isnan(rate[i, j]) else f"{_percent(rate[i, j])}\n{tags[code[i, j]]}".strip()
            ax.text(j, i, text, ha="center", va="center", fontsize=7,
                    color="white" if not np.isnan(rate[i, j]) and rate[i, j] > 0.5 else "black")
    ax.set_xticks(range(n), names, rotation=45, ha="right")
    ax.set_yticks(range(n), names)
    ax.set_title(f"{c.mechanism}: share of {c.samples} samples in collision")
    fig.colorbar(im, ax=ax, label="% of samples")
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    plt.close(fig)
    return buf.getvalue()


def _percent(rate: float) -> str:
    """A heat-map cell's rate: one decimal, and never "0.0%" for a pair that did collide."""
    return "<0.1%" if 0 < rate < 0.0005 else f"{rate:.1%}"


def collisions_text(c: Collisions, mech: Mechanism, files: dict) -> str:
    """The sweep's summary, lengths and angles in the file's units."""
    lf, unit = mech.length_factor, mech.length_unit or "m"

    def length(v):
        return f"{format_number(round(v / lf, 1 if lf < 0.01 else 4) * lf, lf)} {unit}"

    lines = [f"{c.mechanism}: {c.samples} samples (seed {c.seed}), padding {length(c.padding)}",
             f"collision-free: {c.free_fraction:.2%} of samples (pairs the matrix keeps checking)",
             *([f"skipped {c.unreachable} samples where a loop cannot close (past a dead point)"] if c.unreachable
               else []),
             f"{'pair':<28} {'collide':>9}  matrix    clearance (never colliding)"]
    for p in c.pairs:
        name = f"{p.body1} / {p.body2}"
        clear = ""
        if p.clearance is not None:
            clear = (f"{length(p.clearance)} (exact) at the nearest of the {CANDIDATES} samples closest by "
                     f"bounding volumes; no sample under {length(max(p.clearance_floor, 0.0))}")
        lines.append(f"{name:<28} {p.collisions / max(c.samples, 1):>9.3%}  {p.reason or 'checked':<9} {clear}")
    lines.append("disabled: " + ", ".join(f"{v} {k.lower()}" for k, v in c.reason_counts().items())
                 + f" ({c.always_rounds} round(s) of 200 for 'always')")
    lines += [f"{k}: {v}" for k, v in files.items()]
    return "\n".join(lines)
