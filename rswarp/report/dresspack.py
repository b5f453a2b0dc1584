"""``rswarp dresspack``: a design sweep of one dress-pack hose over a RAPID program. The designs
(``--vary``: its length, its clamps shifted and tilted in their links' axes) are drawn by Sobol over
the box and run at once, one environment each (``rswarp.sim.designs``); each gets the verdict
``rswarp cable`` gives (``report.verdicts``) and its margins per rating. The shortest passing design
is written as ``best.rsxml`` (with the robot data beside it, its meshes where they were), so that
``rswarp cable best.rsxml --program ...`` runs the same hose and gives the same verdict."""

from __future__ import annotations

import csv
import io
import math
import os
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Callable

import numpy as np

from ..config import BatchOptions, DesignOptions, HoseOptions, TaskOptions, VideoOptions, routed
from ..errors import InputError
from ..files import atomic_write, read_regular
from ..kinematics.trajectory import Trajectory
from ..motion.cells import base_offsets, floor_in_robot, is_cell
from ..outputs import atomic_folder
from ..rsxml.cable_spans import LENGTH_TOLERANCE, MAX_CABLE_SEGMENTS, cable_spans
from ..rsxml.cell import read_cell
from ..rsxml.documents import load_mechanism
from ..rsxml.robot_data import data_file
from ..rsxml.write import to_rsxml
from ..sim.cable.results import CableResult
from ..sim.cables import SWING_AFTER, design_runs, simulate_cables
from ..sim.designs import DesignSet, Variable, design, inside_links, parse_vary, sample
from ..sim.engine import cluster_for
from .cable_lines import fatigue_line
from .cables import check_cable_folder, check_video_options, rated_fatigue, run_findings
from .dresspack_options import cable_options, ratings_of, repeat_command
from .figures import figure_png
from .output import Output, Warn, ignore, json_bytes, json_safe
from .verdicts import FAIL, Ratings, verdict, verdict_lines

MARGINS = ("bend", "taut", "torsion", "rub", "clamp")  # the ratings a design's margin is taken against
SLIM_MARGIN = 0.05  # a chosen design's least margin under this is said to be slim


@dataclass(frozen=True)
class DesignRow:
    """One design's outcome: its values (SI, tilts in rad), hose length, verdict, failing kinds, the
    margin to each rating (1 - value/limit; for the bend radius limit/value's complement) and the
    least of them, and its findings."""

    index: int
    values: tuple[float, ...]
    length: float
    verdict: str
    fails: tuple[str, ...]
    margins: dict
    least: float
    findings: tuple
    result: CableResult

    @property
    def stopped(self) -> bool:
        """Run, but stopped (a crush): no margin, no figures."""
        return self.result is not None and not math.isfinite(self.least)


