"""The ``rswarp`` command line. It orchestrates; the work is done in the modules it calls.

Bad input ends with one ``file:line: message`` line per problem and a non-zero exit, never a
traceback (set RSWARP_DEBUG=1 to see one for an internal error).
"""

from __future__ import annotations

import argparse
import json
import os
import sys

from .documents import Report, check
from .errors import RsxmlError
from .info import report_dict, report_text
from .geometry import DEFAULT_DENSITY
from .model import Mechanism, SmartComponent
from .poses import limit_warnings


def _emit_json(obj) -> None:
    print(json.dumps(obj, indent=2, allow_nan=False))


def _print_problems(report: Report, stream) -> None:
    for d in report.all_diagnostics:
        print(str(d), file=stream)


def cmd_check(args) -> int:
    reports = [check(f) for f in args.files]
    if args.json:
        _emit_json({"ok": all(r.ok for r in reports), "files": [
            {"path": r.path, "kind": r.kind, "ok": r.ok,
             "errors": [{"file": d.file, "line": d.line, "message": d.message} for d in r.errors],
             "warnings": [{"file": d.file, "line": d.line, "message": d.message} for d in r.warnings]}
            for r in reports]})
    else:
        for r in reports:
            _print_problems(r, sys.stdout)
            state = "OK" if r.ok else "FAILED"
            print(f"{r.path}: {state} ({r.kind}; {len(r.errors)} error{'s' * (len(r.errors) != 1)}, "
                  f"{len(r.warnings)} warning{'s' * (len(r.warnings) != 1)})")
    return 0 if all(r.ok for r in reports) else 1


def _checked(path: str) -> Report:
    """A report without errors, or RsxmlError (printed by main as file:line lines)."""
    report = check(path)
    if report.errors:
        raise RsxmlError(report.errors)
    return report


def cmd_info(args) -> int:
    report = _checked(args.file)
    if args.json:
        _emit_json(report_dict(report))
    else:
        _print_problems(report, sys.stderr)  # warnings only
        print(report_text(report))
    return 0


def cmd_demo(args) -> int:
    """check + info on every bundled example; for each robot also its flange at home (fk), its reach
    (a short sweep) and its USD and URDF exports into --out."""
    from pathlib import Path

    from . import examples

    out = Path(args.out)
    results, summary = [], []
    for path in examples.ALL:
        report = check(path)
        results.append(report)
        if not args.json:
            print(f"== rswarp check {path.name}")
            _print_problems(report, sys.stdout)
            print(f"{'OK' if report.ok else 'FAILED'}: {len(report.errors)} errors, {len(report.warnings)} warnings")
            print(f"== rswarp info {path.name}")
            print(report_text(report) if report.model is not None else "(nothing to show)")
            print()
        if report.ok and isinstance(report.model, Mechanism):
            summary.append(_demo_robot(report.model, out, quiet=args.json))
    if args.json:
        _emit_json({"ok": all(r.ok for r in results), "examples": [report_dict(r) for r in results], "robots": summary})
    return 0 if all(r.ok for r in results) else 1


def _demo_robot(mech: Mechanism, out, quiet: bool) -> dict:
    from .export_urdf import to_urdf
    from .export_usd import to_usd
    from .kinematics import Kinematics
    from .sweeps import workspace

    kin = Kinematics(mech)
    home = mech.home_position()
    flange = kin.flange(home[None])[0]
    ws = workspace(mech, samples=20_000, seed=0, kinematics=kin)
    out.mkdir(parents=True, exist_ok=True)
    usd, urdf = out / f"{mech.name}.usdc", out / f"{mech.name}.urdf"
    warnings = to_usd(mech, usd) + to_urdf(mech, urdf)
    lf, unit = mech.length_factor, mech.length_unit or "m"
    if not quiet:
        from .poses import rounded

        pos = ", ".join(rounded(float(v), lf, 1e-4) for v in flange[:3, 3])
        print(f"== {mech.name}: flange at home ({pos}) {unit}; reach {rounded(ws.reach.value, lf, 1e-4)} {unit} "
              f"(J1 axis to wrist centre, 20000 samples refined)")
        for w in warnings[:1]:
            print(f"   {w}")
        print(f"   exported {usd} and {urdf}")
        print()
    return {"name": mech.name, "flange_at_home": flange[:3, 3].astype(float).tolist(), "reach": ws.reach.value,
            "usd": str(usd), "urdf": str(urdf)}


