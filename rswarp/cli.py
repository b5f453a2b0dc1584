"""The ``rswarp`` command line: each command parses its arguments, calls one library function and
prints. Bad input (``InputError``) ends with one ``file:line: message`` line per problem and exit 1;
anything else is an internal error, exit 2, with its traceback under ``--debug``."""

from __future__ import annotations

import argparse
import json
import math
import os
import sys

from .errors import InputError, RsxmlError, one_line
from .files import DEFAULT_MAX_FILE_SIZE, Terminated, file_size_limit
from .export.physics import DRIVE_HZ
from .geometry.mass import DEFAULT_DENSITY
from .rsxml.documents import check, checked, load_mechanism


def _emit_json(obj) -> None:
    print(json.dumps(obj, indent=2, allow_nan=False))


def cmd_check(args) -> int:
    from .report.info import check_dict, check_verdict

    reports = []
    for f in args.files:
        reports.append(report := check(f))
        if not args.json:  # problems on stderr, the verdict on stdout, file by file
            for d in report.all_diagnostics:
                print(str(d), file=sys.stderr, flush=True)
            print(check_verdict(report), flush=True)
    if args.json:
        _emit_json(check_dict(reports))
    return 0 if all(r.ok for r in reports) else 1


def cmd_info(args) -> int:
    from .report.info import report_dict, report_text

    report = checked(args.file)
    if args.json:
        _emit_json(report_dict(report))
        return 0
    for d in report.warnings:
        print(str(d), file=sys.stderr)
    print(report_text(report))
    return 0


def cmd_fk(args) -> int:
    from .report.poses import fk_report, joint_values, limit_warnings

    mech, _ = load_mechanism(args.file)
    q = joint_values(mech, args.q)
    for warning in limit_warnings(mech, q):
        print(warning, file=sys.stderr)
    doc, text = fk_report(mech, q, device=args.device)
    _emit_json(doc) if args.json else print(text)
    return 0


def cmd_sweep(args) -> int:
    from .report.outputs import check_sweep_folder, sweep_resolution, sweep_text, write_sweep
    from .sim.kinematics import Kinematics
    from .sim.workspace import workspace

    mech, _ = load_mechanism(args.file)
    check_sweep_folder(args.out)
    cluster = _cluster(args)
    ws = workspace(mech, samples=args.samples, seed=args.seed, method=args.method,
                   resolution=sweep_resolution(mech, args.resolution),
                   kinematics=Kinematics(mech, device=_driver_device(args, cluster)), progress=_Progress("sweep"),
                   cluster=cluster)
    doc = write_sweep(ws, mech, args.out)
    _emit_json(doc) if args.json else print(sweep_text(ws, mech, doc["files"]))
    return 0


def cmd_collisions(args) -> int:
    from .report.collisions import check_collisions_folder, collisions_text, environment_meshes, write_collisions
    from .sim.collisions import collisions

    mech, _ = load_mechanism(args.file)
    check_collisions_folder(args.out)
    cluster = _cluster(args)
    result = collisions(mech, samples=args.samples, seed=args.seed, padding=args.padding * mech.length_factor,
                        environment=environment_meshes(mech, args.env), device=_driver_device(args, cluster),
                        progress=None if args.json else _Progress("collisions"), cluster=cluster)
    for w in result.warnings:
        print(w, file=sys.stderr)
    doc = write_collisions(result, args.out)
    _emit_json(doc) if args.json else print(collisions_text(result, mech, doc["files"]))
    return 0


def cmd_cable(args) -> int:
    from .report.cables import cable_trajectories, cables_text, check_cable_folder, write_cables
    from .sim.cables import CableOptions, simulate_cables

    mech, _ = load_mechanism(args.file)
    check_cable_folder(args.out)
    trajectories = cable_trajectories(mech, args.trajectory, args.random, args.envs, args.seconds, args.seed)
    f = mech.length_factor
    options = CableOptions(frame_rate=args.frame_rate, substeps=args.substeps, density=args.density,
                           min_bend_radius=None if args.min_bend_radius is None else args.min_bend_radius * f,
                           floor=None if args.no_floor else args.floor * f, record=0 if args.usd else -1,
                           device=args.device)
    cluster = _cluster(args)
    progress = _Progress("cable", unit="environment" if cluster else "frame")
    run = simulate_cables(mech, trajectories, args.envs, args.seconds, options,
                          progress=None if args.json else progress, cluster=cluster)
    for w in run.warnings:
        print(w, file=sys.stderr)
    doc = write_cables(run, mech, args.out, usd=args.usd)
    _emit_json(doc) if args.json else print(cables_text(run, doc["files"]))
    return 0


