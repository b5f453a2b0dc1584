"""``rswarp demo``: check and info on every bundled example, and for each robot its flange at home,
its reach from a short sweep, its USD and URDF exports, a cable run where it has cables, and the
RAPID programs beside it run through it."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from ..errors import RsxmlError
from ..rsxml.documents import Report, check
from ..rsxml.model import Mechanism
from .demo_cells import demo_cells
from .info import report_dict, report_text
from .output import Output
from .placement.demo import demo_placement

DEMO_SAMPLES = 20_000
DEMO_CABLE_ENVS, DEMO_CABLE_SECONDS = 16, 4.0
DEMO_RAY_TASKS = 4  # collision-sweep chunks run as Ray tasks
DEMO_VIDEO = 480  # pixels a side of the demo's videos: the band's text legible
DEMO_VIDEO_FPS = 10.0  # their frames a second of the run's time: a third of a video's 30, for the demo's time


@dataclass
class Demo:
    """What the demo did: a report per example and a summary per robot."""

    reports: list[Report] = field(default_factory=list)
    robots: list[dict] = field(default_factory=list)
    libraries: list[dict] = field(default_factory=list)
    dresspack: dict = field(default_factory=dict)
    ray: dict = field(default_factory=dict)
    cells: list[dict] = field(default_factory=list)
    placement: dict = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return all(r.ok for r in self.reports) and self.ray.get("same_as_local", True) and \
            not any(c["errors"] for c in self.cells) and self.placement.get("best") is not None

    def as_dict(self) -> dict:
        return {"ok": self.ok, "examples": [report_dict(r) for r in self.reports], "robots": self.robots,
                "libraries": self.libraries, "dresspack": self.dresspack, "cells": self.cells,
                "placement": self.placement, "ray": self.ray}


def demo_output(out: str | Path = "rswarp-demo", say: Callable[[str], None] = lambda text: None) -> Output:
    """``rswarp demo``: the demo as a command shows it (its text told to ``say`` as it goes)."""
    demo = run_demo(out, say)
    return Output(demo.as_dict(), "", 0 if demo.ok else 1)


def run_demo(out: str | Path, say: Callable[[str], None] = lambda text: None) -> Demo:
    """Run the demo, writing exports into ``out`` and telling ``say`` what it does; its videos
    at ``DEMO_VIDEO`` pixels, ``DEMO_VIDEO_FPS`` frames a second."""
    from .videos import frame_rate

    with frame_rate(DEMO_VIDEO_FPS):
        return _run_demo(out, say)


def _run_demo(out: str | Path, say: Callable[[str], None]) -> Demo:
    from .. import examples

    demo = Demo()
    robots = []
    for path in examples.ALL:
        report = check(path)
        demo.reports.append(report)
        say(_check_text(path.name, report))
        if report.ok and isinstance(report.model, Mechanism):
            robots.append(report.model)
            demo.robots.append(demo_robot(report.model, Path(out), say))
        elif report.ok and report.kind == "LibraryCompiler":
            demo.libraries.append(demo_library(path, Path(out) / "library", say))
    demo.dresspack = demo_dresspack(Path(out), say)
    demo.cells = demo_cells(Path(out) / "cells", say, DEMO_VIDEO)
    demo.placement = demo_placement(Path(out) / "place", say)
    demo.ray = demo_ray(robots, say)
    return demo


# the demo's design sweep: the hose's length (m), the tool clamp's height (m) and pitch (deg), the upper
# arm clamp along x (m), about a region a 128-design sweep found passing designs in
DEMO_SWEEP = {"length": (1.19, 1.24), "Link6.z": (0.035, 0.08), "Link6.pitch": (-12.0, -3.0),
              "Link3.x": (-0.085, -0.065)}
DEMO_DESIGNS = 32


def demo_dresspack(out: Path, say: Callable[[str], None]) -> dict:
    """The IRB 2600's upper-arm dress pack over its pick-and-place program, then over random
    programs: the answers a dress-pack engineer asks for."""
    from .. import examples
    from ..config import VideoOptions
    from .cables import run_cables

    path, program = str(examples.IRB2600_DRESSPACK), str(examples.IRB2600_PROGRAM)
    say(f"== dress pack: {examples.IRB2600_DRESSPACK.name}, a 30 mm process hose from the upper arm over the "
        "wrist to the tool")
    runs = {}
    for label, folder, kwargs in (
            (f"over {examples.IRB2600_PROGRAM.name} (rswarp cable --program --video)", "dresspack-program",
             {"envs": 1, "program": program,
              "video": VideoOptions(str(out / "dresspack-program.gif"), video_size=DEMO_VIDEO)}),
            (f"over {DEMO_CABLE_ENVS} random programs of {DEMO_CABLE_SECONDS:g} s (rswarp cable --random --video)",
             "dresspack-random", {"envs": DEMO_CABLE_ENVS, "random": True, "seconds": DEMO_CABLE_SECONDS,
                                  "video": VideoOptions(str(out / "dresspack-random.gif"), video_size=DEMO_VIDEO)})):
        done = run_cables(path, str(out / folder), **kwargs)
        runs[folder] = done.doc
        lines = [line for line in done.text.splitlines()[2:] if not line.split(":")[0].endswith(("plot", "report"))]
        say("\n".join([f"   {label} -> {out / folder}", *(f"   {line}" for line in lines)]))
    say("   (the random programs keep the robot off the floor, off itself and off the hose's clamps and their "
        "leads; they drive the wrist through its whole range, so the hose bends tighter there than over the "
        "program: docs/cables.md)")
    runs["dresspack-sweep"] = _sweep(path, program, out, say)
    return {"mechanism": examples.IRB2600_DRESSPACK.name, "runs": runs}


def _sweep(path: str, program: str, out: Path, say: Callable[[str], None]) -> dict:
    """The design sweep over the program: the bundled hose fails it; which length and clamps pass."""
    from .dresspack import run_dresspack

    vary = [f"{k}={low:g}:{high:g}" for k, (low, high) in DEMO_SWEEP.items()]
    done = run_dresspack(path, [program], str(out / "dresspack-sweep"), vary=vary, designs=DEMO_DESIGNS)
    say("\n".join([f"   design sweep (rswarp dresspack --vary {' --vary '.join(vary)} --designs {DEMO_DESIGNS}) -> "
                   f"{out / 'dresspack-sweep'}", *(f"   {line}" for line in done.text.splitlines())]) + "\n")
    return done.doc


def demo_ray(robots: list[Mechanism], say: Callable[[str], None]) -> dict:
    """The first robot's collision sweep again as tasks on a local Ray instance, compared with the
    local run; or, without Ray, how to get it."""
    import importlib.util

    from ..errors import InputError
    from ..sim.collisions import CHUNK, collisions
    from ..sim.engine import INSTALL, Cluster, identical

    if importlib.util.find_spec("ray") is None:
        say(f"== Ray: not installed; {INSTALL.split(': ', 1)[1]} to run sweeps, collision sweeps and cable runs "
            "as tasks on a cluster (--ray)\n")
        return {"installed": False}
    for mech in robots:
        samples = DEMO_RAY_TASKS * CHUNK
        try:
            here = collisions(mech, samples=samples, seed=0)
        except InputError:  # no meshes: nothing to sweep
            continue
        there = collisions(mech, samples=samples, seed=0, cluster=Cluster(task_samples=CHUNK))
        same = identical(here, there)
        say(f"== Ray: {mech.name}'s collision sweep of {samples} samples as {DEMO_RAY_TASKS} tasks on a local Ray "
            f"instance: {'the same report as the local run' if same else 'DIFFERENT from the local run'}\n")
        return {"installed": True, "mechanism": mech.name, "samples": samples, "same_as_local": same}
    return {"installed": True}


def demo_library(path: Path, out: Path, say: Callable[[str], None]) -> dict:
    """Build a library file's assets (USD packages with metadata and previews) into ``out``."""
    from .library import build_library, size_text

    build = build_library(path, out)
    assets = ", ".join(f"{Path(r.output).name} ({size_text(r.size)})" for r in build.results if r.output)
    failed = [r.message for r in build.results if r.status != "built"]
    no_preview = [w.split(": ", 1)[-1] for r in build.results for w in r.warnings if "no preview" in w]
    previews = sum(1 for r in build.results if r.output) - len(no_preview)
    say("\n".join([f"== rswarp build {path.name}: {len(build.results) - len(failed)} of {len(build.results)} built "
                   f"into {out}: {assets}; {previews} with a preview", *(f"   {w}" for w in no_preview[:1]),
                   *(f"   error: {m}" for m in failed), ""]))
    return build.report()


