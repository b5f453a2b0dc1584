"""The ``rswarp`` command line: each command parses its arguments, calls one library function
(``rswarp.report``'s ``run_*``), its options gathered into the typed objects of ``rswarp.config`` and prints
its ``Output``. Bad input (``InputError``) ends with one ``file:line: message`` line per problem
and exit 1; anything else is an internal error, exit 2, with its traceback under ``--debug``."""

from __future__ import annotations

import argparse
import dataclasses
import importlib
import inspect
import os
import signal
import sys
import time
import traceback

from .config import OPTION_KINDS, from_namespace
from .errors import InputError, RsxmlError, one_line
from .files import DEFAULT_MAX_FILE_SIZE, Terminated, file_size_limit, interrupted, note_interrupts, signals_held
from .options import argument

RAY_HELP = ("run the batch as tasks on Ray: a local Ray instance on this machine, or the cluster at ADDRESS "
            "('auto', 'ray://host:10001'); workers use --device; needs pip install 'rswarp[ray]'")


class _Parser(argparse.ArgumentParser):
    """argparse with a usage error on one line (``rswarp sweep: --seed: must be at least 0, ...``)."""

    def error(self, message: str):
        self.exit(1, f"{self.prog}: {one_line(message)} (see {self.prog} --help)\n")


def _parents() -> dict[str, argparse.ArgumentParser]:
    """The options several commands share, each defined once."""
    made = {}
    for name, add in (
            ("json", lambda p: p.add_argument("--json", action="store_true",
                                              help="machine-readable output (metres, radians, snake_case keys)")),
            ("device", lambda p: p.add_argument("--device", default="cpu",
                                                help='Warp device: "cpu" (default) or "cuda" / "cuda:N"')),
            ("ray", lambda p: p.add_argument("--ray", nargs="?", const="local", metavar="ADDRESS", help=RAY_HELP)),
            ("seed", lambda p: p.add_argument("--seed", type=argument("seed"), default=0,
                                              help="sampling seed, >= 0 (default 0)")),
            ("out", lambda p: p.add_argument("--out", required=True, metavar="DIR", help="the output folder"))):
        made[name] = argparse.ArgumentParser(add_help=False)
        add(made[name])
    return made


SIMULATED = "s simulated"  # a cable run's progress: its simulated seconds, every environment at once
# command -> (library entry as "module:function", progress unit, help, parents)
COMMANDS = {
    "check": ("info:run_check", None, "validate RSXML, LibraryCompiler and LibraryResource files, and cell files",
              ("json",)),
    "info": ("info:run_info", None, "show what a file (or a cell file) describes, in its own units", ("json",)),
    "fk": ("poses:run_fk", None, "link and flange poses for one set of joint values", ("json", "device")),
    "sweep": ("sweep:run_sweep", "sample", "workspace over the joint limits: reach, voxels, work-range figures",
              ("json", "device", "ray", "seed", "out")),
    "collisions": ("collisions:run_collisions", "sample",
                   "self-collision sweep over the joint limits and the MoveIt collision matrix",
                   ("json", "device", "ray", "seed", "out")),
    "export": ("exports:run_export", None, "write OpenUSD (.usda/.usdc/.usdz) or URDF (.urdf); from a cell file "
                                           "(.toml), the whole cell as one USD stage", ("json",)),
    "build": ("library:run_build", "asset", "build the assets of a LibraryCompiler XML: USD with metadata and a "
                                            "preview", ("json", "device")),
    "cable": ("cables:run_cables", SIMULATED, "cable (dress-pack) dynamics in many environments, each robot on "
                                                  "its own trajectory: slack, bend radius, tension, clamp loads, "
                                                  "twist and torque, contact and wear",
              ("json", "device", "ray", "seed", "out")),
    "dresspack": ("dresspack:run_dresspack", SIMULATED, "a design sweep of a dress-pack hose over a RAPID "
                                                            "program: its length and clamps varied, every design "
                                                            "run at once, the shortest that passes written out",
                  ("json", "device", "ray", "seed", "out")),
    "program": ("program:run_program", "sample", "run a RAPID routine through the robot: targets by inverse "
                                                 "kinematics with their confdata, the trajectory, and its joint "
                                                 "limits, collisions, floor and singularities",
                ("json", "device", "ray")),
    "place": ("placement.run:run_place", "base", "where the robot should stand: candidate bases scored over every "
                                                 "pose of a RAPID task in one batch, the best run through the whole "
                                                 "program and ranked by cycle time",
              ("json", "device", "ray", "seed", "out")),
    "reach": ("placement.study:run_reach", None, "a reach study of a part for the base where the robot stands: "
                                                "every face approached along its normal, reached, manipulability, "
                                                "joint-limit margin; a coloured PLY", ("json", "device", "out")),
    "demo": ("demo:demo_output", None, "run rswarp on the bundled example robots", ("json",)),
}