def _cluster(args):
    """``--ray [ADDRESS]`` as a Cluster (None without it); Ray missing is said here, first."""
    if args.ray is None:
        return None
    from .sim.cluster import Cluster, ray_module

    ray_module()
    return Cluster(address=None if args.ray == "local" else args.ray, device=args.device)


def _driver_device(args, cluster) -> str:
    """The device of this machine's share of a run (MoveIt's rounds, clearances, refining extremes):
    ``--device``, as on the workers, so a Ray run equals a local one; the CPU, with a warning,
    where this machine lacks it."""
    if cluster is None or args.device == "cpu":
        return args.device
    from .sim.launch import warp_device

    try:
        warp_device(args.device)
        return args.device
    except InputError:
        print(f"rswarp: warning: this machine has no '{args.device}': its share of the run goes on the CPU, so "
              f"the results may differ in the last digits from a run all on '{args.device}'", file=sys.stderr)
        return "cpu"


def cmd_build(args) -> int:
    from .report.library import build_library, build_text

    build = build_library(args.file, args.out, layout=args.layout, size=args.size, device=args.device,
                          progress=None if args.json else _Progress("build", unit="asset"))
    _emit_json(build.report()) if args.json else print(build_text(build))
    return 0 if build.ok else 1


def cmd_export(args) -> int:
    from .export import export
    from .export.physics import PhysicsOptions
    from .report.exports import export_dict, export_text

    report = checked(args.file)
    physics = PhysicsOptions(density=args.density, mass=args.mass, collision=args.collision,
                             drive_hz=args.drive_hz or None, armature=args.armature, effort=args.effort,
                             velocity=args.velocity, disabled=_collision_matrix(report.model, args))
    result = export(report.model, args.output, layout=args.layout, mesh_paths=args.mesh_paths, physics=physics)
    for w in result.warnings:
        print(w, file=sys.stderr)
    _emit_json(export_dict(result)) if args.json else print(export_text(result))
    return 0


def _collision_matrix(model, args) -> tuple:
    """The disabled pairs of ``--collision-matrix FILE``, or of a sweep of ``--collision-samples N``."""
    from .export.frames import mechanism_of

    if args.collision_matrix is None and args.collision_samples is None:
        return ()
    mech = mechanism_of(model)[0]
    if args.collision_matrix is not None:
        from .export.srdf import read_srdf

        return read_srdf(args.collision_matrix, mech.link_names)
    from .sim.collisions import collisions

    return tuple(collisions(mech, samples=args.collision_samples).disabled())


def cmd_demo(args) -> int:
    from .report.demo import run_demo

    demo = run_demo(args.out, say=(lambda text: None) if args.json else print)
    if args.json:
        _emit_json(demo.as_dict())
    return 0 if demo.ok else 1


RAY_HELP = ("run the batch as tasks on Ray: a local Ray instance on this machine, or the cluster at ADDRESS "
            "('auto', 'ray://host:10001'); workers use --device; needs pip install 'rswarp[ray]'")


class _Progress:
    """A progress bar on stderr (tqdm), fed ``(done, total)`` by the library."""

    def __init__(self, label: str, unit: str = "sample"):
        self.label, self.unit, self.bar = label, unit, None

    def __call__(self, done: int, total: int) -> None:
        if self.bar is None:
            from tqdm import tqdm

            self.bar = tqdm(total=total, desc=self.label, unit=self.unit, unit_scale=self.unit == "sample",
                            file=sys.stderr, mininterval=0.5)
        self.bar.update(done - self.bar.n)
        if done >= total:
            self.bar.close()


