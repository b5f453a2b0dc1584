"""Cable dynamics: our Cosserat rod against Newton's rod (``add_rod``, ``SolverVBD``), MuJoCo's
cable plugin and PyElastica, in one process: a hanging hose, a cantilever and a twisted rod.

The hose: span 1 m, length 1.2 m, radius 2.5 cm, E 5e7 Pa, density 1200 kg/m^3, both ends pinned
at one height; 20 and 40 segments; 1, 64 and 256 environments. Figures:

- CPU-seconds per simulated second per environment (process CPU time over the timed window, all
  threads, Python's garbage collector held off as ``timeit`` does, for every simulator), after a
  settling run that is not timed. Ours runs on one thread, as Newton's Warp launches do on the
  CPU (equal threads: the ratio's); on every core too (``rswarp*``), where two threads sharing
  the machine cost more CPU time each;
- sag error against the inextensible catenary, and shape error (RMS of the height along the arc,
  relative to the sag) against a converged reference: the inextensible elastica with pinned ends
  under its weight, solved by SciPy's ``solve_bvp``. With this stiffness (bending length
  (EI/w)^(1/3) = 0.87 m) the hose sags less than the catenary, so the shape error is the fair
  accuracy figure.

Each peer is stepped the way its examples do: Newton at 1.67 ms steps with 5 VBD iterations and
its end segments kinematic, and again at equal accuracy: the cheapest step and iteration count
(work per simulated second, iterations / step) whose shape error, on one environment after the
same settling, is no more than ours, of every count from 1 to 20 iterations at steps of 16.7,
8.3, 4.2 and 1.7 ms, cheapest first (a grid of 5, 10 and 20 iterations alone skipped VBD's
cheaper counts). MuJoCo at 0.5 ms (it is reported to go NaN at 1 ms), implicitfast, one MjData
per environment (its cost is per environment; 64 and 256 are timed as 4 environments and
scaled, said in the table). Ours: 60 frames per second of 4 substeps and at most 2 Gauss-Newton
iterations each, the run's defaults.

Last, the issue's target: the bundled IRB 2600ID's hose, 256 environments x 10 s of random motion,
through ``simulate_cables`` (``--whole-run`` measures only this).

The ratio's row (20 segments, 256 environments) is timed again after the table, ours and the
cheaper Newton setting each settled once and then timed in each of three rounds, once a round in
turn, each one's best kept (single windows of the same day have differed by a fifth).

Usage: python benchmarks/bench_cable.py [--quick] [--whole-run]. Ends with a JSON line: the ratio is the best
peer's CPU cost over ours at 20 segments and 256 environments, from the alternated rounds.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

import numpy as np
from limits import alternated, copy_rate, held_gc
from scipy.integrate import solve_bvp
from scipy.optimize import brentq

SPAN, LENGTH, RADIUS, E, RHO, G = 1.0, 1.2, 0.025, 5e7, 1200.0, 9.81
W = RHO * G * np.pi * RADIUS ** 2  # N/m
EI = E * np.pi * RADIUS ** 4 / 4
HEIGHT = 1.0


def catenary_sag() -> float:
    c = brentq(lambda a: 2 * a * np.sinh(SPAN / 2 / a) - LENGTH, 0.05, 10.0)
    return c * (np.cosh(SPAN / 2 / c) - 1)


def elastica() -> tuple[np.ndarray, np.ndarray]:
    """The pinned inextensible elastica under its weight: (arc samples, (n, 2) x and z)."""
    s = np.linspace(0.0, LENGTH, 401)
    sag = catenary_sag()
    guess = np.zeros((6, len(s)))
    guess[0] = s / LENGTH * SPAN
    guess[1] = -4 * sag * (s / LENGTH) * (1 - s / LENGTH)
    guess[2] = np.arctan2(np.gradient(guess[1], s), np.gradient(guess[0], s))
    guess[4], guess[5] = -W * LENGTH, -W * LENGTH / 2 + W * s  # rough internal forces

    def ode(_, y):  # x, z, theta, m, nx, nz: force n on the part before s, moment m = EI theta'
        x, z, th, m, nx, nz = y
        return np.vstack([np.cos(th), np.sin(th), m / EI, -(np.cos(th) * nz - np.sin(th) * nx),
                          np.zeros_like(x), np.full_like(x, W)])

    def bc(a, b):
        return np.array([a[0], a[1], a[3], b[0] - SPAN, b[1], b[3]])

    sol = solve_bvp(ode, bc, s, guess, tol=1e-8, max_nodes=100000)
    if not sol.success:
        raise RuntimeError(f"reference elastica: {sol.message}")
    y = sol.sol(s)
    return s, np.stack([y[0], y[1] + HEIGHT], axis=1)


def accuracy(points: np.ndarray, ref: tuple[np.ndarray, np.ndarray]) -> tuple[float, float]:
    """(sag error against the catenary, RMS height error against the reference / its sag)."""
    s_ref, xz = ref
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    arc *= LENGTH / arc[-1]
    z_ref = np.interp(arc, s_ref, xz[:, 1])
    sag = HEIGHT - points[:, 2].min()
    ref_sag = HEIGHT - xz[:, 1].min()
    return sag / catenary_sag() - 1, float(np.sqrt(np.mean((points[:, 2] - z_ref) ** 2)) / ref_sag)


def initial_points(ref, segments: int) -> np.ndarray:
    s_ref, xz = ref
    s = np.linspace(0.0, LENGTH, segments + 1)
    return np.stack([np.interp(s, s_ref, xz[:, 0]), np.zeros_like(s), np.interp(s, s_ref, xz[:, 1])], axis=1)


# -- ours -------------------------------------------------------------------------------------------


def _rod(xml: str, **options):
    """Our Cosserat rod solver for one RSXML text (``CableOptions`` given)."""
    import rswarp
    from rswarp.sim.cable.rod import CosseratRod
    from rswarp.sim.cable.solver import CableOptions

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "bench.rsxml"
        path.write_text(xml)
        mech = rswarp.load(path)
    return CosseratRod(mech, CableOptions(**options))


def _steps(solver, state, seconds: float, joints=lambda t: ()) -> float:
    """Frames of ``seconds``; the CPU seconds they took."""
    from rswarp.config import FRAME_RATE

    envs, subs, frame = state.x.shape[0], solver.options.substeps, 1 / FRAME_RATE
    with held_gc():
        cpu = time.process_time()
        for f in range(int(round(seconds * FRAME_RATE))):
            t = (f + (np.arange(subs) + 1) / subs) * frame
            q = np.array([[joints(u) for u in t]] * envs, np.float64).reshape(envs, subs, solver.dof)
            solver.step(state, q, frame)
        return time.process_time() - cpu


def _cable(name: str, radius: float, seg: float, youngs: float, points: str, length: float | None = None,
           joints: str = "", links: str = "", limits: str = "") -> str:
    extra = f' desiredLength="{length * 1000}"' if length else ""
    return f"""<?xml version="1.0"?>