# Commands that run a RAPID task and take --payload (``TaskOptions.payload``), a load carried on top
# of the tools' for the whole run.
PAYLOAD_COMMANDS = ("program", "cable", "dresspack")


def _payload(p: argparse.ArgumentParser) -> None:
    p.add_argument("--payload", metavar="KG[@x,y,z] | MODULE:NAME",
                   help="a load carried on top of the tool's for the whole run, lowering the accelerations "
                        "(docs/payload-timing.md): a mass with its centre of gravity in the flange's frame (in the "
                        "file's length unit), or a RAPID tooldata's or loaddata's load (default: none)")


def build_parser() -> argparse.ArgumentParser:
    from . import cli_options

    parser = _Parser(prog="rswarp", description="ABB RobotStudio RSXML robot models: check them, export them to "
                                                "OpenUSD, Newton and URDF, and run batched Warp kinematics, sweeps "
                                                "and cable simulations.")
    parser.add_argument("--debug", action="store_true", help="show the traceback of an internal error")
    parser.add_argument("--max-file-size", type=argument("max-file-size"), metavar="MIB",
                        default=DEFAULT_MAX_FILE_SIZE / 2**20,
                        help=f"largest input file read, in MiB (default {DEFAULT_MAX_FILE_SIZE // 2**20})")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    parents = _parents()
    for name, (entry, unit, text, shared) in COMMANDS.items():
        p = sub.add_parser(name, help=text, parents=[parents[s] for s in shared])
        getattr(cli_options, name)(p)
        if name in PAYLOAD_COMMANDS:
            _payload(p)
        p.set_defaults(entry=entry, unit=unit)
    parser.commands = sub.choices  # each command's parser, for its own usage errors
    return parser


# A library entry's parameters that take a whole options object, by name (``config.OPTION_KINDS``).
OPTION_PARAMETERS = OPTION_KINDS
# What the command line itself uses of the parsed arguments, not the library.
META = frozenset({"command", "entry", "unit", "debug", "max_file_size", "json"})


def entry_of(args):
    """The library function a parsed command names (``report.<module>:<function>``)."""
    module, function = args.entry.split(":")
    return getattr(importlib.import_module(f".report.{module}", __package__), function)


def library_arguments(fn, values: dict) -> tuple[dict, set]:
    """(keyword arguments, the options they leave unused) of ``fn`` from a command's parsed
    options: an options parameter (``OPTION_PARAMETERS``) gets its object built from them once,
    any other parameter the option of its name."""
    kwargs, used = {}, set(META)
    parameters = inspect.signature(fn).parameters
    for name in parameters:
        if name in OPTION_PARAMETERS:
            kind = OPTION_PARAMETERS[name]
            kwargs[name] = from_namespace(kind, values)
            used |= {f.name for f in dataclasses.fields(kind)}
        elif name in values:
            kwargs[name] = values[name]
            used.add(name)
    takes_any = any(p.kind is p.VAR_KEYWORD for p in parameters.values())
    if takes_any and not set(parameters) & set(OPTION_PARAMETERS):  # a plain **kwargs entry: every option
        kwargs |= {k: v for k, v in values.items() if k not in used}
        used = set(values)
    return kwargs, set(values) - used