class _Parser(argparse.ArgumentParser):
    """argparse with a usage error on one line (``rswarp sweep: --seed: must be at least 0, ...``)."""

    def error(self, message: str):
        self.exit(1, f"{self.prog}: {one_line(message)} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="rswarp", description="ABB RobotStudio RSXML robot models: check them, export them to OpenUSD, "
                                   "Newton and URDF, and run batched Warp kinematics and workspace sweeps.")
    parser.add_argument("--debug", action="store_true", help="show the traceback of an internal error")
    parser.add_argument("--max-file-size", type=_positive, metavar="MIB", default=DEFAULT_MAX_FILE_SIZE / 2**20,
                        help=f"largest input file read, in MiB (default {DEFAULT_MAX_FILE_SIZE // 2**20})")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    json_help = "machine-readable output (metres, radians, snake_case keys)"
    device_help = 'Warp device: "cpu" (default) or "cuda" / "cuda:N"'

    p = sub.add_parser("check", help="validate RSXML, LibraryCompiler and LibraryResource files")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("--json", action="store_true", help=json_help)
    p.set_defaults(func=cmd_check)

    p = sub.add_parser("info", help="show what a file describes, in its own units")
    p.add_argument("file", metavar="FILE")
    p.add_argument("--json", action="store_true", help=json_help)
    p.set_defaults(func=cmd_info)

    p = sub.add_parser("fk", help="link and flange poses for one set of joint values")
    p.add_argument("file", metavar="FILE")
    p.add_argument("--q", required=True, help='active joint values in the file\'s units, e.g. "0,0,0,0,30,0"')
    p.add_argument("--json", action="store_true", help=json_help)
    p.add_argument("--device", default="cpu", help=device_help)
    p.set_defaults(func=cmd_fk)

    p = sub.add_parser("sweep", help="workspace over the joint limits: reach, voxels, work-range figures")
    p.add_argument("file", metavar="FILE")
    p.add_argument("--samples", type=_count(1), default=1_000_000, help="joint configurations (default 1000000)")
    p.add_argument("--out", required=True, metavar="DIR", help="folder for workspace.npz, side.png, top.png, report.json")
    p.add_argument("--method", choices=["random", "sobol", "grid"], default="random")
    p.add_argument("--seed", type=_count(0), default=0, help="random and sobol sampling seed, >= 0 (default 0)")
    p.add_argument("--resolution", type=_positive, help="voxel size in the file's length unit (default 25 mm)")
    p.add_argument("--json", action="store_true", help=json_help)
    p.add_argument("--device", default="cpu", help=device_help)
    p.add_argument("--ray", nargs="?", const="local", metavar="ADDRESS", help=RAY_HELP)
    p.set_defaults(func=cmd_sweep)

    _collisions_parser(sub, json_help, device_help)

    _export_parser(sub, json_help)

    _build_parser(sub, json_help, device_help)

    _cable_parser(sub, json_help, device_help)

    p = sub.add_parser("demo", help="run rswarp on the bundled example robots")
    p.add_argument("--out", default="rswarp-demo", metavar="DIR", help="where the exports go (default ./rswarp-demo)")
    p.add_argument("--json", action="store_true", help=json_help)
    p.set_defaults(func=cmd_demo)
    return parser



def _collisions_parser(sub, json_help: str, device_help: str) -> None:
    """``rswarp collisions``: the sweep, its padding and environment, and where the matrix goes."""
    p = sub.add_parser("collisions", help="self-collision sweep over the joint limits and the MoveIt collision matrix")
    p.add_argument("file", metavar="FILE")
    p.add_argument("--samples", type=_count(1), default=1_000_000, help="random configurations (default 1000000)")
    p.add_argument("--out", required=True, metavar="DIR",
                   help="folder for collision_matrix.srdf, report.json and heatmap.png")
    p.add_argument("--seed", type=_count(0), default=0, help="sampling seed, >= 0 (default 0)")
    p.add_argument("--padding", type=_non_negative, default=0.0,
                   help="pairs closer than this (file's length unit) count as colliding (default 0)")
    p.add_argument("--env", action="append", default=[], metavar="MESH@x,y,z",
                   help="an environment mesh placed in the world (file's length unit), tested against every "
                        "link; repeat for more")
    p.add_argument("--json", action="store_true", help=json_help)
    p.add_argument("--device", default="cpu", help=device_help)
    p.add_argument("--ray", nargs="?", const="local", metavar="ADDRESS", help=RAY_HELP)
    p.set_defaults(func=cmd_collisions)


