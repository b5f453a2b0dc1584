"""Random programs a robot could run: waypoints drawn within the limits that are free of the
robot's own links and of the floor, joined by joint moves whose every sample is free too, checked
with the collision kernels (``program_check``). Where a link clamps a cable, the clamp and the
cable's lead out of it count as part of the link (``hose_leads``): a move that drives another
link into them would press the cable against its clamp. A robot without link meshes checks only
the floor, against its joint and flange points. A cable run over them no longer drives the arm
through the floor, through itself, or into its own dress pack's clamps."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..kinematics.trajectory import WAYPOINT_SPAN, Trajectory, joint_speed_limits
from ..options import checked
from .bodies import hose_leads
from .cable.solver import CableOptions, allowed_bend_radius
from .program_check import ProgramTools, checked_pairs, lowest, program_tools

CANDIDATES = 8  # waypoints drawn at once; the first whose move is free is taken
ROUNDS = 8  # draws before the robot holds where it is for HOLD seconds
HOLD = 0.5
STEP = np.radians(2.0)  # the largest joint step between two checked samples of a move
PADDING = 0.01  # m: links closer than this count as touching, for what passes between samples
FLOOR_MARGIN = 0.02  # m: every point of the robot stays this far above the floor


def free(tools: ProgramTools, pairs: np.ndarray | None, q: np.ndarray, floor: float) -> np.ndarray:
    """(N,) whether each configuration is clear of the robot's own links and of the floor (its
    lowest point at least ``floor``: a height, not the floor itself)."""
    ok = lowest(tools, q) >= floor
    if tools.checker is not None and pairs is not None and ok.any():
        hit, _ = tools.checker.verdicts(q[ok])
        ok[ok] = ~(hit & pairs).any(axis=1)
    return ok


def _free_moves(tools, pairs, start: np.ndarray, ends: np.ndarray, floor: float) -> np.ndarray:
    """(K,) whether each joint move from ``start`` to ``ends[k]`` is free at every sample."""
    n = int(np.ceil(np.max(np.abs(ends - start)) / STEP)) + 1
    s = np.linspace(0.0, 1.0, n + 1)[1:]
    q = start + s[None, :, None] * (ends - start)[:, None, :]
    return free(tools, pairs, q.reshape(-1, len(start)), floor).reshape(len(ends), n).all(axis=1)


def random_program(mech, seconds: float, seed: int, floor: float = 0.0, tools: ProgramTools | None = None,
                   pairs: np.ndarray | None = None) -> Trajectory:
    """Smooth random motion whose waypoints and moves are all free (``random_trajectory``'s moves
    and speeds otherwise): no link lower than ``floor`` + ``FLOOR_MARGIN`` (or than at home);
    reproducible for ``seed``."""
    checked("seconds", seconds)
    if not mech.dof:
        return Trajectory(f"random program (seed {seed})", np.array([0.0, seconds]), np.zeros((2, 0)), smooth=True)
    lower, upper = mech.bounds()
    if not (np.all(np.isfinite(lower)) and np.all(np.isfinite(upper))):
        raise InputError("every active joint needs finite limits for a random program")
    if tools is None:
        tools, pairs = _tools(mech, CableOptions())
    vmax = joint_speed_limits(mech)
    rng = np.random.default_rng([seed, 0xCAB1E, 1])
    home = np.clip(mech.home_position(), lower, upper)
    # the floor margin, or as low as the robot already is at home (a model placed on the floor)
    floor = min(floor + FLOOR_MARGIN, float(lowest(tools, home[None])[0]) - 1e-9)
    knots_t, knots_q = [0.0], [home]
    while knots_t[-1] < seconds:
        here = knots_q[-1]
        nxt = None
        for _ in range(ROUNDS):
            step = rng.uniform(-1, 1, (CANDIDATES, len(lower))) * WAYPOINT_SPAN * (upper - lower)
            ends = np.clip(here + step, lower, upper)
            ok = free(tools, pairs, ends, floor)
            if ok.any():
                good = ends[ok]
                moves = _free_moves(tools, pairs, here, good, floor)
                if moves.any():
                    nxt = good[np.argmax(moves)]
                    break
        if nxt is None:  # boxed in: hold, then draw again
            knots_t.append(knots_t[-1] + HOLD)
            knots_q.append(here)
            continue
        duration = max(float(np.max(1.875 * np.abs(nxt - here) / vmax)), 0.2)
        knots_t.append(knots_t[-1] + duration)
        knots_q.append(nxt)
    return Trajectory(f"random program (seed {seed})", np.array(knots_t), np.array(knots_q), smooth=True,
                      until=float(seconds))


def _tools(mech, options: CableOptions) -> tuple[ProgramTools, np.ndarray | None]:
    """The checks' kernels, the cables' clamps and leads (at ``options``' allowed bend radius)
    among the bodies, and the pairs checked."""
    tools = program_tools(mech, (), padding=PADDING, leads=hose_leads(mech, lambda c: allowed_bend_radius(c, options)),
                          tool=options.tool)
    return tools, checked_pairs(mech, tools)


def random_programs(mech, envs: int, seconds: float, seed: int, floor: float = 0.0,
                    options: CableOptions = CableOptions()) -> list[Trajectory]:
    """One random program per environment, from seeds ``seed``, ``seed + 1``, ...; the kernels
    built once for all; cable clamps' leads as long as ``options``' allowed bend radius makes them."""
    tools, pairs = _tools(mech, options)
    return [random_program(mech, seconds, seed + e, floor, tools, pairs) for e in range(envs)]