def _check_text(name: str, report: Report) -> str:
    lines = [f"== rswarp check {name}", *(str(d) for d in report.all_diagnostics),
             f"{'OK' if report.ok else 'FAILED'}: {sum(d.repeats for d in report.errors)} errors, "
             f"{sum(d.repeats for d in report.warnings)} warnings",
             f"== rswarp info {name}", report_text(report) if report.model is not None else "(nothing to show)", ""]
    return "\n".join(lines)


def demo_robot(mech: Mechanism, out: Path, say: Callable[[str], None]) -> dict:
    """The flange at home, the reach and the exports of one robot."""
    from ..export import export
    from ..kinematics.kinematics import Kinematics
    from ..sim.workspace import workspace
    from .exports import data_physics
    from .poses import rounded

    kin = Kinematics(mech)
    flange = kin.flange(mech.home_position()[None])[0]
    ws = workspace(mech, samples=DEMO_SAMPLES, seed=0, kinematics=kin)
    out.mkdir(parents=True, exist_ok=True)
    matrix, collision_line = _collisions(mech, out)
    usd, urdf = out / f"{mech.name}.usdc", out / f"{mech.name}.urdf"
    physics = data_physics(str(mech.path), mech, matrix or ())  # its robot data, as rswarp export reads it
    done, no_urdf = [export(mech, usd, physics=physics)], ""
    try:
        done.append(export(mech, urdf, physics=physics))
    except RsxmlError as exc:  # a loop URDF cannot express (not linear in the active joints)
        no_urdf = f" (no URDF: {exc})"
    warnings = [w for d in done for w in d.warnings]
    lf, unit = mech.length_factor, mech.length_unit or "m"
    pos = ", ".join(rounded(float(v), lf, 1e-4) for v in flange[:3, 3])
    reach = ws.reach or ws.flange_reach
    what = "J1 axis to wrist centre" if ws.reach is not None else "J1 axis to flange"
    lines = [f"== {mech.name}: flange at home ({pos}) {unit}; reach {rounded(reach.value, lf, 1e-4)} {unit} "
             f"({what}, {DEMO_SAMPLES} samples refined)", *(f"   {w}" for w in warnings[:1]),
             f"   {collision_line}",
             f"   exported {usd}" + (f" and {urdf}" if len(done) > 1 else no_urdf)
             + f": {_physics_line(done[0].physics)}",
             *_cables(mech, out), *_standard_cycle(mech), *_programs(mech, out), ""]
    say("\n".join(lines))
    return {"name": mech.name, "flange_at_home": flange[:3, 3].astype(float).tolist(), "reach": reach.value,
            "usd": str(usd), "urdf": str(urdf) if len(done) > 1 else None}