def run_dresspack(path: str, programs: list[str], out: str, task: TaskOptions | None = None,
                  hose: HoseOptions | None = None, design: DesignOptions | None = None,
                  batch: BatchOptions | None = None, video: VideoOptions | None = None, *,
                  progress: Callable[[float, float], None] | None = None, warn: Warn = ignore,
                  **changes) -> Output:
    """``rswarp dresspack``: ``design.designs`` designs of ``design.cable`` (``design.vary``: specs,
    or one TOML file of them) over the RAPID task ``programs`` run as ``task`` says, ranked, written
    into ``out``: the chosen design is the shortest hose that passes with ``design.min_margin`` % to
    every rating of ``hose``; the options as ``rswarp cable --program`` takes them (the robot file's
    length unit); ``video``: the chosen design's run rendered there, as ``rswarp cable --video``
    renders one. ``changes`` replace fields of the options (``vary=["length=1:2"]``, ``designs=8``)."""
    o = routed(changes, task=task or TaskOptions(), hose=hose or HoseOptions(), design=design or DesignOptions(),
               batch=batch or BatchOptions(), video=video or VideoOptions())
    task, hose, sweep, batch, video = o["task"], o["hose"], o["design"], o["batch"], o["video"]
    cell = read_cell(path) if is_cell(path) else None
    mech, _ = load_mechanism(cell.robot.rsxml if cell is not None else path)
    placed = replace(task, floor=floor_in_robot(cell, mech, task.floor))  # the floor in the robot's frame
    rated = rated_fatigue(hose.rated_cycles, mech)
    drawn, short = _drawn(mech, sweep.cable, sweep.vary, sweep.designs, batch.seed)
    k = drawn.cable
    run_set = DesignSet(k, drawn.variables, np.delete(drawn.values, list(short), axis=0))
    ratings = ratings_of(mech, hose)
    check_cable_folder(out)
    check_video_options(video.video, None, video.video_color, 1, out)
    # the sweep keeps each design's least clearances, never their series: a frame measures only lower ones
    options = replace(cable_options(mech, placed, hose, batch.device), frame_clearances=False)
    plan = _task_plan(path, programs, task, warn)
    trajectories = [Trajectory(", ".join(plan.run.files), plan.times, plan.q, base=base_offsets(cell, plan))]
    start = time.perf_counter()
    run = simulate_cables(mech, trajectories, len(run_set), None, options, progress=progress,
                          cluster=cluster_for(batch.ray, batch.device), designs=run_set)
    seconds = time.perf_counter() - start
    kept = [i for i in range(len(drawn)) if i not in short]
    runs = design_runs(run)
    rows = [_row(kept[i], run_set.values[i], r, k, trajectories, plan.moves, ratings) for i, r in enumerate(runs)]
    rows = sorted(rows + [_short_row(i, drawn.values[i], why) for i, why in short.items()], key=lambda r: r.index)
    keep = sweep.min_margin / 100.0
    best = _best(rows, keep)
    command = repeat_command(out, programs, placed, hose, best.verdict == "PASS")
    doc = _doc(mech, drawn, rows, best, seconds, command, ratings) | {"min_margin": keep}
    _write(out, mech, drawn, rows, best, doc)
    text = _text(mech, drawn, rows, best, seconds, plan, command, keep, rated)
    if video.video is not None:
        text += _video(mech, drawn, best, runs[kept.index(best.index)] if best.result is not None else None,
                       trajectories, plan, doc, video.video, video.video_color, video.video_size)
    return Output(doc, text)


def _drawn(mech, cable: str | None, vary: list[str], designs: int, seed: int) -> tuple:
    """(every design drawn, {index: why} of those too short to lay out); an InputError where all
    are, or a design's rest shape crosses a link."""
    k = _cable_index(mech, cable)
    variables = parse_vary(_specs(vary), mech.cables[k])
    drawn = DesignSet(k, variables, sample(variables, designs, seed))
    mechs = drawn.mechanisms(mech)
    short = _too_short(mechs, k)
    if len(short) == len(drawn):
        raise InputError(f"--vary: every design's hose is shorter than the path through its control points (design "
                         f"1: {next(iter(short.values()))}); raise the length range")
    _check_inside(mech, k, [m for d, m in enumerate(mechs) if d not in short])
    return drawn, short


def _task_plan(path: str, programs: list[str], task: TaskOptions, warn: Warn):
    """The RAPID task's plan the designs run over; an error where it stops before its first move."""
    from ..motion.plan import moved_before_stop, program_plan

    _, plan = program_plan(path, programs, task, warn=warn)
    moved_before_stop(plan)
    return plan


def _video(mech, drawn, best, run, trajectories, plan, doc: dict, video: str, color: str, size: int) -> str:
    """The chosen design's run rendered into ``video`` (``doc['video']``), and its line of text."""
    if run is None:  # not run (too short to lay out): nothing to show
        return f"\nvideo: none (design {best.index + 1} was not run)"
    from .videos import cable_video

    picked = design(mech, drawn.cable, drawn.variables, drawn.values[best.index])
    doc["video"] = cable_video(picked, run, trajectories, video, 0, color, size, plan.moves,
                               label=f"design {best.index + 1}") | {"design": best.index + 1}
    return f"\nvideo: {video} (design {best.index + 1}, {doc['video']['frames']} frames)"


def _cable_index(mech, name: str | None) -> int:
    names = [c.name for c in mech.cables]
    if not names:
        raise InputError(f"{mech.path or mech.name}: the mechanism has no Cable to vary")
    if name is None:
        if len(names) > 1:
            raise InputError(f"{mech.path}: {len(names)} cables ({', '.join(names)}); name the one to vary with "
                             "--cable")
        return 0
    if name not in names:
        raise InputError(f"--cable '{name}': {mech.path} has {', '.join(names)}")
    return names.index(name)