def _joint_values(report: Report, text: str):
    """``--q`` in the file's units -> SI; a bad value or count is a one-line error."""
    import numpy as np

    mech = report.model
    names = [j.name for j in mech.active_joints]
    try:
        values = [float(v) for v in text.replace(",", " ").split()]
    except ValueError:
        raise SystemExit(f"rswarp: --q: '{text}' is not a list of numbers") from None
    if len(values) != len(names) or not all(np.isfinite(values)):
        raise SystemExit(f"rswarp: --q needs {len(names)} finite values ({', '.join(names)}), got '{text}'")
    return np.array([v * mech.joint_factor(j) for v, j in zip(values, mech.active_joints)])


def cmd_fk(args) -> int:
    from .poses import pose_dict, pose_text

    report = _checked(args.file)
    mech = report.model
    if not isinstance(mech, Mechanism):
        raise SystemExit(f"rswarp: {args.file} is a {report.kind}, not a mechanism")
    q = _joint_values(report, args.q)
    for warning in limit_warnings(mech, q):
        print(warning, file=sys.stderr)
    kin = _kinematics(mech, args.device)
    links = kin.fk(q[None])[0]
    flanges = {f.name: kin.flange(q[None], f.name)[0] for f in mech.flanges}
    if args.json:
        _emit_json({"q": q.tolist(), "links": {n: pose_dict(m) for n, m in zip(kin.links, links)},
                    "flanges": {n: pose_dict(m) for n, m in flanges.items()}})
    else:
        print(pose_text(mech, list(zip(kin.links, links)), list(flanges.items())))
    return 0


def _kinematics(mech: Mechanism, device: str):
    """Kinematics on the device asked for; an unavailable device is a one-line error."""
    from .kinematics import Kinematics

    try:
        return Kinematics(mech, device=device)
    except ValueError as exc:
        raise SystemExit(f"rswarp: {exc}") from None


class _Progress:
    """A progress bar on stderr (a line per tenth when stderr is not a terminal)."""

    def __init__(self, label: str):
        self.label, self.tty, self.shown = label, sys.stderr.isatty(), -1

    def __call__(self, done: int, total: int) -> None:
        frac = done / max(total, 1)
        if self.tty:
            bar = "#" * int(frac * 30)
            print(f"\r{self.label} [{bar:<30}] {frac:4.0%} ({done}/{total})", end="", file=sys.stderr, flush=True)
            if done >= total:
                print(file=sys.stderr)
        elif int(frac * 10) > self.shown:
            self.shown = int(frac * 10)
            print(f"{self.label}: {frac:.0%} ({done}/{total})", file=sys.stderr, flush=True)


def cmd_sweep(args) -> int:
    from pathlib import Path

    from .figures import work_range_figures
    from .units import format_number
    from .sweeps import save_voxels, workspace
    from .write import atomic_write

    report = _checked(args.file)
    mech = report.model
    if not isinstance(mech, Mechanism):
        raise SystemExit(f"rswarp: {args.file} is a {report.kind}, not a mechanism")
    if args.samples < 1:
        raise SystemExit("rswarp: --samples must be at least 1")
    lf = mech.length_factor
    resolution = (args.resolution * lf) if args.resolution is not None else 0.025
    if not resolution > 0:
        raise SystemExit("rswarp: --resolution must be positive")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    try:
        ws = workspace(mech, samples=args.samples, seed=args.seed, method=args.method, resolution=resolution,
                       kinematics=_kinematics(mech, args.device), progress=_Progress("sweep"))
    except ValueError as exc:  # nothing to measure: no flange
        raise SystemExit(f"rswarp: {args.file}: {exc}") from None
    files = {"voxels": out / "workspace.npz", "report": out / "report.json"}
    save_voxels(ws, files["voxels"])
    if ws.reach is not None:
        files["side_view"], files["top_view"] = out / "side.png", out / "top.png"
        work_range_figures(ws, mech, files["side_view"], files["top_view"])
    doc = ws.report() | {"files": {k: str(v) for k, v in files.items()}}
    atomic_write(files["report"], (json.dumps(doc, indent=2) + "\n").encode())
    if args.json:
        _emit_json(doc)
        return 0
    unit = mech.length_unit or "m"

    def length(v):
        return f"{format_number(round(v / lf, 1 if lf < 0.01 else 4) * lf, lf)} {unit}"

    print(f"{mech.name}: {ws.samples} {ws.method} samples (seed {ws.seed}) within the joint limits")
    if ws.reach is not None:
        print(f"  reach (J1 axis to wrist centre): {length(ws.reach.value)}  (best sample {length(ws.reach.sampled)})")
        print(f"  wrist centre height: {length(ws.wrist_low.value)} to {length(ws.wrist_high.value)}")
    print(f"  flange reach: {length(ws.flange_reach.value)}")
    print(f"  flange height: {length(ws.flange_low.value)} to {length(ws.flange_high.value)}")
    print("  wrote " + ", ".join(str(p) for p in files.values()))
    return 0


