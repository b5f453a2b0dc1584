"""Loops with no closed form (spatial loops, five-bars, cylinders arranged otherwise) solved by a
damped Newton method on the loop-closure equations, with continuation: the active joints move from
zero (the assembled pose the spec defines) to their values in ``STEPS`` steps, each starting from
the last solution, so the solve stays on the branch of the zero position. Where the closing joint
cannot be reached (past a dead point) the residual stays large: the passive joints are NaN.
Near a singular pose two branches meet, and a path through one may come out on either: the sign of
the determinant of the closure's best-conditioned square part (chosen at zero) is tracked along
the path, and a configuration whose path makes it change sign or nearly vanish is NaN too, never a
pose on a branch rswarp cannot vouch for.

A loop is described by rows (``Chain.newton_rows``, laid out in ``rswarp.kernels.specs``): the joints
of path A (loop ancestor down to the closing joint's parent link), of path B (down to its child
link), and the closing joint. The closure: the closing joint's point and axis, carried by both
paths, coincide. Only revolute closing joints are taken. ``newton_loop_values`` is the host twin
(float64) of ``rswarp.kernels.loops``.
"""

from __future__ import annotations

import numpy as np

from ..kernels.specs import (
    CLOSING,
    CLOSURE_TOLERANCE,
    FINE_ITERATIONS,
    FINE_STEPS,
    ITERATIONS,
    MAX_STEP,
    MAX_UNKNOWNS,
    NEAR,
    PATH_A,
    PATH_B,
    POLISH,
    ROW,
    SINGULAR,
    STEPS,
    square_rows,
)


def newton_rows(graph, loop, first_unknown: int) -> tuple[np.ndarray, dict[int, int], str | None]:
    """(rows, {link index: unknown index}, None), or (empty, {}, why) for a loop this solver does
    not take: a prismatic closing joint, too many passive joints, or one whose active joints do not
    fix its passive ones, or cannot move it."""
    closing = loop.closing
    if not closing.revolute or closing.active:
        return np.zeros((0, ROW)), {}, "its closing joint is not a passive revolute joint"
    ancestor = graph.common_ancestor(closing)
    paths = [_path(graph, graph.index[end], ancestor) for end in (closing.parent, closing.child)]
    unknowns: dict[int, int] = {}
    rows = []
    for role, path in zip((PATH_A, PATH_B), paths):
        for k in path:
            j = graph.tree_joint[k]
            u = -1
            if not j.active:
                u = unknowns.setdefault(k, first_unknown + len(unknowns))
            rows.append(_row(role, j, graph.column(j.name), u))
    rows.append(_row(CLOSING, closing, -1, -1))
    rows = np.array(rows)
    m = len(unknowns)
    jac_u, jac_q = _zero_jacobians(rows, first_unknown, m) if m else (None, None)
    why = _mobility(jac_u, jac_q, m)
    if why:
        return np.zeros((0, ROW)), {}, why
    rows[-1, 11:] = _square_part(jac_u, m)
    return rows, unknowns, None


def _zero_jacobians(rows: np.ndarray, first: int, m: int) -> tuple[np.ndarray, np.ndarray]:
    """The closure's Jacobians at the zero position: in the loop's unknowns (6, m) and in the
    active joints (6, dof)."""
    dof = max(int(rows[:, 3].max()) + 1, 1)
    _, jac_u, jac_q = _closure(rows, np.zeros((1, dof)), np.zeros((1, first + m)), first, m)
    return jac_u[0], jac_q[0]


def _path(graph, link: int, ancestor: int) -> list[int]:
    """The links from just below ``ancestor`` down to ``link``, parents first."""
    out = []
    while link != ancestor:
        out.append(link)
        link = graph.parent[link]
    return out[::-1]


def _row(role: int, joint, column: int, unknown: int) -> list[float]:
    return [0, role, 0 if joint.revolute else 1, column, unknown, *joint.axis, *joint.point1, 0, 0]


def _square_part(jac_u: np.ndarray, m: int) -> tuple[int, float]:
    """(bit mask of the m residual rows whose square Jacobian is best conditioned at zero, its
    determinant there)."""
    from itertools import combinations

    pick = max(combinations(range(6), m), key=lambda r: abs(np.linalg.det(jac_u[list(r)])))
    return sum(1 << r for r in pick), float(np.linalg.det(jac_u[list(pick)]))


def _mobility(jac_u: np.ndarray | None, jac_q: np.ndarray | None, m: int) -> str | None:
    """Why the loop cannot be solved at the zero position, or None: its passive joints must be
    fixed by the closure (full column rank) and the active ones must be able to move it."""
    if m == 0:
        return "it has no passive joint to solve for"
    if m > MAX_UNKNOWNS:
        return f"it has {m} passive joints; the solver takes {MAX_UNKNOWNS} per loop"
    rank = np.linalg.matrix_rank(jac_u, tol=1e-9)
    if rank < m:
        return "the active joints do not fix its passive joints"
    if np.linalg.matrix_rank(np.concatenate([jac_u, jac_q], axis=1), tol=1e-9) > rank:
        return "its joints lock it: the active joints cannot move it"
    return None


