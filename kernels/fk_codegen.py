"""Warp kernels specialized to one mechanism: the chain unrolled, axes and points as constants,
zero terms of each joint's rotation dropped, link poses kept in registers instead of a scratch
array. On a CPU this is several times faster than the generic tree walk of ``rswarp.kernels.fk``.
It takes the same plain arrays as that kernel (parent, joint type, q column, axis, point per link,
links in topological order).

The source is written to a per-user cache folder named by its hash and imported from there (Warp
needs a real source file); Warp then compiles it once and caches the binary by the same content.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import sys
from pathlib import Path
from typing import NamedTuple

import numpy as np

REVOLUTE, PRISMATIC = 0, 1  # joint types, as in rswarp.kernels.fk
ZERO = 1e-15


def _lit(x: float) -> str:
    return repr(float(x))


def _sum(terms: list[tuple[float, str]], const: float = 0.0) -> str:
    """``const + sum(coef * expr)`` as Warp source, leaving out zero terms and unit factors."""
    parts = [] if abs(const) < ZERO else [_lit(const)]
    for coef, expr in terms:
        if abs(coef) < ZERO:
            continue
        if expr == "1":
            parts.append(_lit(coef))
        elif coef == 1.0:
            parts.append(expr)
        elif coef == -1.0:
            parts.append(f"(-{expr})")
        else:
            parts.append(f"{_lit(coef)} * {expr}")
    return " + ".join(parts) if parts else "0.0"


def _joint(k: int, jtype: int, axis: np.ndarray, point: np.ndarray, col: int) -> list[str]:
    """Source lines defining ``rj{k}`` (mat33) and ``tj{k}`` (vec3) for link k's joint."""
    th = f"q[i, {col}]" if col >= 0 else "0.0"
    if jtype == REVOLUTE:
        a = axis
        skew = [[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]]
        # Rodrigues as R = a a^T + (I - a a^T) c + K s: each entry a constant plus c and s terms
        rc = {(i, j): ((1.0 if i == j else 0.0) - a[i] * a[j]) for i in range(3) for j in range(3)}
        r = [[_sum([(rc[i, j], "c"), (skew[i][j], "s")], a[i] * a[j]) for j in range(3)] for i in range(3)]
        # t = p - R p, collected the same way
        t = [_sum([(-sum(rc[i, j] * point[j] for j in range(3)), "c"), (-sum(skew[i][j] * point[j] for j in range(3)), "s")],
                  point[i] - sum(a[i] * a[j] * point[j] for j in range(3))) for i in range(3)]
        return [f"    th{k} = {th}", f"    s = wp.sin(th{k})", f"    c = wp.cos(th{k})",
                f"    rj{k} = wp.mat33({', '.join(x for row in r for x in row)})",
                f"    tj{k} = wp.vec3({', '.join(t)})"]
    if jtype == PRISMATIC:
        return [f"    th{k} = {th}", f"    rj{k} = wp.identity(n=3, dtype=float)",
                f"    tj{k} = wp.vec3({', '.join(_sum([(a, f'th{k}')]) for a in axis)})"]
    return [f"    rj{k} = wp.identity(n=3, dtype=float)", f"    tj{k} = wp.vec3(0.0, 0.0, 0.0)"]


def _chain(tree: "Tree", needed: set[int]) -> list[str]:
    """Lines computing ``r{k}``, ``t{k}`` (world pose) for every link in ``needed`` and its ancestors."""
    keep = set()
    for k in needed:
        while k >= 0 and k not in keep:
            keep.add(k)
            k = int(tree.parent[k])
    lines = []
    for k in range(len(tree.parent)):
        if k not in keep:
            continue
        p = int(tree.parent[k])
        if p < 0:
            lines += [f"    r{k} = wp.identity(n=3, dtype=float)", f"    t{k} = wp.vec3(0.0, 0.0, 0.0)"]
            continue
        lines += _joint(k, int(tree.jtype[k]), tree.axis[k], tree.point[k], int(tree.qidx[k]))
        if tree.parent[p] < 0:  # parent is the base: identity, nothing to compose
            lines += [f"    r{k} = rj{k}", f"    t{k} = tj{k}"]
        else:
            lines += [f"    r{k} = r{p} * rj{k}", f"    t{k} = r{p} * tj{k} + t{p}"]
    return lines


def _store(out: str, r: str, t: str) -> str:
    return (f"    {out} = wp.mat44({r}[0, 0], {r}[0, 1], {r}[0, 2], {t}[0], {r}[1, 0], {r}[1, 1], {r}[1, 2], {t}[1], "
            f"{r}[2, 0], {r}[2, 1], {r}[2, 2], {t}[2], 0.0, 0.0, 0.0, 1.0)")