def cmd_export(args) -> int:
    from pathlib import Path

    report = _checked(args.file)
    model = report.model
    if not isinstance(model, (Mechanism, SmartComponent)):
        raise SystemExit(f"rswarp: {args.file} is a {report.kind}: only a mechanism exports")
    out = Path(args.output)
    if not out.parent.is_dir():
        raise SystemExit(f"rswarp: {out.parent}: no such folder")
    if not args.density > 0:
        raise SystemExit("rswarp: --density must be positive")
    if out.suffix.lower() == ".urdf":
        from .export_urdf import to_urdf

        if isinstance(model, SmartComponent):
            raise SystemExit("rswarp: URDF export takes a mechanism file")
        warnings = to_urdf(model, out, density=args.density)
    elif out.suffix.lower() in (".usda", ".usdc", ".usd", ".usdz"):
        from .export_usd import to_usd

        try:
            warnings = to_usd(model, out, density=args.density, collision=args.collision, layout=args.layout)
        except ValueError as exc:  # nothing to export (a SmartComponent without a mechanism)
            raise SystemExit(f"rswarp: {args.file}: {exc}") from None
    else:
        raise SystemExit(f"rswarp: {out}: the output must end in .usda, .usdc, .usdz or .urdf")
    for w in warnings:
        print(w, file=sys.stderr)
    if args.json:
        _emit_json({"output": str(out), "warnings": warnings})
    else:
        print(f"wrote {out}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="rswarp", description="ABB RobotStudio RSXML robot models: check them, export them to OpenUSD, "
                                   "Newton and URDF, and run batched Warp kinematics and workspace sweeps.")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("check", help="validate RSXML, LibraryCompiler and LibraryResource files")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=cmd_check)

    p = sub.add_parser("info", help="show what a file describes, in its own units")
    p.add_argument("file", metavar="FILE")
    p.add_argument("--json", action="store_true", help="machine-readable output (SI units)")
    p.set_defaults(func=cmd_info)

    p = sub.add_parser("fk", help="link and flange poses for one set of joint values")
    p.add_argument("file", metavar="FILE")
    p.add_argument("--q", required=True, help='active joint values in the file\'s units, e.g. "0,0,0,0,30,0"')
    p.add_argument("--json", action="store_true", help="machine-readable output (metres, 4x4 matrices)")
    p.add_argument("--device", default="cpu", help='Warp device: "cpu" (default) or "cuda" / "cuda:N"')
    p.set_defaults(func=cmd_fk)

    p = sub.add_parser("sweep", help="workspace over the joint limits: reach, voxels, work-range figures")
    p.add_argument("file", metavar="FILE")
    p.add_argument("--samples", type=int, default=1_000_000, help="joint configurations (default 1000000)")
    p.add_argument("--out", required=True, metavar="DIR", help="folder for workspace.npz, side.png, top.png, report.json")
    p.add_argument("--method", choices=["random", "sobol", "grid"], default="random")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--resolution", type=float, help="voxel size in the file's length unit (default 25 mm)")
    p.add_argument("--json", action="store_true", help="print the report as JSON (metres, radians)")
    p.add_argument("--device", default="cpu", help='Warp device: "cpu" (default) or "cuda" / "cuda:N"')
    p.set_defaults(func=cmd_sweep)

    p = sub.add_parser("export", help="write OpenUSD (.usda/.usdc/.usdz) or URDF (.urdf)")
    p.add_argument("file", metavar="FILE")
    p.add_argument("-o", "--output", required=True, metavar="OUT")
    p.add_argument("--layout", choices=["flat", "component"], default="flat",
                   help="USD: one file, or an interface layer with payloaded geometry/materials/physics layers")
    p.add_argument("--collision", choices=["convexHull", "convexDecomposition"], default="convexHull")
    p.add_argument("--density", type=float, default=DEFAULT_DENSITY,
                   help=f"kg/m^3 for link masses (default {DEFAULT_DENSITY:g}, cast aluminium)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_export)

    p = sub.add_parser("demo", help="run rswarp on the bundled example robots")
    p.add_argument("--out", default="rswarp-demo", metavar="DIR", help="where the exports go (default ./rswarp-demo)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=cmd_demo)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except RsxmlError as exc:
        for d in exc.diagnostics:
            print(str(d), file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:
        return 0
    except Exception as exc:  # a bug, not bad input: one line unless asked for the traceback
        if os.environ.get("RSWARP_DEBUG"):
            raise
        print(f"rswarp: internal error: {type(exc).__name__}: {exc} (set RSWARP_DEBUG=1 for details)",
              file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