def _rodrigues(axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotations about a unit axis by angles (N,)."""
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    c, s = np.cos(angle)[:, None, None], np.sin(angle)[:, None, None]
    return np.eye(3) + s * k + (1 - c) * (k @ k)


def _closure(rows: np.ndarray, q: np.ndarray, x: np.ndarray, first: int, m: int):
    """Residual (N, 6) of one loop at active values ``q`` and unknowns ``x``, its Jacobian in the
    loop's unknowns (N, 6, m) and in the active joints (N, 6, dof)."""
    n = len(q)
    closing = rows[rows[:, 1] == CLOSING][0]
    ends = []
    jac_u = np.zeros((n, 6, m))
    jac_q = np.zeros((n, 6, q.shape[1]))
    records = []
    for role in (PATH_A, PATH_B):
        rot, tra = np.tile(np.eye(3), (n, 1, 1)), np.zeros((n, 3))
        for row in rows[rows[:, 1] == role]:
            axis, point, col, u = row[5:8], row[8:11], int(row[3]), int(row[4])
            value = x[:, u] if u >= 0 else q[:, col] if col >= 0 else np.zeros(n)
            w, o = rot @ axis, np.einsum("nij,j->ni", rot, point) + tra
            records.append((role, row[2], col, u, w, o))
            if row[2] == 0:
                r = _rodrigues(axis, value)
                t = point - np.einsum("nij,j->ni", r, point)
            else:
                r, t = np.tile(np.eye(3), (n, 1, 1)), value[:, None] * axis
            rot, tra = rot @ r, np.einsum("nij,nj->ni", rot, t) + tra
        ends.append((np.einsum("nij,j->ni", rot, closing[8:11]) + tra, rot @ closing[5:8]))
    (xa, aa), (xb, ab) = ends
    for role, jtype, col, u, w, o in records:
        sign, end, ax = (1.0, xa, aa) if role == PATH_A else (-1.0, xb, ab)
        parts = [np.cross(w, end - o), np.cross(w, ax)] if jtype == 0 else [w, np.zeros_like(w)]
        column = np.concatenate(parts, axis=1)
        if u >= 0:
            jac_u[:, :, u - first] += sign * column
        elif col >= 0:
            jac_q[:, :, col] += sign * column
    return np.concatenate([xa - xb, aa - ab], axis=1), jac_u, jac_q


def newton_loop_values(rows: np.ndarray, q: np.ndarray, unknowns: int) -> np.ndarray:
    """(N, unknowns) passive values of every Newton-solved loop at ``q`` (N, dof), float64; NaN for the
    loop's joints where it cannot close."""
    q = np.atleast_2d(np.asarray(q, np.float64))
    x = np.zeros((len(q), unknowns))
    for lid in np.unique(rows[:, 0]):
        loop = rows[rows[:, 0] == lid]
        u = loop[:, 4][loop[:, 4] >= 0].astype(int)
        first, m = int(u.min()), int(u.max() - u.min() + 1)
        x[:, first:first + m] = _solve(loop, q, x, first, m)
    return x


def _solve(rows: np.ndarray, q: np.ndarray, x: np.ndarray, first: int, m: int) -> np.ndarray:
    """One loop's unknowns by continuation from zero and damped Newton steps; paths that come near
    a singular pose are taken again in fine steps, and NaN where they meet one."""
    out, ratio = _continue(rows, q, x, first, m, STEPS, ITERATIONS)
    near = ~(ratio >= NEAR)  # NaN too: a determinant the elimination could not take
    if near.any():
        out[near], ratio[near] = _continue(rows, q[near], x[near], first, m, FINE_STEPS, FINE_ITERATIONS)
    x = x.copy()
    x[:, first:first + m] = out
    e = _closure(rows, q, x, first, m)[0]
    out[(np.linalg.norm(e, axis=1) > CLOSURE_TOLERANCE) | ~(ratio >= SINGULAR)] = np.nan
    return out


def _continue(rows: np.ndarray, q: np.ndarray, x: np.ndarray, first: int, m: int, steps: int,
              iterations: int) -> tuple[np.ndarray, np.ndarray]:
    """(unknowns, the smallest determinant ratio of the square part along the path)."""
    x = x.copy()
    x[:, first:first + m] = 0.0
    square, det0 = square_rows(rows), rows[rows[:, 1] == CLOSING][0, 12]
    ratio = np.full(len(q), np.inf)
    plan = [(k + 1) / steps for k in range(steps) for _ in range(iterations)] + [1.0] * POLISH
    for s in plan:
        e, jac, _ = _closure(rows, s * q, x, first, m)
        ratio = np.minimum(ratio, np.linalg.det(jac[:, square]) / det0)
        jt = np.swapaxes(jac, 1, 2)
        normal = jt @ jac + 1e-12 * np.eye(m)
        step = -np.linalg.solve(normal, (jt @ e[..., None]))[..., 0]
        length = np.linalg.norm(step, axis=1, keepdims=True)
        x[:, first:first + m] += step * np.minimum(1.0, MAX_STEP / np.maximum(length, 1e-300))
    return x[:, first:first + m], ratio