<Mechanism xmlns="urn:abb-robotics-robotstudio-graphiccomponent" type="Other" name="{name}" lengthUnit="mm"
           angleUnit="deg">
  <Links baseLink="Base"><Part name="Base"/>{links}</Links>
  <AdditionalComponents>
    <Cable radius="{radius * 1000}" maxSegmentLength="{seg * 1000 + 1e-6}" name="Rod"{extra} youngsModulus="{youngs}">
      <ControlPoints>{points}</ControlPoints>
    </Cable>
  </AdditionalComponents>
  <Joints>{joints}</Joints>
  {limits}
</Mechanism>"""


def ours(segments: int, envs: int, settle: float, timed: float, ref, threads: int | None = 1) -> dict:
    """The hanging hose, from its rest route (the peers start from the reference shape); on one
    thread, as Newton's Warp launches run on the CPU, or on ``threads`` (None: every core)."""
    solver, state = _ours_settled(segments, envs, settle, threads)
    return _ours_row(solver, state, _steps(solver, state, timed) / timed / envs, ref)


def _ours_settled(segments: int, envs: int, settle: float, threads: int | None):
    """(solver, state): our hanging hose in ``envs`` environments after ``settle`` seconds."""
    points = (f'<ControlPoint attachedTo="Base" position="0, 0, {HEIGHT * 1000}"/>'
              f'<ControlPoint attachedTo="Base" position="{SPAN * 1000}, 0, {HEIGHT * 1000}"/>')
    solver = _rod(_cable("Hose", RADIUS, LENGTH / segments, E, points, LENGTH), damping=1.0, floor=None,
                  threads=threads)
    assert solver.layout.cables[0].segments == segments
    state = solver.state(envs)
    _steps(solver, state, settle)
    return solver, state


