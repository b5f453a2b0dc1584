"""``rswarp reach ROBOT_OR_CELL PART@x,y,z --out DIR``: a reach study in REACH's sense, for the base
where it stands: every face centre of the part is a target, approached along its normal (the
tool's z against the face), the tool spun about it every ``--spin`` degrees; each solved in one
batch (every closed-form branch), scored where it is reached: Yoshikawa's manipulability
(sqrt det J J^T, of the best configuration) and its distance to the joint limits. The fraction of
points reached, and the points as ``points.csv``, a coloured ``part.ply`` a CAD viewer opens and a
top-view ``points.png``."""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

import numpy as np

from ...config import BatchOptions, TaskOptions, routed
from ...errors import InputError
from ...geometry.meshes import file_mesh
from ...kinematics.ik import OK, ArmConstants
from ...kinematics.kinematics import Kinematics
from ...motion.cells import robot_of, tool_spec
from ...motion.tcp import rigid_inverse
from ...outputs import atomic_folder, check_replaceable
from ...sim.bodies import placed_environments
from ...sim.tool import load_tool
from ..output import Output, Warn, ignore, json_safe

MAX_POINTS = 200_000  # faces of a part studied at once
CLEAR_DEG = 30.0  # a configuration this far from every joint limit scores in full


def run_reach(path: str, part: str, task: TaskOptions | None = None, batch: BatchOptions | None = None, *,
              spin: float = 90.0, out: str = "rswarp-reach", warn: Warn = ignore, **changes) -> Output:
    """``rswarp reach``: the part (``MESH@x,y,z`` in the world, the robot file's length unit) studied
    at the robot's base, the tool (``--tool``, its TCP from its RSXML; the flange for a mesh)."""
    o = routed(changes, task=task or TaskOptions(), batch=batch or BatchOptions())
    task, batch = o["task"], o["batch"]
    if not (isinstance(spin, (int, float)) and 1.0 <= spin <= 360.0):
        raise InputError(f"--spin must be 1 to 360 degrees, not {spin}")
    check_replaceable(Path(out))
    mech, cell = robot_of(path)
    if cell is not None and (cell.team or cell.carrier is not None):
        raise InputError(f"{path}: a reach study is of one robot standing on the floor")
    placed = placed_environments(mech, [part])[0]
    try:
        mesh = file_mesh(mech, Path(placed.path), placed.pose)
    except (ValueError, OSError) as exc:
        raise InputError(f"{placed.path}: {exc}") from None
    if not 0 < len(mesh.faces) <= MAX_POINTS:
        raise InputError(f"{placed.path}: {len(mesh.faces)} faces: a part of 1 to {MAX_POINTS} faces, please")
    tool = load_tool(mech, tool_spec(cell, task.tool))
    base = cell.robot.frame if cell is not None else (mech.base_frame.matrix() if mech.base_frame else np.eye(4))
    kin = Kinematics(mech, batch.device)
    if not isinstance(kin._ik_form(), ArmConstants):
        raise InputError(f"'{mech.name}' is not a 6-axis arm with a spherical wrist: the study solves its closed form")
    spins = np.radians(np.arange(0.0, 360.0 - 1e-9, spin))
    tcp = tool.tcp if tool is not None and tool.tcp is not None else np.eye(4)
    centres, normals = mesh.triangles_center, mesh.face_normals
    scores = _study(kin, rigid_inverse(base[None])[0], centres, normals, spins, tcp)
    scores["score"] = _score(scores)  # what every output shows, made once
    with atomic_folder(out) as tmp:
        (tmp / "points.csv").write_text(_points_csv(centres, normals, scores))
        mesh.visual = _coloured(mesh, scores)
        (tmp / "part.ply").write_bytes(mesh.export(file_type="ply"))
        (tmp / "points.png").write_bytes(_png(centres, scores, base, f"{mech.name}: {Path(placed.path).name}"))
    doc = _document(path, placed.path, out, scores, len(spins), tool)
    return Output(json_safe(doc), _text(doc))