def _cable_parser(sub, json_help: str, device_help: str) -> None:
    """``rswarp cable``: the environments, their trajectories, and how the cables are judged."""
    from .sim.cable import DENSITY
    from .sim.cables import FRAME_RATE, SUBSTEPS

    p = sub.add_parser("cable", help="cable (dress-pack) dynamics in many environments, each robot on its own "
                                     "trajectory: tension, bend radius, clearance, slack, twist")
    p.add_argument("file", metavar="FILE")
    p.add_argument("--envs", type=_count(1), default=16, help="parallel environments (default 16)")
    how = p.add_mutually_exclusive_group(required=True)
    how.add_argument("--trajectory", action="append", metavar="CSV",
                     help="joint trajectory, time,<joint>,... in the file's units; repeat for more (assigned "
                          "round-robin)")
    how.add_argument("--random", action="store_true", help="smooth random trajectories within the limits, one "
                                                         "per environment")
    p.add_argument("--seconds", type=_positive, help="simulated time (default: the longest trajectory; 10 with "
                                                     "--random)")
    p.add_argument("--seed", type=_count(0), default=0, help="seed of the random trajectories (default 0)")
    p.add_argument("--out", required=True, metavar="DIR",
                   help="folder for report.json, tension.png, bend_radius.png, clearance.png (and playback.usdc)")
    p.add_argument("--usd", action="store_true", help="also write playback.usdc: environment 0's robot and cables "
                                                      "over time, for usdview")
    p.add_argument("--min-bend-radius", type=_positive, metavar="R",
                   help="allowed bend radius in the file's length unit (default ten times the diameter)")
    p.add_argument("--floor", type=_finite, default=0.0, help="height of the floor in the file's length unit "
                                                            "(default 0)")
    p.add_argument("--no-floor", action="store_true", help="no floor")
    p.add_argument("--density", type=_positive, default=DENSITY, help=f"kg/m^3 (default {DENSITY:g}, a hose)")
    p.add_argument("--frame-rate", type=_positive, default=FRAME_RATE,
                   help=f"results per simulated second (default {FRAME_RATE:g})")
    p.add_argument("--substeps", type=_count(1), default=SUBSTEPS, help=f"steps per frame (default {SUBSTEPS})")
    p.add_argument("--json", action="store_true", help=json_help)
    p.add_argument("--device", default="cpu", help=device_help)
    p.add_argument("--ray", nargs="?", const="local", metavar="ADDRESS", help=RAY_HELP)
    p.set_defaults(func=cmd_cable)


def _build_parser(sub, json_help: str, device_help: str) -> None:
    """``rswarp build``: a LibraryCompiler XML to packaged USD assets with previews."""
    p = sub.add_parser("build", help="build the assets of a LibraryCompiler XML: USD with metadata and a preview")
    p.add_argument("file", metavar="LIBRARY.xml")
    p.add_argument("-o", "--out", metavar="DIR", help="where the assets go (default: beside the XML)")
    p.add_argument("--layout", choices=["usdz", "component"], default="usdz",
                   help="one .usdz per asset (default), or a folder per asset: an interface layer with payloaded "
                        "geometry/materials/physics layers and the preview PNG")
    p.add_argument("--size", type=_count(16), default=512, help="preview image width and height in pixels (default 512)")
    p.add_argument("--json", action="store_true", help=json_help)
    p.add_argument("--device", default="cpu", help=device_help)
    p.set_defaults(func=cmd_build)