def _ours_row(solver, state, cost: float, ref) -> dict:
    """The table's entry of our settled hose at ``cost`` CPU-s per simulated second per environment."""
    sag, shape = accuracy(solver.points(state, 0, 0), ref)
    return {"cpu": cost, "sag": sag, "shape": shape, "step": f"{1e3 / 60 / solver.options.substeps:.2f} ms"}


# -- Newton -----------------------------------------------------------------------------------------


def newton_rod(segments: int, envs: int, settle: float, timed: float, ref, dt: float = 1 / 600,
               iterations: int = 5) -> dict:
    window, row = _newton_settled(segments, envs, settle, ref, dt, iterations)
    return row(window(timed) / timed / envs)


def _newton_settled(segments: int, envs: int, settle: float, ref, dt: float, iterations: int):
    """(window, row): Newton's rod in ``envs`` worlds after ``settle`` seconds; ``window(s)`` the CPU
    seconds of ``s`` more, ``row(cost)`` the table's entry at that cost."""
    import newton
    import warp as wp

    pts = initial_points(ref, segments)
    one = newton.ModelBuilder()
    cfg = one.default_shape_cfg.copy()
    cfg.density = RHO
    rod = newton.Rod([wp.vec3(*p) for p in pts], radius=RADIUS, youngs_modulus=E, poissons_ratio=0.49,
                     rest_straight=True)
    bodies, _ = one.add_rod(rod=rod, cfg=cfg, body_frame_origin="start", wrap_in_articulation=True)
    for b in (bodies[0], bodies[-1]):
        one.body_mass[b] = 0.0
        one.body_inv_mass[b] = 0.0
    builder = newton.ModelBuilder()
    for _ in range(envs):
        builder.add_world(one)
    builder.color(balance_colors=False)
    model = builder.finalize(device="cpu")
    solver = newton.solvers.SolverVBD(model, iterations=iterations)
    s0, s1, control = model.state(), model.state(), model.control()

    def run(seconds: float):
        nonlocal s0, s1
        for _ in range(int(round(seconds / dt))):
            s0.clear_forces()
            solver.step(s0, s1, control, None, dt)
            s0, s1 = s1, s0

    def window(seconds: float) -> float:
        with held_gc():
            cpu = time.process_time()
            run(seconds)
            return time.process_time() - cpu

    def row(cost: float) -> dict:
        q = s0.body_q.numpy()[: len(bodies), :3]
        nodes = np.vstack([q, pts[-1]])  # body origins are segment starts; the last node is held
        sag, shape = accuracy(nodes, ref)
        return {"cpu": cost, "sag": sag, "shape": shape, "step": f"{1e3 * dt:.2f} ms"}

    run(settle)
    return window, row


NEWTON_GRID = [(dt, it) for dt in (1 / 60, 1 / 120, 1 / 240, 1 / 600) for it in range(1, 21)]


ROUNDS = 3  # the ratio's row: ours and Newton timed once a round in turn, each one's best kept