def _specs(vary: list[str]) -> list[str]:
    """``--vary`` as specs: as given, or read from one TOML file (``NAME = "MIN:MAX"`` or
    ``NAME = [MIN, MAX]``, under ``[vary]`` or at its top)."""
    if not vary:
        raise InputError("give at least one --vary (length=MIN:MAX, or LINK.x=MIN:MAX ...), or a TOML file of them")
    if len(vary) != 1 or not vary[0].lower().endswith(".toml"):
        return list(vary)
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib
    path = vary[0]
    try:
        table = tomllib.loads(read_regular(path).decode("utf-8"))
    except OSError as exc:
        raise InputError(f"{path}: cannot read the TOML file of variables: {exc.strerror or exc}") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: not a TOML file of variables ({exc})") from None
    except RecursionError:
        raise InputError(f"{path}: not a TOML file of variables (nested too deep)") from None
    table = table.get("vary", table)
    if not isinstance(table, dict):
        raise InputError(f"{path}: 'vary' must be a table of NAME = \"MIN:MAX\" or NAME = [MIN, MAX] ([vary], or "
                         f"at the file's top), not {_toml_kind(table)}")
    specs = []
    for name, value in table.items():
        if isinstance(value, list) and len(value) == 2 and not any(isinstance(v, (list, dict)) for v in value):
            value = f"{value[0]}:{value[1]}"
        if not isinstance(value, str):
            raise InputError(f"{path}: '{name}' must be \"MIN:MAX\" or [MIN, MAX], not {_toml_kind(value)}")
        specs.append(f"{name}={value}")
    if not specs:
        raise InputError(f"{path}: no variables; give NAME = \"MIN:MAX\" lines, under [vary] or at the top")
    return specs


def _toml_kind(value) -> str:
    """What a TOML value is, in TOML's words."""
    kinds = ((bool, "a boolean"), (int, "an integer"), (float, "a float"), (str, "a string"), (list, "an array"),
             (dict, "a table"))
    return next((word for kind, word in kinds if isinstance(value, kind)), "a date or time")


def _too_short(mechs, cable: int) -> dict[int, str]:
    """The designs whose hose is shorter than the path through their control points at rest: they
    cannot be laid out, so they are rows that fail, not environments. A design that fails for
    another reason (a hose too long for ``MAX_CABLE_SEGMENTS`` segments of ``maxSegmentLength``,
    two control points shifted onto one place) is the sweep's error, said before any work."""
    out, refused = {}, []
    for d, m in enumerate(mechs):
        try:
            cable_spans(m.cables[cable], m.length_factor)
        except ValueError as exc:
            if _short(m.cables[cable]):
                out[d] = str(exc).split(": ", 1)[-1]
            else:
                refused.append((d, m, str(exc)))
    if refused:
        d, m, why = refused[0]
        c = m.cables[cable]
        more = f" (and {len(refused) - 1} more)" if len(refused) > 1 else ""
        chords = np.linalg.norm(np.diff([p.position for p in c.control_points], axis=0), axis=1)
        if len(chords) and (chords > 0).all():  # neither short nor two points at one place: too many segments
            fits = (MAX_CABLE_SEGMENTS - len(chords)) * c.max_segment_length
            wanted = math.ceil(c.desired_length / c.max_segment_length)
            raise InputError(f"--vary: design {d + 1}'s hose of {c.desired_length:g} m{more} would be about "
                             f"{wanted:.3g} segments of at most {c.max_segment_length / m.length_factor:g} "
                             f"(maxSegmentLength), and a cable takes at most {MAX_CABLE_SEGMENTS}: keep the length "
                             f"range under about {fits:.4g} m, or raise maxSegmentLength")
        raise InputError(f"--vary: design {d + 1}{more}: {why}; narrow the shift ranges")
    return out


def _short(c) -> bool:
    """Whether cable ``c`` (SI) is shorter than the path through its control points."""
    chords = np.linalg.norm(np.diff([p.position for p in c.control_points], axis=0), axis=1)
    path = float(chords.sum())
    return len(chords) > 0 and (chords > 0).all() and c.desired_length is not None and \
        c.desired_length < path * (1 - LENGTH_TOLERANCE)