def _programs(mech: Mechanism, out: Path) -> list[str]:
    """Each RAPID module beside the robot's file run through it (``rswarp program``), its table
    and findings, with the demo's collision matrix, its trajectory written as a CSV; and each task
    folder beside it (a cell's modules), its cycle and what it assumed."""
    if not mech.path:
        return []
    folder = Path(mech.path).parent
    gripper = folder / "gripper" / "Gripper.rsxml"  # the tool the modules beside the robot hold
    tool = str(gripper) if gripper.is_file() else None
    lines = []
    for module in sorted(folder.glob("*.mod")):
        csv = out / f"{mech.name}-{module.stem}.csv"
        video = out / f"{mech.name}-{module.stem}.gif" if module.stem == "service" else None
        done = _program(mech, out, [module], csv, video, tool=tool)
        held = f", with --tool {Path(tool).relative_to(folder.parent)}" if tool else ""
        lines.append(f"   program {module.name} (rswarp program{held}), trajectory -> {csv}:")
        lines += [f"     | {line}" for line in _purpose(module)]
        lines += [f"     {line}" for line in done.text.splitlines() if not line.startswith("trajectory:")]
    for task in sorted(d for d in folder.iterdir() if d.is_dir() and any(d.glob("*.mod"))):
        csv = out / f"{mech.name}-{task.name}.csv"
        said: list[str] = []
        done = _program(mech, out, [task], csv, None, said.append)
        text = done.text.splitlines()
        lines.append(f"   task {task.name}/ ({len(done.doc['files'])} modules, rswarp program), trajectory -> {csv}:")
        lines += [f"     {line}" for line in text[:2] + [t for t in text if t.startswith(("findings", "  ", "errors"))]]
        lines += [f"     assumed: {line.split(': warning: ', 1)[-1]}" for line in said]
    return lines


def _standard_cycle(mech: Mechanism) -> list[str]:
    """ABB's standard pick cycle (``examples/standard_cycle.mod``) on a 6-axis arm: its steady
    cycle time and the axis data that timed it (nothing for other mechanisms)."""
    from .. import examples
    from ..kinematics.kinematics import Kinematics
    from .program import run_program

    if not mech.path or Kinematics(mech).ik_method != "arm":
        return []
    doc = run_program(str(mech.path), [str(examples.STANDARD_CYCLE)], cycles=3).doc
    timed = any(f < 1.0 for load in doc["loads"] for f in load["acceleration_factor"])
    unloaded = "" if timed else " (the 1 kg not timed: no link meshes, so no masses)"
    return [f"   standard cycle 25 x 300 x 25 mm with 1 kg ({examples.STANDARD_CYCLE.name}, rswarp program "
            f"--cycles 3): {doc['cycle_s']:.3f} s steady{unloaded}; {doc['axis_limits']['summary']}"]