def ratio_rounds(segments: int, envs: int, settle: float, timed: float, ref, newton: tuple[float, int]):
    """The ratio's row again, as ``bench_collisions`` times its checkers: ours (one thread) and
    Newton at ``newton`` (step, iterations) each settled once, then timed for ``timed`` seconds in
    each of ROUNDS rounds, once a round in turn; each one's least disturbed window kept, so a noisy
    spell on a shared machine takes both or neither."""
    solver, state = _ours_settled(segments, envs, settle, 1)
    window, row = _newton_settled(segments, envs, settle, ref, *newton)
    runs = alternated({"ours": lambda: _steps(solver, state, timed), "newton": lambda: window(timed)}, ROUNDS)
    return _ours_row(solver, state, min(runs["ours"]) / timed / envs, ref), row(min(runs["newton"]) / timed / envs)


def newton_equal_accuracy(segments: int, settle: float, ref, target: float) -> tuple[float, int] | None:
    """Newton's cheapest (step, iterations) of ``NEWTON_GRID`` whose shape error is at most
    ``target`` (ours), each tried on one environment; None where none is."""
    for dt, it in sorted(NEWTON_GRID, key=lambda c: c[1] / c[0]):
        r = newton_rod(segments, 1, settle, 0.5, ref, dt=dt, iterations=it)
        print(f"  Newton {dt * 1e3:.2f} ms, {it} iterations: shape error {r['shape']:.2%}", flush=True)
        if r["shape"] <= target:
            return dt, it
    return None


# -- MuJoCo -----------------------------------------------------------------------------------------