def _check_inside(mech, cable: int, mechs) -> None:
    """A design with a clamp inside its link at rest cannot be built: refused before any work."""
    inside = inside_links(mech, cable, tuple(mechs))
    if inside:
        more = f" (and {len(inside) - 1} more)" if len(inside) > 1 else ""
        raise InputError(f"--vary: {inside[0]} at rest{more}: a clamp cannot sit inside its link; narrow the "
                         "shift ranges")


def _short_row(index: int, values, why: str) -> DesignRow:
    return DesignRow(index, tuple(float(v) for v in values), math.nan, "FAIL", ("short",), {}, -math.inf,
                     (why,), None)


def _row(index: int, values, run, cable: int, trajectories, moves, ratings: Ratings) -> DesignRow:
    """A design's verdict and margins; one that stopped has no margin (least: -inf)."""
    c = run.cables[cable]
    found = [f for f in run_findings(run, trajectories, moves, ratings) if f.cable == c.name]
    stopped = str(c.status[0]) != "ok"
    margins = {} if stopped else _margins(c, ratings)
    least = -math.inf if stopped else min(margins.values())
    fails = tuple(sorted({f.kind for f in found if f.severity == FAIL}))
    return DesignRow(index, tuple(float(v) for v in values), c.length, verdict(found), fails, margins, least,
                     tuple(found), c)


def _margins(c: CableResult, r: Ratings) -> dict:
    """Each rating's margin for environment 0: 1 - value/limit (the bend radius: 1 - allowed/value),
    positive when within it."""
    strain = float(c.peak_tension[0]) / c.axial_stiffness
    out = {"bend": 1.0 - c.allowed_bend_radius / max(float(c.min_bend_radius[0]), 1e-12),
           "taut": 1.0 - strain / r.max_strain, "torsion": 1.0 - float(c.max_twist_rate[0]) / r.max_torsion}
    if r.max_contact_force is not None:
        out["rub"] = 1.0 - float(c.peak_normal[0]) / r.max_contact_force
    if r.max_clamp_load is not None and c.clamp_force.shape[1]:
        out["clamp"] = 1.0 - float(np.nanmax(c.clamp_force[0])) / r.max_clamp_load
    return out


def _best(rows: list[DesignRow], min_margin: float = 0.0) -> DesignRow:
    """The passing design with the shortest hose (ties: the larger least margin) of those keeping
    ``min_margin`` to every rating; none such, the one with the fewest failing kinds and the
    largest least margin."""
    passing = [r for r in rows if r.verdict == "PASS" and r.least >= min_margin]
    if passing:
        return min(passing, key=lambda r: (round(r.length, 9), -r.least))
    return min(rows, key=lambda r: (r.least == -math.inf, len(r.fails), -r.least, r.length))


def _design(chosen: DesignSet, r: DesignRow) -> str:
    """A design's hose length, then the other variables' values as --vary names them."""
    rest = [f"{v.name} {_shown(v, x)}" for v, x in zip(chosen.variables, chosen.values[r.index]) if v.what != "length"]
    return ", ".join([f"hose {r.length:.4f} m", *rest])


def _shown(v: Variable, x: float) -> str:
    return f"{v.given(x):.1f} deg" if v.unit == "deg" else f"{x * 1000:.1f} mm" if v.what != "length" else f"{x:.4f} m"


def _contrast(rows: list[DesignRow], best: DesignRow) -> DesignRow | None:
    """A failing design to show beside the best: the failing one nearest it in length."""
    failing = [r for r in rows if r.verdict == "FAIL" and r is not best and r.result is not None]
    return min(failing, key=lambda r: abs(r.length - best.length)) if failing else None


