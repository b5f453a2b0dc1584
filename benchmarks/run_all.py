"""Every benchmark, one after another, and what each printed in one file: ``benchmarks/results.json``
(the machine, the date, the versions of rswarp and of each peer, and per script its command, wall
time, exit status, its JSON lines and its printed tables). The figures of the README's Measured
table are read from this file by ``tests/test_measured.py``.

Usage: python benchmarks/run_all.py [--only bench_ik,bench_fk] [--quick]. ``--only`` runs those
and keeps the others' entries from the file as they were. Scripts run in turn, never side by side:
each has the machine to itself.

A run on another machine (a lent GPU) is recorded beside them, with that machine said:
``python benchmarks/run_all.py --record bench_dresspack_h200 OUTPUT --on "NVIDIA H200, 16-core host"
--command "python benchmarks/bench_dresspack.py --device cuda"``, OUTPUT being what it printed (UTF-8
text with at least one metric line; anything else is refused and the file is left as it was).

The file is strict JSON (a non-finite number is written as null, and read back only if strict; a
recorded line whose ``ours`` or ``ratio`` is not a finite number is refused) and is written whole or
not at all: a temporary file beside it, then a rename (through a symlink, beside the file it points
to, which is replaced; the link is kept). Bad input (a missing or
unreadable OUTPUT, a broken results file) ends in one line and exit 1.
"""

from __future__ import annotations

import argparse
import datetime
import importlib.metadata
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
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
    "bench_cycle": ([], []),
    "bench_preview": ([], ["--repeats", "1"]),
    "bench_video": ([], ["--seconds", "2"]),
    "bench_cable": ([], ["--quick"]),
    "bench_cable_whole_run": (["--whole-run"], ["--whole-run", "--quick"]),
    "bench_dresspack": ([], ["--designs", "64", "--alone", "2"]),
    "bench_ray": ([], ["--quick"]),
    "bench_place": ([], ["--quick"]),
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
    out["rswarp_commit"] = commit()
    return out


def commit() -> str | None:
    """The checkout's commit, with ``+changes`` where its tracked files differ from it (results
    files aside): the code a run measured, said as it was."""
    def git(*args):
        return subprocess.run(["git", *args], cwd=HERE, text=True, capture_output=True, check=True).stdout

    try:
        head = git("rev-parse", "--short", "HEAD").strip()
        ours = {RESULTS.name, QUICK.name}
        changed = [line for line in git("status", "--porcelain", "--untracked-files=no").splitlines()
                   if Path(line[3:].strip()).name not in ours]
    except (OSError, subprocess.CalledProcessError):
        return None
    return f"{head}+changes" if changed else head


def fail(message: str):
    """End the run with one line on stderr and exit 1."""
    sys.exit(f"run_all.py: {' '.join(str(message).split())}")