def mujoco_cable(segments: int, envs: int, settle: float, timed: float, ref) -> dict:
    import mujoco

    pts = initial_points(ref, segments)
    verts = " ".join(f"{p[0]:.9f} {p[1]:.9f} {p[2]:.9f}" for p in pts)
    last = pts[-1] - pts[-2]
    xml = f"""<mujoco><extension><plugin plugin="mujoco.elasticity.cable"/></extension>
<option timestep="0.0005" integrator="implicitfast"/>
<worldbody><composite type="cable" prefix="c" vertex="{verts}" initial="ball">
<plugin plugin="mujoco.elasticity.cable"><config key="twist" value="{E / 3:g}"/><config key="bend" value="{E:g}"/>
<config key="vmax" value="0"/></plugin>
<joint kind="main" damping="0.001"/>
<geom type="capsule" size="{RADIUS}" density="{RHO}"/>
</composite></worldbody>
<equality><connect body1="cB_last" body2="world" anchor="{np.linalg.norm(last):.9f} 0 0"/></equality>
</mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    timed_envs = min(envs, 4)  # per-environment cost: MuJoCo steps each MjData on its own
    datas = [mujoco.MjData(model) for _ in range(timed_envs)]
    steps = lambda seconds: int(round(seconds / model.opt.timestep))  # noqa: E731
    for d in datas:
        mujoco.mj_step(model, d, steps(settle))
    with held_gc():
        cpu = time.process_time()
        for d in datas:
            mujoco.mj_step(model, d, steps(timed))
        cpu = time.process_time() - cpu
    d = datas[0]
    mujoco.mj_kinematics(model, d)
    names = ["cB_first", *(f"cB_{k}" for k in range(1, segments - 1)), "cB_last"]  # body k starts at vertex k
    nodes = np.vstack([d.xpos[[model.body(n).id for n in names]], pts[-1:]])
    sag, shape = accuracy(nodes, ref)
    out = {"cpu": cpu / timed / timed_envs, "sag": sag, "shape": shape, "step": "0.50 ms"}
    notes = [f"timed on {timed_envs}, per environment"] if timed_envs < envs else []
    unstable = sum(int(x.warning[mujoco.mjtWarning.mjWARN_BADQACC].number) for x in datas)
    if unstable:  # MuJoCo resets a diverged MjData to its initial state: the shape would look perfect
        out["sag"] = out["shape"] = float("nan")
        notes.append(f"went unstable {unstable} time(s) and was reset")
    if notes:
        out["note"] = "; ".join(notes)
    return out


# -- PyElastica ------------------------------------------------------------------------------------


def elastica_rod(pts, radius, youngs, nu=0.5, pinned=True, clamp_start=False, clamp_end=False, twist=0.0,
                 gravity=True, settle=3.0, timed=1.0, damping=1.0):
    """PyElastica's Cosserat rod through ``pts`` (its frames by parallel transport; the last turned
    ``twist`` about the axis), ends pinned or clamped, stepped with its PositionVerlet at a tenth of
    the axial wave's crossing time of a segment: (rod, CPU-s per simulated s, step)."""
    import elastica as ea

    class Sim(ea.BaseSystemCollection, ea.Constraints, ea.Forcing, ea.Damping, ea.CallBacks):
        pass

    sim = Sim()
    n = len(pts) - 1
    tang = np.diff(pts, axis=0)
    lens = np.linalg.norm(tang, axis=1)
    tang /= lens[:, None]
    d1 = np.cross([0.0, 0.0, 1.0] if abs(tang[0][2]) < 0.9 else [1.0, 0, 0], tang[0])
    d1 /= np.linalg.norm(d1)
    dirs = np.zeros((3, 3, n))
    for k in range(n):
        a = d1 - np.dot(d1, tang[k]) * tang[k]
        a /= np.linalg.norm(a)
        dirs[0, :, k], dirs[1, :, k], dirs[2, :, k] = a, np.cross(tang[k], a), tang[k]
        d1 = a
    if twist:
        c, s = np.cos(twist), np.sin(twist)
        a, b = dirs[0, :, -1].copy(), dirs[1, :, -1].copy()
        dirs[0, :, -1], dirs[1, :, -1] = c * a + s * b, -s * a + c * b
    rod = ea.CosseratRod.straight_rod(n, pts[0], tang[0], dirs[0, :, 0], lens.sum(), radius, RHO, youngs_modulus=youngs,
                                      shear_modulus=youngs / (2 * (1 + nu)), position=pts.T.copy(), directors=dirs)
    sim.append(rod)
    dt = 0.1 * lens.min() / np.sqrt(youngs / RHO)
    pos_idx = tuple(i for i, on in ((0, clamp_start or pinned), (-1, clamp_end or pinned)) if on)
    dir_idx = tuple(i for i, on in ((0, clamp_start), (-1, clamp_end)) if on)
    sim.constrain(rod).using(ea.FixedConstraint, constrained_position_idx=pos_idx, constrained_director_idx=dir_idx)
    if gravity:
        sim.add_forcing_to(rod).using(ea.GravityForces, acc_gravity=np.array([0.0, 0.0, -9.81]))
    sim.dampen(rod).using(ea.AnalyticalLinearDamper, uniform_damping_constant=damping, time_step=dt)
    sim.finalize()
    stepper = ea.PositionVerlet()
    t = 0.0
    for _ in range(int(settle / dt)):
        t = stepper.step(sim, t, dt)
    with held_gc():
        cpu = time.process_time()
        for _ in range(int(timed / dt)):
            t = stepper.step(sim, t, dt)
        cpu = time.process_time() - cpu
    return rod, cpu / timed, dt
def elastica_hose(segments: int, envs: int, settle: float, timed: float, ref) -> dict:
    rod, cpu, dt = elastica_rod(initial_points(ref, segments), RADIUS, E, settle=settle, timed=timed)
    sag, shape = accuracy(rod.position_collection.T, ref)
    note = "per environment (one rod per simulator)" if envs > 1 else ""
    return {"cpu": cpu, "sag": sag, "shape": shape, "step": f"{1e3 * dt:.4f} ms", "note": note}


# -- the cantilever and the twisted rod -----------------------------------------------------------------

BEAM_L, BEAM_R, BETA5_E = 0.5, 0.01, 5.885e7 / 5  # q L^3 / EI = 5 at 1200 kg/m^3
TWIST_E, TWIST_PHI = 5e8, np.pi / 2
CASE_ENVS = 256


