"""What ``rswarp place`` writes into its folder: ``candidates.csv`` (a row per base), ``limiting.csv``
(the poses that rule out most bases, and why), ``map.png`` (a top view of the share of poses each
x, y reaches at its best yaw, the program's targets drawn) and the cell files of the bases run
through the program (``rank-K.toml``, and ``best.toml``): ``rswarp program`` re-runs each."""

from __future__ import annotations

import csv
import io
import math
import os
from pathlib import Path

import numpy as np

from ...rsxml.robot_data import read_toml
from .reach import REASONS

COLUMNS = ("x_mm", "y_mm", "z_mm", "yaw_deg", "reached", "poses", "feasible", "wrist_deg", "elbow_deg", "shoulder_mm",
           "cycle_s")


def candidates_csv(values: np.ndarray, reached: np.ndarray, poses: int, feasible: np.ndarray, singular: np.ndarray,
                   cycles: dict[int, float]) -> str:
    """One row per candidate: its base, poses reached of all, whether every pose is reached and
    nothing collides, its least singularity distances, and its cycle time where it was run."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(COLUMNS)
    for k, v in enumerate(values):
        s = ["" if math.isnan(x) else f"{x:.3f}" for x in singular[k]]
        w.writerow([f"{x:.3f}" for x in v] + [int(reached[k]), poses, int(feasible[k])] + s +
                   [f"{cycles[k]:.4f}" if cycles.get(k) is not None else ""])
    return buf.getvalue()


def limiting_csv(poses, ruled_out: np.ndarray, beyond: np.ndarray, hits: np.ndarray, pair: list,
                 shown: int = 50) -> str:
    """The poses that rule out most candidates, the most first: each with its target, its line,
    how many bases each reason rules it out at, how far beyond reach, the pair that collides."""
    total = ruled_out.sum(axis=1) + hits
    order = sorted(np.flatnonzero(total), key=lambda j: (-total[j], j))[:shown]
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["target", "where", "tcp_x_mm", "tcp_y_mm", "tcp_z_mm", "ruled_out"] +
               [r.replace(" ", "_") for r in REASONS] +
               ["beyond_reach_mm_least", "beyond_reach_mm_most", "collisions", "colliding_pair"])
    for j in order:
        lo, hi = beyond[j]
        w.writerow([poses.names[j], poses.where[j]] + [f"{1000.0 * v:.1f}" for v in poses.tcp[j]] + [int(total[j])] +
                   [int(c) for c in ruled_out[j]] +
                   ["" if math.isnan(lo) else f"{lo:.1f}", "" if math.isnan(hi) else f"{hi:.1f}", int(hits[j]),
                    " / ".join(pair[j]) if pair[j] else ""])
    return buf.getvalue()


def map_png(values: np.ndarray, share: np.ndarray, targets: np.ndarray, best: int | None, current: np.ndarray,
            title: str) -> bytes:
    """Top view: each x, y's best share of poses reached (over its yaws and heights), the targets'
    TCPs, the current base (x) and the best (star), in mm."""
    from ..figures import figure_png

    xy = np.round(values[:, :2], 6)
    keys, inverse = np.unique(xy, axis=0, return_inverse=True)
    top = np.full(len(keys), -1.0)
    np.maximum.at(top, inverse.ravel(), share)

    def draw(ax):
        art = ax.scatter(keys[:, 0], keys[:, 1], c=top, cmap="viridis", vmin=0.0, vmax=1.0, s=_size(len(keys)),
                         marker="s", label="bases (share of poses reached)")
        ax.figure.colorbar(art, ax=ax, label="poses reached (best yaw)")
        ax.scatter(targets[:, 0] * 1000.0, targets[:, 1] * 1000.0, s=6, c="k", label="targets (TCP)")
        ax.scatter([current[0]], [current[1]], marker="x", c="tab:red", s=60, label="current base")
        if best is not None:
            ax.scatter([values[best, 0]], [values[best, 1]], marker="*", c="tab:orange", s=160, label="best base")
        ax.set_aspect("equal", adjustable="datalim")

    return figure_png(draw, title, "x [mm]", "y [mm]")


def _size(count: int) -> float:
    return float(np.clip(4000.0 / max(count, 1), 4.0, 120.0))


def cell_toml(source: str, is_cell: bool, frame: list[float], folder: Path, note: str) -> str:
    """A cell file placing the robot at ``frame`` (x, y, z mm; rx, ry, rz degrees): the cell file
    ``source`` with its ``[robot] frame`` replaced (or, where a unit carries the robot, that unit's
    ``frame``), or a cell of the robot file ``source`` alone; every path relative to ``folder``,
    where it is written."""
    if not is_cell:
        doc = {"robot": {"rsxml": str(Path(source).resolve()), "frame": frame}}
    else:
        doc = read_toml(source)[1]
        carrier = doc["robot"].get("on")
        units = [t for t in doc.get("external", []) if t.get("name") == carrier]
        (units[0] if carrier and units else doc["robot"])["frame"] = frame  # a carried robot: its unit moves
        _rebased(doc, Path(source).resolve().parent)
    return f"# {note}\n" + _dump(_relative(doc, folder))


PATH_KEYS = {"backup": None, "robot": ("rsxml",), "external": ("rsxml",), "tool": ("path",), "environment": ("mesh",)}


def _rebased(doc: dict, origin: Path) -> None:
    """The cell's paths made absolute (they were relative to its own file)."""
    _each_path(doc, lambda v: str((origin / v.replace("\\", "/")).resolve()))


def _relative(doc: dict, folder: Path) -> dict:
    """Absolute paths made relative to ``folder`` (where the file goes)."""
    _each_path(doc, lambda v: Path(os.path.relpath(v, folder.resolve())).as_posix())
    return doc


def _each_path(doc: dict, change) -> None:
    """Every path of the cell document (``PATH_KEYS``) replaced by ``change(path)``, in place."""
    if isinstance(doc.get("backup"), str):
        doc["backup"] = change(doc["backup"])
    for table, keys in PATH_KEYS.items():
        found = doc.get(table)
        for t in (found if isinstance(found, list) else [found]) if keys else []:
            for key in keys:
                if isinstance(t, dict) and isinstance(t.get(key), str):
                    t[key] = change(t[key])


def _dump(doc: dict) -> str:
    """The cell document as TOML: its top-level values, its tables, its arrays of tables."""
    lines = [f"{k} = {_value(v)}" for k, v in doc.items() if not isinstance(v, (dict, list)) or
             (isinstance(v, list) and not any(isinstance(x, dict) for x in v))]
    for k, v in doc.items():
        if isinstance(v, dict):
            lines += ["", f"[{k}]"] + [f"{a} = {_value(b)}" for a, b in v.items()]
        elif isinstance(v, list) and any(isinstance(x, dict) for x in v):
            for t in v:
                lines += ["", f"[[{k}]]"] + [f"{a} = {_value(b)}" for a, b in t.items()]
    return "\n".join(lines) + "\n"


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(float(v)) if isinstance(v, float) else str(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    raise TypeError(f"a cell file holds no {type(v).__name__}")