def _study(kin, to_base: np.ndarray, centres, normals, spins, tcp) -> dict:
    """Per point: spins reached, and of the best configuration its manipulability and its least
    distance to a joint limit (degrees)."""
    frames = _approaches(centres, normals, spins)  # (F, S, 4, 4) TCP poses in the world
    f, s = frames.shape[:2]
    flanges = to_base @ frames.reshape(-1, 4, 4) @ rigid_inverse(tcp[None])[0]
    sol = kin.ik64(flanges)
    lo, hi = kin.mech.bounds()
    good = sol.status == OK
    with np.errstate(invalid="ignore"):
        margin = np.where(good, np.min(np.minimum(sol.q - lo, hi - sol.q), axis=2), -np.inf)
    best = np.argmax(margin, axis=1)
    rows = np.arange(len(best))
    ok = good[rows, best]
    q = sol.q[rows, best]
    manip = np.full(len(q), np.nan)
    manip[ok] = manipulability(kin, q[ok])
    margin_deg = np.where(ok, np.degrees(margin[rows, best]), np.nan)
    return {"reached": ok.reshape(f, s).sum(axis=1), "manipulability": _nanmax(manip.reshape(f, s)),
            "limit_deg": _nanmax(margin_deg.reshape(f, s))}


def _nanmax(v: np.ndarray) -> np.ndarray:
    """The greatest of each row, NaN for a row of NaN (a point no spin reaches)."""
    top = np.where(np.isnan(v), -np.inf, v).max(axis=1)
    return np.where(np.isinf(top), np.nan, top)


def _approaches(centres: np.ndarray, normals: np.ndarray, spins: np.ndarray) -> np.ndarray:
    """(F, S, 4, 4): at each face centre the tool's z against the normal, spun about it."""
    z = -normals
    helper = np.where(np.abs(z[:, 2:3]) < 0.9, np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0]))
    x = np.cross(helper, z)
    x /= np.linalg.norm(x, axis=1, keepdims=True)
    y = np.cross(z, x)
    c, s = np.cos(spins)[None, :, None], np.sin(spins)[None, :, None]
    xs, ys = c * x[:, None] + s * y[:, None], -s * x[:, None] + c * y[:, None]
    out = np.zeros((len(centres), len(spins), 4, 4))
    out[..., :3, 0], out[..., :3, 1], out[..., :3, 2] = xs, ys, np.broadcast_to(z[:, None], xs.shape)
    out[..., :3, 3], out[..., 3, 3] = centres[:, None], 1.0
    return out


def manipulability(kin, q: np.ndarray, h: float = 1e-6) -> np.ndarray:
    """Yoshikawa's measure sqrt(det J J^T) of configurations q (N, 6), J the flange's geometric
    Jacobian (m/rad and rad/rad) by central differences of the forward kinematics."""
    if not len(q):
        return np.zeros(0)
    link, off = kin.flange_frame()
    n, dof = q.shape
    steps = np.repeat(q[:, None], 2 * dof, axis=1)
    for k in range(dof):
        steps[:, 2 * k, k] += h
        steps[:, 2 * k + 1, k] -= h
    f = kin.fk64(steps.reshape(-1, dof))[:, link] @ off
    f = f.reshape(n, dof, 2, 4, 4)
    lin = (f[:, :, 0, :3, 3] - f[:, :, 1, :3, 3]) / (2 * h)
    turn = f[:, :, 0, :3, :3] @ np.swapaxes(f[:, :, 1, :3, :3], -1, -2)  # R(q+h) R(q-h)^T
    ang = np.stack([turn[..., 2, 1] - turn[..., 1, 2], turn[..., 0, 2] - turn[..., 2, 0],
                    turn[..., 1, 0] - turn[..., 0, 1]], axis=-1) / (4 * h)
    jac = np.concatenate([lin, ang], axis=-1).swapaxes(1, 2)  # (N, 6, dof)
    return np.sqrt(np.maximum(np.linalg.det(jac @ np.swapaxes(jac, 1, 2)), 0.0))