def cantilever(settle: float, timed: float, envs: int) -> list[tuple[str, dict]]:
    """Tip drop / L against the elastica's 0.49591, 40 segments."""
    seg = BEAM_L / 40
    points = ('<ControlPoint attachedTo="Base" position="0, 0, 1000" direction="1, 0, 0"/>'
              f'<ControlPoint position="{BEAM_L * 1000}, 0, 1000"/>')
    solver = _rod(_cable("Beam", BEAM_R, seg, BETA5_E, points), damping=5.0, floor=None)
    state = solver.state(envs)
    _steps(solver, state, settle)
    cpu = _steps(solver, state, timed) / timed / envs
    ours = {"cpu": cpu, "error": (1 - solver.points(state, 0, 0)[-1, 2]) / BEAM_L / 0.49591 - 1}
    pts = np.stack([np.linspace(0, BEAM_L, 41), np.zeros(41), np.ones(41)], axis=1)
    rod, cpu, _ = elastica_rod(pts, BEAM_R, BETA5_E, pinned=False, clamp_start=True, settle=settle, timed=timed,
                               damping=5.0)
    return [("rswarp", ours),
            ("PyElastica", {"cpu": cpu, "error": (1 - rod.position_collection[2, -1]) / BEAM_L / 0.49591 - 1})]


def twisted(settle: float, timed: float, envs: int) -> list[tuple[str, dict]]:
    """A vertical rod clamped at both ends, its head turned a quarter turn: torque against G J Phi /
    L, 20 segments."""
    gj = TWIST_E / 3 * np.pi * BEAM_R ** 4 / 2
    want = gj * TWIST_PHI / BEAM_L
    points = ('<ControlPoint attachedTo="Base" position="0, 0, 1000" direction="0, 0, 1"/>'
              f'<ControlPoint attachedTo="Head" position="0, 0, {1000 + BEAM_L * 1000}" direction="0, 0, 1"/>')
    joint = ('<Joint name="Turn" parent="Base" child="Head" type="Rotational" active="true" point1="0,0,0" '
             'point2="0,0,1"/>')
    xml = _cable("Twist", BEAM_R, BEAM_L / 20, TWIST_E, points, joints=joint, links='<Part name="Head"/>',
                 limits='<Limits><Limit joint="Turn" min="-180" max="180"/></Limits>')
    solver = _rod(xml, damping=5.0, floor=None)
    state = solver.state(envs)
    turn = lambda t: (TWIST_PHI * min(t, 1.0),)  # noqa: E731
    _steps(solver, state, settle, turn)
    cpu = _steps(solver, state, timed, lambda t: (TWIST_PHI,)) / timed / envs
    ours = {"cpu": cpu, "error": solver.statistics(state)[0]["torque"][0] / want - 1}
    pts = np.stack([np.zeros(21), np.zeros(21), np.linspace(1.0, 1.0 + BEAM_L, 21)], axis=1)
    rod, cpu, _ = elastica_rod(pts, BEAM_R, TWIST_E, pinned=False, clamp_start=True, clamp_end=True, twist=TWIST_PHI,
                               gravity=False, settle=min(settle, 0.5), timed=timed, damping=20.0)
    torque = float(np.abs(rod.internal_couple[2]).mean())
    return [("rswarp", ours), ("PyElastica", {"cpu": cpu, "error": torque / want - 1})]