def _purpose(module: Path) -> list[str]:
    """A module's leading comment, what it is for in its author's words, wrapped for the demo."""
    import textwrap

    said = []
    for line in module.read_text(encoding="utf-8", errors="replace").splitlines():
        text = line.strip()
        if text.startswith("!"):
            said.append(text.lstrip("! ").rstrip())
        elif said:
            break
    return textwrap.wrap(" ".join(said), 96)


def _program(mech: Mechanism, out: Path, paths: list[Path], csv: Path, video: Path | None, warn=None,
             tool: str | None = None):
    from ..config import VideoOptions
    from .program import run_program

    srdf = out / f"{mech.name}-collisions" / "collision_matrix.srdf"
    return run_program(str(mech.path), [str(p) for p in paths], csv=str(csv),
                       video=VideoOptions(None if video is None else str(video), video_size=DEMO_VIDEO),
                       collision_matrix=str(srdf) if srdf.exists() else None, tool=tool,
                       **({"warn": warn} if warn is not None else {}))


def _has_mesh(mech: Mechanism, part) -> bool:
    from ..geometry.meshes import part_mesh_path

    return part_mesh_path(mech, part) is not None


def _collisions(mech: Mechanism, out: Path) -> tuple[tuple, str]:
    """A collision sweep and its matrix (written to ``out/<name>-collisions``), for the exports."""
    from ..errors import InputError
    from ..sim.collisions import collisions
    from .collisions import write_collisions

    try:
        c = collisions(mech, samples=DEMO_SAMPLES, seed=0)
    except InputError as exc:  # no meshes: nothing to collide
        return (), f"no collision sweep: {exc}"
    folder = out / f"{mech.name}-collisions"
    write_collisions(c, folder)
    counts = ", ".join(f"{v} {k.lower()}" for k, v in c.reason_counts().items())
    return tuple(c.disabled()), (f"collisions: {c.free_fraction:.1%} of {c.samples} samples free; matrix disables "
                                 f"{counts} pairs -> {folder}")


def _cables(mech: Mechanism, out: Path) -> list[str]:
    """A cable run on random programs (``rswarp cable --random``), written to ``out/<name>-cables``."""
    if not mech.cables:
        return []
    from ..sim.cables import simulate_cables
    from ..sim.random_program import random_programs
    from .cables import cables_text, run_findings, verdict_data, write_cables

    trajectories = random_programs(mech, DEMO_CABLE_ENVS, DEMO_CABLE_SECONDS, 0)
    run = simulate_cables(mech, trajectories, DEMO_CABLE_ENVS, DEMO_CABLE_SECONDS)
    folder = out / f"{mech.name}-cables"
    found = run_findings(run, trajectories)
    doc = write_cables(run, mech, folder, more=verdict_data(run, found))
    text = cables_text(run, {"report": doc["files"]["report"]}, found).splitlines()
    meshes = any(_has_mesh(mech, part) for link in mech.link_names for part, _ in mech.parts(link) if part.source)
    bare = "" if meshes else "; no meshes ship with this robot, so its hose meets only the floor"
    head = (f"   cables ({DEMO_CABLE_ENVS} random programs, free of the floor and the robot itself, "
            f"{DEMO_CABLE_SECONDS:g} s{bare}) -> {folder}")
    if not meshes:  # its answers say little: the dress pack below is the example to read
        keep = [line for line in text[1:-1] if line.strip().startswith(("verdict", "fail ", "bend radius"))]
        return [head, *(f"   {line}" for line in keep), "   (the dress pack below is a hose on a robot with meshes)"]
    return [head, *(f"   {line}" for line in text[1:-1])]


def _physics_line(robot) -> str:
    """Mass, drives and filtered pairs of an export, in one line."""
    if not robot.total_mass > 0:
        return "kinematics only"
    touching = sum(1 for *_, r in robot.filtered if r == "overlap at home")
    source = f" (from {robot.mass_source})" if robot.mass_source else \
        f" (at {robot.density:g} kg/m^3: no robot data)"
    driven = sum(j.stiffness > 0 for j in robot.joints.values())
    return (f"{robot.total_mass:.1f} kg{source}, drives holding home on {driven} joints, {len(robot.filtered)} link "
            f"pairs filtered ({touching} touching at home)")