def _score(scores: dict) -> np.ndarray:
    """Per point 0 .. 1: its manipulability over the part's best, times its joint-limit margin over
    ``CLEAR_DEG`` (capped at 1); 0 where no spin reaches it."""
    m = np.nan_to_num(scores["manipulability"], nan=0.0)
    top = m.max() if m.size and m.max() > 0 else 1.0
    return np.where(scores["reached"] > 0, m / top * np.clip(np.nan_to_num(scores["limit_deg"]) / CLEAR_DEG, 0, 1), 0)


def _points_csv(centres, normals, scores) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["face", "x_mm", "y_mm", "z_mm", "nx", "ny", "nz", "spins_reached", "manipulability", "limit_deg",
                "score"])
    score = scores["score"]
    for k in range(len(centres)):
        m, d = scores["manipulability"][k], scores["limit_deg"][k]
        w.writerow([k, *(f"{1000 * v:.2f}" for v in centres[k]), *(f"{v:.5f}" for v in normals[k]),
                    int(scores["reached"][k]), "" if math.isnan(m) else f"{m:.6f}", "" if math.isnan(d) else f"{d:.2f}",
                    f"{score[k]:.4f}"])
    return buf.getvalue()


def _coloured(mesh, scores):
    """Face colours: red where no spin reaches a point, else from yellow (a low score) to green."""
    import trimesh

    s = scores["score"]
    colours = np.zeros((len(s), 4), np.uint8)
    colours[:, 3] = 255
    colours[:, 0] = np.where(scores["reached"] > 0, (255 * (1 - s)).astype(np.uint8), 220)
    colours[:, 1] = np.where(scores["reached"] > 0, 200, 30)
    colours[:, 2] = 30
    return trimesh.visual.ColorVisuals(mesh, face_colors=colours)


def _png(centres, scores, base, title: str) -> bytes:
    from ..figures import figure_png

    s = scores["score"]
    reached = scores["reached"] > 0

    def draw(ax):
        ax.scatter(1000 * centres[~reached, 0], 1000 * centres[~reached, 1], s=6, c="tab:red", label="not reached")
        art = ax.scatter(1000 * centres[reached, 0], 1000 * centres[reached, 1], s=6, c=s[reached], cmap="viridis",
                         vmin=0.0, vmax=1.0, label="reached (score)")
        ax.figure.colorbar(art, ax=ax, label="score")
        ax.scatter([1000 * base[0, 3]], [1000 * base[1, 3]], marker="x", c="k", s=60, label="the robot's base")
        ax.set_aspect("equal", adjustable="datalim")

    return figure_png(draw, title, "x [mm]", "y [mm]")


def _document(path, part, out, scores, spins: int, tool) -> dict:
    reached = scores["reached"] > 0
    score = scores["score"]
    return {"path": path, "part": part, "out": out, "points": int(len(reached)), "spins": spins,
            "reached": int(reached.sum()), "fraction": float(reached.mean()),
            "mean_score": float(score[reached].mean()) if reached.any() else 0.0,
            "tcp": "the tool's TCP" if tool is not None and tool.tcp is not None else "the flange (tool0)"}


def _text(doc: dict) -> str:
    return (f"{doc['path']}: {doc['reached']} of {doc['points']} points of {Path(doc['part']).name} reached "
            f"({100 * doc['fraction']:.1f} %; {doc['spins']} spins each, {doc['tcp']} against the face), mean score "
            f"{doc['mean_score']:.3f}\nfiles: {doc['out']}/points.csv, part.ply, points.png")


def reach(path: str, part: str, *, out: str = "rswarp-reach", **changes) -> dict:
    """``rswarp.reach``: ``run_reach`` from Python; the study as data (``--json``'s)."""
    return run_reach(path, part, out=str(out), **changes).doc