def where_time_goes(settle: float, timed: float, envs: int = 256, segments: int = 20) -> None:
    """The hanging hose of the ratio (one thread), run again with 1 and 0 Gauss-Newton iterations a substep
    instead of the default: what an iteration costs, and what the rest of a substep does (the
    prediction, the contact search, the measurements, the commit); then the limit line (the state
    read and written a substep beside a copy of the same bytes)."""
    points = (f'<ControlPoint attachedTo="Base" position="0, 0, {HEIGHT * 1000}"/>'
              f'<ControlPoint attachedTo="Base" position="{SPAN * 1000}, 0, {HEIGHT * 1000}"/>')
    solver = _rod(_cable("Hose", RADIUS, LENGTH / segments, E, points, LENGTH), damping=1.0, floor=None,
                  threads=1)
    state = solver.state(envs)
    _steps(solver, state, settle)
    subs, default = solver.options.substeps, solver.options.iterations
    print(f"\nwhere the time goes: {segments} segments, {envs} environments, {subs} substeps a frame")
    cost = {}
    for iterations in (default, 1, 0):
        object.__setattr__(solver.options, "iterations", iterations)  # the same solver, run on
        cost[iterations] = _steps(solver, state, timed) / timed / envs
        print(f"  {iterations} iteration(s) a substep (at most): {cost[iterations]:.5f} CPU-s/sim-s/env, "
              f"{cost[iterations] / (60 * subs) * 1e6:.2f} us an environment's substep")
    object.__setattr__(solver.options, "iterations", default)
    print(f"  the substep without its iterations: {cost[0] / cost[default]:.0%} of the default's time")
    rate = 60 * subs / cost[default]  # environment-substeps a CPU-second
    nbytes = solver.bodies * 16 * 8 * 2 + solver.links * 16 * 8
    copy = copy_rate(nbytes, 100_000)
    print(f"the limit: {nbytes} bytes an environment's substep (each body's state read and written, each link's "
          f"pose read), a copy of the same bytes runs {copy:,.0f}/s (ours at {rate / copy:.2%} of it a CPU-second): "
          "not memory: the bound is the arithmetic, the iterations' 6x6 blocks and, as much again, each "
          "substep's measurements, prediction and commit")