def _call(args) -> int:
    """The command's library function with its options, then its output printed. An option that
    reaches no parameter is rswarp's bug (exit 2), never dropped silently."""
    fn = entry_of(args)
    names = inspect.signature(fn).parameters
    kwargs, unused = library_arguments(fn, vars(args))
    if unused:
        raise RuntimeError(f"rswarp {args.command}: options that reach no library parameter: {sorted(unused)}")
    quiet = getattr(args, "json", False)
    if "json" in names:
        kwargs["json"] = quiet
    said: list[str] = []  # every warning on stderr, for the JSON's ``warnings`` too

    def warn(line) -> None:
        said.append(str(line))
        _stderr(line)

    if "warn" in names:
        kwargs["warn"] = (lambda line: None) if quiet and args.command == "check" else warn
    if "say" in names:
        kwargs["say"] = (lambda line: None) if quiet else (lambda line: print(line, flush=True))
    if "progress" in names and not quiet:
        kwargs["progress"] = _Progress(args.command, args.unit, _progress_detail(args))
    with _video_progress(args.command, "video" in names and not quiet):
        out = fn(**kwargs)
    FINISHED.append(out.code)  # every output is in place: a SIGTERM from here on stops nothing (``run``)
    if quiet:
        from .report.output import json_text

        print(json_text(_with_warnings(out.doc, said)))
    elif out.text:
        print(out.text)
    for line in out.errors:
        print(line, file=sys.stderr)
    return out.code


def _with_warnings(doc, said: list[str]):
    """The JSON document with every warning said on stderr among its ``warnings`` (in the order
    said, after its own), so that a program reading the JSON misses none."""
    if not isinstance(doc, dict) or not said:
        return doc
    own = list(doc.get("warnings") or [])
    return doc | {"warnings": own + [w for w in dict.fromkeys(said) if w not in own]}


