"""Every benchmark, one after another, and what each printed in one file: ``benchmarks/results.json``
(the machine, the date, the versions of rswarp and of each peer, and per script its command, wall
time, exit status, its JSON lines and its printed tables). The figures of the README's Measured
table are read from this file by ``tests/test_measured.py``.

Usage: python benchmarks/run_all.py [--only bench_ik,bench_fk] [--quick]. ``--only`` runs those
and keeps the others' entries from the file as they were. Scripts run in turn, never side by side:
each has the machine to itself.

A run on another machine (a lent GPU) is recorded beside them, with that machine said:
``python benchmarks/run_all.py --record bench_dresspack_h200 OUTPUT --on "NVIDIA H200, 16-core host"
--command "python benchmarks/bench_dresspack.py --device cuda"``, OUTPUT being what it printed.
"""

from __future__ import annotations

import argparse
import datetime
import importlib.metadata
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results.json"
QUICK = HERE / "results-quick.json"  # a --quick run's file: its figures are not the docs'; not kept
# script: its arguments for the figures the docs show (and with --quick, for a check it runs)
RUNS = {
    "bench_fk": ([], ["--sizes", "10000,100000"]),
    "bench_ik": ([], ["--quick"]),
    "bench_collisions": ([], ["--states", "20000", "--peer-states", "1000", "--matrix", "0", "--per-pair", "0"]),
    "bench_loops": ([], ["--n", "10000"]),
    "bench_check": ([], ["--sizes", "10000,100000"]),
    "bench_program": ([], ["--quick"]),
    "bench_preview": ([], ["--repeats", "1"]),
    "bench_video": ([], ["--seconds", "2"]),
    "bench_cable": ([], ["--quick"]),
    "bench_cable_whole_run": (["--whole-run"], ["--whole-run", "--quick"]),
    "bench_dresspack": ([], ["--designs", "64", "--alone", "2"]),
    "bench_ray": ([], ["--quick"]),
}
PEERS = ("warp-lang", "newton", "numpy", "pin", "python-fcl", "coal", "mujoco", "mujoco-warp", "pyelastica",
         "eaik", "ik-geo", "roboticstoolbox-python", "ikpy", "trimesh", "embreex", "ray")
TIMEOUT = 3600  # s a script may take


def machine() -> dict:
    return {"platform": platform.platform(), "processor": platform.processor() or platform.machine(),
            "cores": os.cpu_count(), "python": platform.python_version()}


def versions() -> dict:
    out = {}
    for name in ("rswarp", *PEERS):
        try:
            out[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            out[name] = None
    try:
        out["rswarp_commit"] = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=HERE, text=True,
                                              capture_output=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        out["rswarp_commit"] = None
    return out


def run(name: str, quick: bool) -> dict:
    args = RUNS[name][1 if quick else 0]
    script = HERE / f"{name.split('_whole')[0]}.py"
    command = [sys.executable, str(script), *args]
    print(f"{name}: {' '.join(command[1:])}", flush=True)
    start = time.perf_counter()
    try:
        p = subprocess.run(command, capture_output=True, text=True, timeout=TIMEOUT,
                           env=os.environ | {"PYTHONUNBUFFERED": "1"})
        code, out, err = p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired as exc:
        code, out, err = None, exc.stdout or "", f"timed out after {TIMEOUT} s"
        out = out.decode() if isinstance(out, bytes) else out
    wall = time.perf_counter() - start
    lines = [json.loads(line) for line in out.splitlines() if line.startswith("{") and '"metric"' in line]
    print(f"  {wall:.0f} s, exit {code}, " + "; ".join(f"{d['metric']}: ratio {d.get('ratio')}" for d in lines),
          flush=True)
    return {"command": ["python", f"benchmarks/{script.name}", *args], "seconds": round(wall, 1),
            "returncode": code, "results": lines, "output": out[-20000:], "errors": err[-4000:]}


def record(name: str, output: Path, on: str, command: str) -> dict:
    """An entry for a run made elsewhere: its machine, its command and what it printed."""
    if not any(name.startswith(f"{r}_") for r in RUNS):
        sys.exit(f"run_all.py: a recorded run is named after its script, as bench_dresspack_h200, not {name}")
    out = output.read_text()
    lines = [json.loads(line) for line in out.splitlines() if line.startswith("{") and '"metric"' in line]
    date = datetime.date.fromtimestamp(output.stat().st_mtime).isoformat()
    return {"command": command.split(), "machine": on, "returncode": 0, "results": lines, "output": out,
            "errors": "", "date": date}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--record", nargs=2, metavar=("NAME", "OUTPUT"), help="add a run made on another machine")
    ap.add_argument("--on", help="with --record: the machine it ran on")
    ap.add_argument("--command", help="with --record: the command it ran")
    ap.add_argument("--only", help="comma-separated names (bench_fk, ...): run these, keep the others' entries")
    ap.add_argument("--quick", action="store_true", help="small sizes, into results-quick.json: a check that every "
                                                          "script runs, not the docs' figures")
    args = ap.parse_args()
    if args.record:
        if not (args.on and args.command):
            sys.exit("run_all.py: --record needs --on MACHINE and --command COMMAND")
        doc = json.loads(RESULTS.read_text())
        doc["benchmarks"][args.record[0]] = record(args.record[0], Path(args.record[1]), args.on, args.command)
        RESULTS.write_text(json.dumps(doc, indent=1) + "\n")
        print(f"recorded {args.record[0]} in {RESULTS}")
        return
    names = list(RUNS) if not args.only else [n.strip() for n in args.only.split(",")]
    unknown = [n for n in names if n not in RUNS]
    if unknown:
        sys.exit(f"run_all.py: unknown benchmark(s) {', '.join(unknown)}; known: {', '.join(RUNS)}")
    path = QUICK if args.quick else RESULTS
    old = json.loads(path.read_text()) if args.only and path.exists() else {}
    results = old.get("benchmarks", {})
    for name in names:
        results[name] = run(name, args.quick) | {"date": datetime.date.today().isoformat()}
    now = versions()  # with --only, a peer not installed now keeps the version the kept entries ran with
    kept = {k: v for k, v in old.get("versions", {}).items() if now.get(k) is None and v is not None}
    doc = {"machine": machine(), "date": datetime.date.today().isoformat(), "versions": now | kept,
           "quick": args.quick, "benchmarks": results}
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(doc, indent=1) + "\n")
    os.replace(tmp, path)
    print(f"wrote {path}")
    failed = [n for n in names if results[n]["returncode"] != 0]
    if failed:
        sys.exit(f"run_all.py: {', '.join(failed)} failed (their output and errors are in {path.name})")


if __name__ == "__main__":
    main()