def whole_run(envs: int = 256, seconds: float = 10.0) -> None:
    """The issue's target on the bundled IRB 2600ID: ``simulate_cables`` for ``envs`` random
    trajectories of ``seconds`` (its kernel compiled first, by a one-frame run), wall and CPU time."""
    import rswarp
    from rswarp.examples import IRB2600ID
    from rswarp.kinematics.trajectory import random_trajectory
    from rswarp.sim.cables import simulate_cables

    mech = rswarp.load(IRB2600ID)
    trajectories = [random_trajectory(mech, seconds, seed) for seed in range(envs)]
    simulate_cables(mech, trajectories[:1], 1, seconds=1 / 60)
    wall, cpu = time.perf_counter(), time.process_time()
    simulate_cables(mech, trajectories, envs, seconds)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    print(f"\nwhole run, IRB 2600ID hose, {envs} environments x {seconds:g} s of random motion "
          f"(settling included): {wall:.1f} s wall, {cpu:.1f} CPU-s")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="shorter runs (a check that the script works)")
    ap.add_argument("--whole-run", action="store_true", help="only the whole-run timing on the IRB 2600ID")
    args = ap.parse_args()
    if args.whole_run:
        whole_run()
        return
    settle, timed = (1.0, 0.5) if args.quick else (6.0, 2.0)
    ref = elastica()
    print(f"hanging hose: catenary sag {catenary_sag() * 1000:.1f} mm, elastica (reference) sag "
          f"{(HEIGHT - ref[1][:, 1].min()) * 1000:.1f} mm")
    print(f"{'segments':>8} {'envs':>5} {'solver':>10} {'step':>9} {'CPU-s/sim-s/env':>16} {'sag vs catenary':>16} "
          f"{'shape error':>12}")
    rows, equal_20 = [], None
    for segments in (20, 40):
        alone = elastica_hose(segments, 1, settle, timed, ref)  # one rod per simulator: cost per env
        target = ours(segments, 1, settle, timed, ref)["shape"]
        print(f"Newton at equal accuracy, {segments} segments (shape error at most ours, {target:.2%}):")
        equal = newton_equal_accuracy(segments, settle, ref, target)
        equal_20 = equal if segments == 20 else equal_20
        for envs in (1, 64, 256):
            per_env = dict(alone, note="per environment" if envs > 1 else "")
            peers = [("rswarp", ours), ("Newton", newton_rod), ("MuJoCo", mujoco_cable),
                     ("PyElastica", lambda *_, r=per_env: r)]
            if envs > 1:  # ours on every core too: its CPU cost, with what sharing the machine costs
                peers.insert(1, ("rswarp*", lambda *a: dict(ours(*a, threads=None), note="* on every core")))
            if equal is not None:
                peers.insert(2, ("Newton*", lambda *a, e=equal: dict(newton_rod(*a, dt=e[0], iterations=e[1]),
                                                                    note=f"* at equal accuracy, {e[1]} iterations")))
            for name, fn in peers:
                r = fn(segments, envs, settle, timed, ref)
                rows.append((segments, envs, name, r))
                print(f"{segments:>8} {envs:>5} {name:>10} {r['step']:>9} {r['cpu']:>16.5f} {r['sag']:>+16.2%} "
                      f"{r['shape']:>12.2%} {r.get('note', '')}", flush=True)
    for title, case in (("self-weight cantilever, beta = 5: tip drop against the elastica's 0.49591 L", cantilever),
                        ("clamped rod twisted a quarter turn: torque against G J Phi / L", twisted)):
        print(f"\n{title} (ours: {CASE_ENVS} environments)")
        results = case(settle, timed, CASE_ENVS)
        for name, r in results:
            print(f"{name:>10} {r['cpu']:>16.5f} CPU-s/sim-s/env {r['error']:>+10.3%}")
        print(f"{'ratio':>10} {results[1][1]['cpu'] / results[0][1]['cpu']:>16.1f}x")
    best = {(s, e): min(r["cpu"] for s2, e2, n, r in rows if (s2, e2) == (s, e) and not n.startswith("rswarp"))
            for s, e, _, _ in rows}
    print("\nratio (best peer's CPU cost / ours, both on one thread; * ours on every core):")
    for s, e, n, r in rows:
        if n.startswith("rswarp"):
            print(f"  {s} segments, {e} envs{' *' * (n != 'rswarp')}: {best[(s, e)] / r['cpu']:.1f}x")
    ours_256, peer_256 = _ratio_row(rows, settle, timed, ref, equal_20, envs=256)
    where_time_goes(settle, timed, envs=16 if args.quick else 256)
    whole_run(envs=16 if args.quick else 256, seconds=2.0 if args.quick else 10.0)
    print(json.dumps({"metric": "cable CPU-s per simulated s per env (20 segments, 256 envs)",
                      "ours": ours_256, "peer": peer_256, "ratio": peer_256 / ours_256}))


def _ratio_row(rows: list, settle: float, timed: float, ref, equal: tuple[float, int] | None, envs: int):
    """(ours, the best peer) at 20 segments: ours and the Newton setting that cost least in the
    table timed again in alternated rounds (``ratio_rounds``); a peer that is not Newton at its table
    cost."""
    table = [(n, r) for s, e, n, r in rows if (s, e) == (20, envs) and not n.startswith("rswarp")]
    name, _ = min(table, key=lambda nr: nr[1]["cpu"])
    others = min(r["cpu"] for n, r in table if not n.startswith("Newton"))
    setting = equal if name == "Newton*" and equal is not None else (1 / 600, 5)
    mine, newton = ratio_rounds(20, envs, settle, timed, ref, setting)
    print(f"\nthe ratio's row again, 20 segments, {envs} environments: rswarp and Newton at {setting[0] * 1e3:.2f} ms, "
          f"{setting[1]} iterations, the cheaper of its table rows, each timed {timed:g} s in each of {ROUNDS} rounds, "
          f"once a round in turn, its best kept")
    peer = min(newton["cpu"], others)
    print(f"  rswarp {mine['cpu']:.5f}, Newton {newton['cpu']:.5f} CPU-s/sim-s/env (shape error "
          f"{newton['shape']:.2%}); the other peers' least {others:.5f}: ratio {peer / mine['cpu']:.1f}x")
    return mine["cpu"], peer


if __name__ == "__main__":
    main()