def _stderr(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


class _Progress:
    """One progress bar on stderr (tqdm) for one long loop, fed ``(done, total)`` by the library in
    the unit the bar shows, so that its percentage is its count. Where stderr is not a terminal (a
    log, a pipe) there is no bar: one line when the loop ends says what it did and in how long
    (``cable: 256 environments, 10 s simulated in 12.3 s``)."""

    def __init__(self, label: str, unit: str, detail: str = ""):
        self.label, self.unit, self.detail = label, unit, detail
        self.bar, self.done, self.total, self.start = None, 0.0, None, 0.0

    def __call__(self, done: float, total: float) -> None:
        if self.bar is None:
            from tqdm import tqdm

            self.start, self.total = time.perf_counter(), total
            self.bar = tqdm(total=total, desc=self.label, unit=self.unit, unit_scale=self.unit == "sample",
                            file=sys.stderr, mininterval=0.5, disable=None, bar_format=self._format(total))
        elif self.done >= self.total:  # ended: said once
            return
        self.bar.update(done - self.done)
        self.done = done
        if done >= total:
            hidden = self.bar.disable  # (closing sets it)
            self.bar.close()
            if hidden:
                print(self.ended(total, time.perf_counter() - self.start), file=sys.stderr, flush=True)

    def _format(self, total: float) -> str | None:
        """The bar's count in its unit: seconds to a tenth, samples scaled (1.00M), others whole."""
        if self.unit == "sample":
            return None
        if self.unit == SIMULATED:
            return "{l_bar}{bar}| {n:.1f}/{total:.1f} " + SIMULATED + " [{elapsed}<{remaining}]"
        return "{l_bar}{bar}| {n:.0f}/{total:.0f} {unit}s [{elapsed}<{remaining}]"

    def ended(self, total: float, seconds: float) -> str:
        """The line that stands for the bar where stderr is not a terminal."""
        what = f"{round(total, 2):g} {SIMULATED}" if self.unit == SIMULATED else f"{total:.0f} {self.unit}s"
        return f"{self.label}: {self.detail + ', ' if self.detail else ''}{what} in {seconds:.1f} s"


def _progress_detail(args) -> str:
    """What a bar's closing line says beside its count: a cable run's environments, a sweep's designs."""
    if args.command == "cable":
        from .report.cables import default_envs

        envs = default_envs(args.envs, args.program)
        return f"{envs} environment{'s' * (envs != 1)}"
    if args.command == "dresspack":
        return f"{args.designs} designs"
    return ""


def _video_progress(command: str, shown: bool):
    """A bar on stderr for the frames of a ``--video`` while the command runs (``shown``: not
    under --json)."""
    import contextlib

    if not shown:
        return contextlib.nullcontext()
    from .report.videos import frame_progress

    return frame_progress(_Progress(f"{command} video", "frame"))


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
        args, extra = parser.parse_known_args(_joined_values(sys.argv[1:] if argv is None else argv))
        if extra:  # said by the command's parser, so that it points at the command's --help
            parser.commands[args.command].error(f"unrecognized arguments: {' '.join(extra)}")
    except SystemExit as exc:  # a usage error is the user's (exit 1), --help is exit 0
        return 1 if exc.code else 0
    try:
        with note_interrupts(), file_size_limit(int(args.max_file_size * 2**20)):
            return _call(args)
    except RsxmlError as exc:
        if interrupted():  # a Ctrl-C a library swallowed, or made an error of its own
            return 130
        for d in exc.diagnostics:
            print(str(d), file=sys.stderr)
        return 1
    except InputError as exc:
        if interrupted():
            return 130
        print(f"rswarp: {one_line(str(exc))}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130
    except Terminated:  # SIGTERM during a write: temporary files are gone, the usual status
        return 143
    except BrokenPipeError:
        return 0
    except Exception as exc:  # a bug, not bad input: exit 2, with its traceback under --debug
        if interrupted():
            return 130
        if args.debug or os.environ.get("RSWARP_DEBUG"):
            traceback.print_exc()
        hint = "" if args.debug or os.environ.get("RSWARP_DEBUG") else " (rerun with --debug for the traceback)"
        print(f"rswarp: internal error: {type(exc).__name__}: {one_line(str(exc))}{hint}", file=sys.stderr)
        return 2


FINISHED: list[int] = []  # the command's status, once its library call returned with every output in place
LATE = "rswarp: SIGTERM came after every output was written: they are complete, and the run ends as it would have"


def run() -> None:
    """The ``rswarp`` command: ``main``'s status as the exit code. SIGTERM, one rule: before the
    command's outputs are all in place it stops the run (exit 143, nothing half-written kept);
    after (while the report prints, while Python shuts down) the run is complete: it ends with its
    own status and a line saying so. A Ctrl-C once main is done ends the process with 130 at once,
    its output flushed, never with a traceback."""
    late = []

    def term(signum, frame):  # outside a write (a write holds its own handler): the run's own SIGTERM
        if not FINISHED:
            _flushed()
            os._exit(128 + signum)
        late.append(True)

    signal.signal(signal.SIGTERM, term)
    try:
        code = main()
    except KeyboardInterrupt:
        code = 130
    finally:
        launch = sys.modules.get(f"{__package__}.launch")  # loaded: a launcher may have workers
        if launch is not None:
            with signals_held():
                launch.stop_workers()

    def leave(signum, frame):
        _flushed()
        if signum == signal.SIGTERM and FINISHED:
            print(LATE, file=sys.stderr, flush=True)
            os._exit(code)
        os._exit(128 + signum)

    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, leave)
    if late:
        print(LATE, file=sys.stderr, flush=True)
    sys.exit(code)


def _flushed() -> None:
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass


if __name__ == "__main__":
    run()