def _export_parser(sub, json_help: str) -> None:
    """``rswarp export``: the output, its layout, and how the robot simulates."""
    p = sub.add_parser("export", help="write OpenUSD (.usda/.usdc/.usdz) or URDF (.urdf)")
    p.add_argument("file", metavar="FILE")
    p.add_argument("-o", "--output", required=True, metavar="OUT")
    p.add_argument("--layout", choices=["flat", "component"],
                   help="USD only: one file (default), or an interface layer with payloaded geometry/materials/"
                        "physics layers")
    p.add_argument("--mesh-paths", choices=["absolute", "relative"],
                   help="URDF only: name the meshes/ files by absolute path (default: every loader finds them, "
                        "pinocchio included) or relative to the URDF (a folder that can be moved)")
    p.add_argument("--collision", choices=["convexHull", "convexDecomposition"], default="convexHull",
                   help="collision geometry rswarp computes once (cached): a convex hull per part (default), or "
                        "a convex decomposition with CoACD")
    p.add_argument("--density", type=_positive, default=DEFAULT_DENSITY,
                   help=f"kg/m^3 for link masses (default {DEFAULT_DENSITY:g}, cast aluminium)")
    p.add_argument("--mass", type=_positive, metavar="KG",
                   help="the robot's total mass: scales the density so the links weigh this in all")
    p.add_argument("--drive-hz", type=_non_negative, default=DRIVE_HZ, metavar="HZ",
                   help=f"bandwidth of the position drives holding home (default {DRIVE_HZ:g}; 0: no drives)")
    p.add_argument("--armature", type=_non_negative, metavar="KGM2",
                   help="motor reflected inertia for every joint, kg m^2 (kg for prismatic joints); default "
                        "1e-3 x total mass x reach^2")
    p.add_argument("--effort", type=_positive, metavar="NM",
                   help="effort limit for every joint, N m (N); default twice the largest gravity load plus "
                        "10 rad/s^2 of acceleration")
    matrix = p.add_mutually_exclusive_group()
    matrix.add_argument("--collision-matrix", metavar="SRDF",
                        help="filter every pair an SRDF disables (from 'rswarp collisions' or MoveIt) from contact")
    matrix.add_argument("--collision-samples", type=_count(1), metavar="N",
                        help="run a collision sweep of N samples and filter every pair its matrix disables")
    p.add_argument("--velocity", type=_positive, metavar="RAD_S",
                   help="velocity limit for every joint, rad/s (m/s); default 90 deg/s (0.5 m/s)")
    p.add_argument("--json", action="store_true", help=json_help)
    p.set_defaults(func=cmd_export)

def _number(text: str, *, zero: bool) -> float:
    """A finite number > 0 (>= 0 with ``zero``); ``inf`` and ``nan`` are refused here, not deep
    inside a computation."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not (math.isfinite(value) and (value >= 0 if zero else value > 0)):
        raise argparse.ArgumentTypeError(f"must be a finite number {'>=' if zero else '>'} 0, not '{text}'")
    return value


def _finite(text: str) -> float:
    """Any finite number (a floor may lie below the base)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, not '{text}'")
    return value


def _positive(text: str) -> float:
    return _number(text, zero=False)


def _non_negative(text: str) -> float:
    return _number(text, zero=True)


def _count(least: int):
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"'{text}' is not a whole number") from None
        if value < least:
            raise argparse.ArgumentTypeError(f"must be at least {least}, not {value}")
        return value
    parse.__name__ = "whole number"
    return parse


def _joined_values(argv: list[str]) -> list[str]:
    """``--q -90,0,...``: a value that starts with '-' is the option's value, not an option."""
    out, skip = [], False
    for i, a in enumerate(argv):
        if skip:
            skip = False
        elif a == "--q" and i + 1 < len(argv) and argv[i + 1].startswith("-"):
            out.append(f"--q={argv[i + 1]}")
            skip = True
        else:
            out.append(a)
    return out


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(_joined_values(sys.argv[1:] if argv is None else argv))
    except SystemExit as exc:  # a usage error is the user's (exit 1), --help is exit 0
        return 1 if exc.code else 0
    try:
        with file_size_limit(int(args.max_file_size * 2**20)):
            return args.func(args)
    except RsxmlError as exc:
        for d in exc.diagnostics:
            print(str(d), file=sys.stderr)
        return 1
    except InputError as exc:
        print(f"rswarp: {one_line(str(exc))}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130
    except Terminated:  # SIGTERM during a write: temporary files are gone, the usual status
        return 143
    except BrokenPipeError:
        return 0
    except Exception as exc:  # a bug, not bad input
        if args.debug or os.environ.get("RSWARP_DEBUG"):
            raise
        print(f"rswarp: internal error: {type(exc).__name__}: {exc} (rerun with --debug for the traceback)",
              file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
