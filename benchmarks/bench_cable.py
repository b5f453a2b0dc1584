"""Cable dynamics: ours against Newton's rod (``ModelBuilder.add_rod``, ``SolverVBD``) and
MuJoCo's cable plugin (``mujoco.elasticity.cable``) on one hanging hose, in one process.

The hose: span 1 m, length 1.2 m, radius 2.5 cm, E 5e7 Pa, density 1200 kg/m^3, both ends pinned
at one height; 20 and 40 segments; 1, 64 and 256 environments. Figures:

- CPU-seconds per simulated second per environment (process CPU time over the timed window, all
  threads), after a settling run that is not timed;
- sag error against the inextensible catenary, and shape error (RMS of the height along the arc,
  relative to the sag) against a converged reference: the inextensible elastica with pinned ends
  under its weight, solved by SciPy's ``solve_bvp``. With this stiffness (bending length
  (EI/w)^(1/3) = 0.87 m) the hose sags less than the catenary, so the shape error is the fair
  accuracy figure.

Each peer is stepped the way its examples do: Newton at 1.67 ms steps with 5 VBD iterations and
its end segments kinematic; MuJoCo at 0.5 ms (it is reported to go NaN at 1 ms), implicitfast, one
MjData per environment (its cost is per environment; 64 and 256 are timed as 4 environments and
scaled, said in the table). Ours: 60 frames per second of 10 substeps, the run's defaults.

Last, the issue's target: the bundled IRB 2600ID's hose, 256 environments x 10 s of random motion,
through ``simulate_cables`` (``--whole-run`` measures only this).

Usage: python benchmarks/bench_cable.py [--quick] [--whole-run]. Ends with a JSON line: the ratio is the best
peer's CPU cost over ours at 20 segments and 256 environments.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

import numpy as np
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


def ours(segments: int, envs: int, settle: float, timed: float, ref) -> dict:
    import rswarp
    from rswarp.sim.cable_chain import ParticleChain
    from rswarp.sim.cable_solver import FRAME_RATE, SUBSTEPS, CableOptions

    xml = f"""<?xml version="1.0"?>
<Mechanism xmlns="urn:abb-robotics-robotstudio-graphiccomponent" type="Other" name="Hose" lengthUnit="mm"
           angleUnit="deg">
  <Links baseLink="Base"><Part name="Base"/></Links>
  <AdditionalComponents>
    <Cable radius="{RADIUS * 1000}" maxSegmentLength="{LENGTH * 1000 / segments + 1e-6}" name="Hose"
           desiredLength="{LENGTH * 1000}" youngsModulus="{E}">
      <ControlPoints>
        <ControlPoint attachedTo="Base" position="0, 0, {HEIGHT * 1000}"/>
        <ControlPoint attachedTo="Base" position="{SPAN * 1000}, 0, {HEIGHT * 1000}"/>
      </ControlPoints>
    </Cable>
  </AdditionalComponents>
  <Joints/>
</Mechanism>"""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "hose.rsxml"
        path.write_text(xml)
        mech = rswarp.load(path)
    chain = ParticleChain(mech, mech.cables[0], CableOptions(substeps=SUBSTEPS, damping=1.0))
    assert len(chain.arrays.rest) == segments, (len(chain.arrays.rest), segments)
    state = chain.state(envs)
    state.x.numpy()[:] = initial_points(ref, segments)[None]  # the peers start from the reference too
    zero = np.zeros((envs, SUBSTEPS, 0), np.float32)
    frame = 1 / FRAME_RATE
    for _ in range(int(settle * FRAME_RATE)):
        chain.step(state, zero, frame)
    cpu = time.process_time()
    for _ in range(int(timed * FRAME_RATE)):
        chain.step(state, zero, frame)
    cpu = time.process_time() - cpu
    sag, shape = accuracy(chain.points(state, 0), ref)
    return {"cpu": cpu / timed / envs, "sag": sag, "shape": shape, "step": f"{1e3 * frame / SUBSTEPS:.2f} ms"}


# -- Newton -----------------------------------------------------------------------------------------


def newton_rod(segments: int, envs: int, settle: float, timed: float, ref) -> dict:
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
    solver = newton.solvers.SolverVBD(model, iterations=5)
    s0, s1, control = model.state(), model.state(), model.control()
    dt = 1 / 600

    def run(seconds: float):
        nonlocal s0, s1
        for _ in range(int(round(seconds / dt))):
            s0.clear_forces()
            solver.step(s0, s1, control, None, dt)
            s0, s1 = s1, s0

    run(settle)
    cpu = time.process_time()
    run(timed)
    cpu = time.process_time() - cpu
    q = s0.body_q.numpy()[: len(bodies), :3]
    nodes = np.vstack([q, pts[-1]])  # body origins are segment starts; the last node is held
    sag, shape = accuracy(nodes, ref)
    return {"cpu": cpu / timed / envs, "sag": sag, "shape": shape, "step": f"{1e3 * dt:.2f} ms"}


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
    print(f"{'segments':>8} {'envs':>5} {'solver':>8} {'step':>8} {'CPU-s/sim-s/env':>16} {'sag vs catenary':>16} "
          f"{'shape error':>12}")
    rows = []
    for segments in (20, 40):
        for envs in (1, 64, 256):
            for name, fn in (("rswarp", ours), ("Newton", newton_rod), ("MuJoCo", mujoco_cable)):
                r = fn(segments, envs, settle, timed, ref)
                rows.append((segments, envs, name, r))
                print(f"{segments:>8} {envs:>5} {name:>8} {r['step']:>8} {r['cpu']:>16.5f} {r['sag']:>+16.2%} "
                      f"{r['shape']:>12.2%} {r.get('note', '')}", flush=True)
    best = {(s, e): min(r["cpu"] for s2, e2, n, r in rows if (s2, e2) == (s, e) and n != "rswarp")
            for s, e, _, _ in rows}
    print("\nratio (best peer's CPU cost / ours):")
    for s, e, n, r in rows:
        if n == "rswarp":
            print(f"  {s} segments, {e} envs: {best[(s, e)] / r['cpu']:.1f}x")
    whole_run(envs=16 if args.quick else 256, seconds=2.0 if args.quick else 10.0)
    ours_256 = next(r["cpu"] for s, e, n, r in rows if (s, e, n) == (20, 256, "rswarp"))
    print(json.dumps({"metric": "cable CPU-s per simulated s per env (20 segments, 256 envs)",
                      "ours": ours_256, "peer": best[(20, 256)], "ratio": best[(20, 256)] / ours_256}))


if __name__ == "__main__":
    main()