def _text(mech, chosen: DesignSet, rows: list[DesignRow], best: DesignRow, seconds: float, plan,
          command: str, keep: float, rated: tuple[float, float] | None = None) -> str:
    passing = sum(r.verdict == "PASS" for r in rows)
    short = sum(r.result is None for r in rows)
    stopped = sum(r.stopped for r in rows)
    c = mech.cables[chosen.cable]
    ranges = "; ".join(f"{v.name} {_shown(v, v.low)} to {_shown(v, v.high)}" for v in chosen.variables)
    lines = [f"dresspack: {len(rows)} designs of cable '{c.name}' over {', '.join(plan.run.files)} "
             f"({plan.times[-1]:.2f} s, and {SWING_AFTER:g} s still after it: the hose swings on) in {seconds:.1f} s "
             f"({len(rows) / seconds:.1f} designs/s)",
             f"  varied: {ranges}", f"  passing: {passing} of {len(rows)}" + (
                 f"; {short} too short for the path through their control points, not run" if short else "") + (
                 f"; {stopped} stopped (a crush, in designs.csv's 'stopped')" if stopped else "")]
    lines += [_head(best, passing, keep) + f": {_design(chosen, best)}, " + (
        f"least margin {best.least:.1%} ({_tightest(best)})" if math.isfinite(best.least) else _why_stopped(best))]
    if best.verdict == "PASS" and best.least < SLIM_MARGIN and not keep:
        lines.append(f"  its least margin is {best.least:.1%}: a design this near a rating passes or fails by the "
                     "model's own error; --min-margin PCT chooses the shortest that keeps more")
    lines += verdict_lines(best.result, list(best.findings))
    if rated is not None and best.result is not None and not best.stopped:  # --rated-cycles: the passes it lasts
        lines.append(fatigue_line(best.result, np.array([0]), max(len(plan.cycles), 1), rated))
    lines.append(f"  {command}")
    other = _contrast(rows, best)
    if other is not None and passing:
        lines.append(f"a failing design beside it: design {other.index + 1}: {_design(chosen, other)}")
        lines += verdict_lines(other.result, list(other.findings))
    return "\n".join(lines)


def _head(best: DesignRow, passing: int, keep: float) -> str:
    """The chosen design's heading: the shortest passing with ``keep`` (a fraction) to every rating,
    the passing one with the most where none keeps it, or the closest to passing."""
    if best.verdict == "PASS" and best.least >= keep:
        keeps = f" with {keep * 100:g} % to every rating" if keep else ""
        return f"best: design {best.index + 1}, the shortest hose that passes{keeps}"
    if best.verdict == "PASS":
        return (f"no design passes with {keep * 100:g} % to every rating ({passing} pass); the one with the most: "
                f"design {best.index + 1}")
    return f"no design passes; the closest: design {best.index + 1}"


def _tightest(row: DesignRow) -> str:
    if not row.margins:
        return "no rating measured"
    kind = min(row.margins, key=row.margins.get)
    return f"{kind} {row.margins[kind]:+.1%}"


def _doc(mech, chosen: DesignSet, rows: list[DesignRow], best: DesignRow, seconds: float, command: str,
         ratings: Ratings) -> dict:
    return json_safe({
        "robot": mech.path, "cable": mech.cables[chosen.cable].name, "designs": len(rows), "seconds": seconds,
        "designs_per_second": len(rows) / seconds,
        "variables": [{"name": v.name, "what": v.what, "point": v.point, "low": v.low, "high": v.high}
                      for v in chosen.variables],
        "ratings": {"max_strain": ratings.max_strain, "max_torsion": ratings.max_torsion,
                    "max_contact_force": ratings.max_contact_force, "max_clamp_load": ratings.max_clamp_load},
        "passing": sum(r.verdict == "PASS" for r in rows), "best": _row_dict(chosen, best, True),
        "best_passes": best.verdict == "PASS", "check": command,
        "rows": [_row_dict(chosen, r, False) for r in rows]})


def _row_dict(chosen: DesignSet, r: DesignRow, findings: bool) -> dict:
    out = {"design": r.index + 1, "values": dict(zip((v.name for v in chosen.variables), r.values)),
           "length": r.length, "verdict": r.verdict, "fails": list(r.fails), "margins": r.margins,
           "least_margin": r.least if math.isfinite(r.least) else None, "stopped": _why_stopped(r) or None}
    if findings:
        out["findings"] = [f if isinstance(f, str) else f.record() for f in r.findings]
    return out