def _mat(m: np.ndarray) -> str:
    return f"wp.mat33({', '.join(_lit(v) for v in m[:3, :3].flatten())})"


def _vec(v) -> str:
    return f"wp.vec3({', '.join(_lit(x) for x in v)})"


class Tree(NamedTuple):
    """The plain arrays of a link tree (see ``rswarp.compile.KinematicTree``)."""

    parent: np.ndarray
    jtype: np.ndarray
    qidx: np.ndarray
    axis: np.ndarray
    point: np.ndarray


def source(tree: Tree, flanges: list[tuple[int, np.ndarray]],
           wrist: tuple[tuple[int, np.ndarray, np.ndarray], tuple[int, np.ndarray, np.ndarray]] | None,
           slots: list[int] | None = None) -> str:
    """The module's source: ``fk_all`` (every link; link k is written to column ``slots[k]``), and
    per flange (link index, 4x4 offset) ``fk_flange{f}`` and ``wrist_flange{f}`` (wrist centre from
    J4 and J5, given as parent link, point and axis; None below five axes)."""
    n = len(tree.parent)
    slots = list(range(n)) if slots is None else [int(s) for s in slots]
    out = ['"""Generated by rswarp.codegen for one mechanism; do not edit."""', "", "import warp as wp", "",
           'wp.set_module_options({"enable_backward": False})', ""]
    out += ["", "@wp.kernel", "def fk_all(q: wp.array2d(dtype=wp.float32), out: wp.array2d(dtype=wp.mat44)):",
            "    i = wp.tid()"]
    out += _chain(tree, set(range(n)))
    out += [_store(f"out[i, {slots[k]}]", f"r{k}", f"t{k}") for k in range(n)]
    for f, (link, m) in enumerate(flanges):
        out += ["", "", "@wp.kernel", f"def fk_flange{f}(q: wp.array2d(dtype=wp.float32), out: wp.array(dtype=wp.mat44)):",
                "    i = wp.tid()"]
        out += _chain(tree, {link})
        out += [f"    rf = r{link} * {_mat(m)}", f"    tf = r{link} * {_vec(m[:3, 3])} + t{link}", _store("out[i]", "rf", "tf")]
    for f, (link, m) in enumerate(flanges):
        out += ["", "", "@wp.kernel", f"def wrist_flange{f}(q: wp.array2d(dtype=wp.float32), wrist: wp.array(dtype=wp.vec3),",
                "                  flange: wp.array(dtype=wp.vec3)):", "    i = wp.tid()"]
        need = {link} | ({wrist[0][0], wrist[1][0]} if wrist else set())
        out += _chain(tree, need)
        out += [f"    flange[i] = r{link} * {_vec(m[:3, 3])} + t{link}"]
        if not wrist:
            out += ["    wrist[i] = wp.vec3(0.0, 0.0, 0.0)  # below five axes there is no wrist centre"]
            continue
        (l4, p4, a4), (l5, p5, a5) = wrist
        # the point of the J5 axis nearest the J4 axis (the wrist centre); parallel axes: J5's anchor
        out += [f"    p4 = r{l4} * {_vec(p4)} + t{l4}", f"    d4 = r{l4} * {_vec(a4)}",
                f"    p5 = r{l5} * {_vec(p5)} + t{l5}", f"    d5 = r{l5} * {_vec(a5)}",
                "    w = p5 - p4", "    b = wp.dot(d4, d5)", "    den = 1.0 - b * b",
                "    if den < 1.0e-12:", "        wrist[i] = p5", "    else:",
                "        wrist[i] = p5 + ((b * wp.dot(w, d4) - wp.dot(w, d5)) / den) * d5"]
    return "\n".join(out) + "\n"


def cache_dir() -> Path:
    """$RSWARP_CACHE, else ~/.cache/rswarp; a temporary folder when neither can be written."""
    base = os.environ.get("RSWARP_CACHE") or os.path.join(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache"), "rswarp")
    folder = Path(base) / "kernels"
    try:
        folder.mkdir(parents=True, exist_ok=True)
        if os.access(folder, os.W_OK):
            return folder
    except OSError:
        pass
    import tempfile

    return Path(tempfile.gettempdir()) / f"rswarp-{os.getuid() if hasattr(os, 'getuid') else 'user'}" / "kernels"


def load(src: str):
    """Import generated source as a module (written once into the cache folder, by hash)."""
    digest = hashlib.sha256(src.encode()).hexdigest()[:16]
    name = f"rswarp_fk_{digest}"
    if name in sys.modules:
        return sys.modules[name]
    folder = cache_dir()
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{name}.py"
    if not path.exists() or path.read_text() != src:
        tmp = folder / f".{name}.{os.getpid()}.tmp"
        tmp.write_text(src)
        os.replace(tmp, path)
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module