def finite(value):
    """``value`` with every non-finite float (NaN, infinities) as None: JSON has no such numbers."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite(v) for v in value]
    return value


def _no_constant(name: str):
    raise ValueError(f"{name} is not JSON")


MEASURED = ("ours", "ratio")  # a metric line's figures that must be numbers where it gives them: refused as NaN


def metric_lines(text: str, source: str, strict: bool = False) -> tuple[list[dict], list[str]]:
    """The metric lines of a script's output (``{"metric": ...}``), their non-finite numbers
    (``NaN``, ``Infinity``, ``1e999``) as None, and a ``source:line: why`` for each that is no JSON
    object (nested too deep, or, with ``strict``, whose ``ours`` or ``ratio`` is not finite)."""
    lines, bad = [], []
    for n, line in enumerate(text.splitlines(), 1):
        if not (line.startswith("{") and '"metric"' in line):
            continue
        try:
            found = json.loads(line, parse_constant=lambda c: math.nan)
        except RecursionError:
            bad.append(f"{source}:{n}: a metric line nested too deep to be one")
            continue
        except ValueError as exc:
            bad.append(f"{source}:{n}: a metric line that is not JSON ({getattr(exc, 'msg', exc)})")
            continue
        if not isinstance(found, dict):
            bad.append(f"{source}:{n}: a metric line that is not a JSON object")
            continue
        broken = [k for k in MEASURED if isinstance(found.get(k), float) and not math.isfinite(found[k])]
        if strict and broken:
            bad.append(f"{source}:{n}: {' and '.join(broken)} {'is' if len(broken) == 1 else 'are'} not a finite "
                       "number: nothing to record")
            continue
        lines.append(finite(found))
    return lines, bad


def load_results(path: Path) -> dict:
    """A results file read strictly (UTF-8, JSON without NaN or Infinity, an object whose
    ``benchmarks`` is an object); one line and exit 1 for anything else."""
    try:
        text = path.read_bytes().decode("utf-8")
        doc = json.loads(text, parse_constant=_no_constant)
    except OSError as exc:
        fail(f"{path}: cannot read: {exc.strerror or exc}")
    except UnicodeDecodeError as exc:
        fail(f"{path}: not UTF-8 text (byte {exc.start}); restore it from git")
    except json.JSONDecodeError as exc:
        fail(f"{path}:{exc.lineno}: not JSON ({exc.msg}; truncated?); restore it from git")
    except RecursionError:
        fail(f"{path}: nested too deep to be a results file; restore it from git")
    except ValueError as exc:
        fail(f"{path}: not strict JSON ({exc}); restore it from git")
    if not isinstance(doc, dict) or not isinstance(doc.get("benchmarks", {}), dict):
        fail(f"{path}: not a results file (an object with a 'benchmarks' object); restore it from git")
    return doc


def write_results(path: Path, doc: dict) -> None:
    """``doc`` as strict JSON into ``path``, whole or not at all: a temporary file beside it, then
    a rename (an interrupted or failed write leaves the old file and no temporary one)."""
    text = json.dumps(finite(doc), indent=1, allow_nan=False) + "\n"
    path = Path(os.path.realpath(path))  # through a symlink: the file it points to is replaced, the link kept
    tmp = None
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
        tmp = None
    except OSError as exc:
        fail(f"{path}: cannot write: {exc.strerror or exc}")
    finally:
        if tmp is not None:
            Path(tmp).unlink(missing_ok=True)


def run(name: str, quick: bool) -> dict:
    args = RUNS[name][1 if quick else 0]
    script = HERE / f"{name.split('_whole')[0]}.py"
    command = [sys.executable, str(script), *args]
    print(f"{name}: {' '.join(command[1:])}", flush=True)
    start = time.perf_counter()
    try:
        p = subprocess.run(command, capture_output=True, text=True, errors="replace", timeout=TIMEOUT,
                           env=os.environ | {"PYTHONUNBUFFERED": "1"})
        code, out, err = p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired as exc:
        code, out, err = None, exc.stdout or "", f"timed out after {TIMEOUT} s"
        out = out.decode(errors="replace") if isinstance(out, bytes) else out
    wall = time.perf_counter() - start
    lines, bad = metric_lines(out, name)  # a bad line is said in the entry, not a lost hour's run
    err = "\n".join([*bad, err]) if bad else err
    print(f"  {wall:.0f} s, exit {code}, " + "; ".join([*(f"{d.get('metric')}: ratio {d.get('ratio')}"
                                                          for d in lines), *bad]), flush=True)
    return {"command": ["python", f"benchmarks/{script.name}", *args], "seconds": round(wall, 1),
            "returncode": code, "results": lines, "output": out[-20000:], "errors": err[-4000:]}


def record(name: str, output: Path, on: str, command: str) -> dict:
    """An entry for a run made elsewhere: its machine, its command and what it printed (UTF-8 text
    with one metric line or more); one line and exit 1 for anything else."""
    if not any(name.startswith(f"{r}_") for r in RUNS):
        fail(f"a recorded run is named after its script, as bench_dresspack_h200, not {name}")
    try:
        if not output.is_file() and output.exists():  # a folder, a FIFO: never opened
            raise IsADirectoryError(0, "a folder, not a file" if output.is_dir() else "not a regular file")
        with open(output, "rb") as fh:
            data = fh.read()
            date = datetime.date.fromtimestamp(os.fstat(fh.fileno()).st_mtime).isoformat()
        out = data.decode("utf-8")
    except OSError as exc:
        fail(f"{output}: cannot read: {exc.strerror or exc}")
    except UnicodeDecodeError as exc:
        fail(f"{output}: not UTF-8 text (byte {exc.start}): give what the script printed")
    lines, bad = metric_lines(out, str(output), strict=True)
    if bad:
        fail(f"{bad[0]}" + (f" (and {len(bad) - 1} more)" if len(bad) > 1 else ""))
    if not lines:
        fail(f"{output}: no metric line (a JSON line with \"metric\"): nothing to record for {name}")
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
    ap.add_argument("--results", type=Path, metavar="FILE",
                    help=f"the results file (default {RESULTS.name}, or {QUICK.name} with --quick)")
    args = ap.parse_args()
    if args.record:
        if not (args.on and args.command):
            fail("--record needs --on MACHINE and --command COMMAND")
        path = args.results or RESULTS
        doc = load_results(path)  # a broken file is said before anything is read or written
        entry = record(args.record[0], Path(args.record[1]), args.on, args.command)
        doc.setdefault("benchmarks", {})[args.record[0]] = entry
        write_results(path, doc)
        print(f"recorded {args.record[0]} in {path}")
        return
    names = list(RUNS) if not args.only else [n.strip() for n in args.only.split(",")]
    unknown = [n for n in names if n not in RUNS]
    if unknown:
        sys.exit(f"run_all.py: unknown benchmark(s) {', '.join(unknown)}; known: {', '.join(RUNS)}")
    path = args.results or (QUICK if args.quick else RESULTS)
    old = load_results(path) if args.only and path.exists() else {}
    results = old.get("benchmarks", {})
    for name in names:
        results[name] = run(name, args.quick) | {"date": datetime.date.today().isoformat(), "commit": commit()}
    now = versions()  # with --only, a peer not installed now keeps the version the kept entries ran with
    kept = {k: v for k, v in old.get("versions", {}).items() if now.get(k) is None and v is not None}
    doc = {"machine": machine(), "date": datetime.date.today().isoformat(), "versions": now | kept,
           "quick": args.quick, "benchmarks": results}
    write_results(path, doc)
    print(f"wrote {path}")
    failed = [n for n in names if results[n]["returncode"] != 0]
    if failed:
        sys.exit(f"run_all.py: {', '.join(failed)} failed (their output and errors are in {path.name})")


if __name__ == "__main__":
    main()