def _csv(chosen: DesignSet, rows: list[DesignRow]) -> bytes:
    """One row per design, each column's unit in its name (a tilt in degrees, as --vary takes it);
    a design that stopped or was not run has no margins, radius or tension, and says why."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["design", *(f"{v.name}_{v.unit}" for v in chosen.variables), "hose_m", "verdict", "fails",
                *(f"{k}_margin" for k in MARGINS), "least_margin", "bend_radius_m", "peak_tension_n", "stopped"])
    for r in rows:
        ran = math.isfinite(r.least)  # run to its end: its figures are there
        w.writerow([r.index + 1, *(f"{v.given(x):.6g}" for v, x in zip(chosen.variables, r.values)),
                    f"{r.length:.6f}", r.verdict, " ".join(r.fails),
                    *(f"{r.margins[k]:.4f}" if k in r.margins else "" for k in MARGINS),
                    f"{r.least:.4f}" if ran else "",
                    *((f"{float(r.result.min_bend_radius[0]):.4f}", f"{float(r.result.peak_tension[0]):.3f}")
                      if ran else ("", "")), _why_stopped(r)])
    return buf.getvalue().encode()


def _why_stopped(r: DesignRow) -> str:
    """Why a design has no margins: not run (its hose too short), or its run stopped."""
    if r.result is None:
        return f"not run: {r.findings[0]}" if r.findings else "not run"
    status = str(r.result.status[0])
    return "" if status == "ok" else status


def _pareto(rows: list[DesignRow], best: DesignRow) -> bytes:
    def draw(ax):
        for ok, colour, mark, label in ((True, "tab:green", "o", "passes"), (False, "tab:red", "x", "fails")):
            pick = [r for r in rows if (r.verdict == "PASS") == ok and "bend" in r.margins]
            if pick:
                ax.scatter([r.length for r in pick], [100 * r.margins["bend"] for r in pick], c=colour, marker=mark,
                           s=18, label=label)
        ax.scatter([best.length], [100 * best.margins.get("bend", np.nan)], s=160, marker="*", c="gold",
                   edgecolors="black", zorder=3,
                   label=f"{'best' if best.verdict == 'PASS' else 'closest'}: design {best.index + 1}")
        ax.axhline(0.0, color="black", lw=0.8)
        stopped = [r.length for r in rows if r.stopped]
        if stopped:  # no margin to plot: marked along the bottom
            ax.scatter(stopped, [ax.get_ylim()[0]] * len(stopped), marker="v", c="dimgray", s=30, clip_on=False,
                       label="stopped (a crush): no margin")

    return figure_png(draw, "Designs: hose length against bend-radius margin", "hose length (m)",
                      "bend margin (%: 1 - allowed / least radius)")


def _write(out: str, mech, chosen: DesignSet, rows: list[DesignRow], best: DesignRow, doc: dict) -> None:
    """designs.csv, pareto.png, the chosen design as best.rsxml (closest.rsxml when none passes),
    with the robot data beside it, and report.json (``doc``, its files added), as one set."""
    target = Path(out)
    name = "best" if best.verdict == "PASS" else "closest"
    data = data_file(mech.path)
    files = {"designs": "designs.csv", "pareto": "pareto.png", name: f"{name}.rsxml", "report": "report.json"} | (
        {"robot_data": f"{name}.robot.toml"} if data else {})
    doc["files"] = {k: str(target / v) for k, v in files.items()}
    picked = design(mech, chosen.cable, chosen.variables, chosen.values[best.index])
    xml = portable(to_rsxml(picked), Path(mech.path).parent, target)
    with atomic_folder(target) as tmp:
        atomic_write(tmp / files["designs"], _csv(chosen, rows))
        atomic_write(tmp / files["pareto"], _pareto(rows, best))
        atomic_write(tmp / files[name], xml)
        if data:
            atomic_write(tmp / files["robot_data"], read_regular(data))
        atomic_write(tmp / files["report"], json_bytes(doc))


def portable(xml: bytes, source_dir: Path, out_dir: Path) -> bytes:
    """The RSXML with every relative ``source`` rewritten to be relative to ``out_dir``, so a file
    written there finds the same meshes."""
    from lxml import etree

    root = etree.fromstring(xml, etree.XMLParser(resolve_entities=False, no_network=True))
    for el in root.iter():
        src = el.get("source")
        if src and not os.path.isabs(src):
            el.set("source", os.path.relpath(os.path.abspath(source_dir / src), os.path.abspath(out_dir)))
    return etree.tostring(root, xml_declaration=True, encoding="utf-8", pretty_print=True)
