"""What a robot programmer reads of ``rswarp program``: one row per move (``file:line`` when the
task has several files, the routine when it has several), its findings under the table, the
cycle time, the loads the moves carry, and every error of a target the robot cannot take."""

from __future__ import annotations

from pathlib import Path

from .findings import grouped

MAX_ROWS = 200  # moves shown one by one; a longer task's table is cut, its findings are not
SLOW = 0.9  # a move whose least TCP speed (away from a stop) is under this share of its programmed one is slow
SLOW_LINES = 3  # slow move lines shown, the slowest first
STILL_M_S = 1e-3  # m/s: a move whose TCP goes no faster on the mean turns the tool in place


def program_text(mech, doc: dict) -> str:
    return "\n".join([_head(doc, doc["files"])] + program_body(doc))


def program_body(doc: dict) -> list[str]:
    """The table of the moves and what is said under it (a MultiMove report's, for each robot)."""
    moves = doc["moves"]
    files = doc["files"]
    several = len(files) > 1
    routines = len({m["routine"] for m in moves}) > 1
    lines = []
    axes = doc.get("external_axes") or {}
    rows = [["line" if not several else "file:line"] + (["routine"] if routines else []) +
            ["instruction", "target", "resolved [mm]"] + (["extax [mm, deg]"] if axes else []) +
            ["start [s]", "duration [s]", "findings"]]
    for m in moves[:MAX_ROWS]:
        where = f"{Path(m['file']).name}:{m['line']}" if several else str(m["line"])
        count = "error" if m.get("error") else str(len(m["findings"])) if m["findings"] else "-"
        rows.append([where] + ([m["routine"]] if routines else []) +
                    [m["instruction"], m["target"], _resolved(m)] + ([_external(m, axes)] if axes else []) +
                    [f"{m['start_s']:.2f}", f"{m['end_s'] - m['start_s']:.2f}", count])
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    lines += ["  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip() for r in rows]
    if len(moves) > MAX_ROWS:
        lines.append(f"... {len(moves) - MAX_ROWS} more moves and waits (--json lists them all)")
    lines += _slow(moves, several)
    lines += _findings(moves, several)
    if doc["errors"]:
        lines.append(f"errors: {len(doc['errors'])} (targets the robot cannot take; their moves are skipped)")
    if doc.get("stopped"):
        lines.append(f"stopped: {doc['stopped']} (every move before it is planned and timed)")
    lines += _assumed(doc.get("assumed") or [], several)
    if doc.get("error"):
        e = doc["error"]
        lines.append(f"error: {e['text']} (the task stops there; every move before it is planned, timed and checked)")
        lines += [f"  called from {c}" for c in e["chain"][:-1][::-1]]
    if doc["csv"]:
        lines.append(f"trajectory: {doc['csv']}")
    if doc.get("speed_plot"):
        lines.append(f"speed plot: {doc['speed_plot']}")
    if doc.get("video"):
        lines.append(f"video: {doc['video']['path']} ({doc['video']['frames']} frames)")
    return lines


def _external(m: dict, axes: dict) -> str:
    """A move's target's external axes as the program writes them (mm, degrees; ``-``: 9E9, the
    axis stays where it is): ``eax_a 1200``."""
    given = m.get("target_extax")
    if not given or m["kind"] == "wait":
        return "-"
    names = ("eax_a", "eax_b", "eax_c", "eax_d", "eax_e", "eax_f")
    return ", ".join(f"{a} {'-' if v is None else f'{v:g}'}" for a, v in zip(names, given) if a in axes)


def _which_pass(doc: dict) -> str:
    """Which pass the cycle time is, and from and into what: the steady pass where the run has two."""
    passes, k = doc["cycles_s"], doc["cycle_pass"]
    if doc["main_loop"]:
        loop = doc["main_loop"]
        what = f"the main loop at {Path(loop.rsplit(':', 1)[0]).name}:{loop.rsplit(':', 1)[1]}"
    else:
        what = f"{doc['routine']} run again and again"
    if doc.get("stopped"):
        return f"the last whole pass of {what} before the stop: {_seconds(passes)} s"
    into = "into the next pass as the loop goes on" if doc["into_next_pass_s"] > 0 else "to rest"
    if len(passes) == 1:
        return f"one pass of {what}, from the moves before it (--cycles 2 times a pass from the one before), {into}"
    return (f"the steady pass: the {_ordinal(k)} of {len(passes)} passes of {what}, from the pass before, "
            f"{'into the pass after' if k < len(passes) else into} (each pass as run: {_seconds(passes)} s)")


def _ordinal(k: int) -> str:
    return {1: "1st", 2: "2nd", 3: "3rd"}.get(k, f"{k}th")


def _head(doc: dict, files: list[str]) -> str:
    moves = doc["moves"]
    count = sum(1 for m in moves if m["kind"] != "wait")
    source = Path(files[0]).name if len(files) == 1 else f"{len(files)} files"
    head = (f"{doc['robot']}: {doc['routine']} of {source}, {count} move{'s' * (count != 1)}, "
            f"{doc['duration_s']:.2f} s in all (zones blended; fine stops)")
    passes = doc["cycles_s"]
    if doc["cycle_s"] is None:
        said = "error" if doc.get("error") else "stopped"
        head += f"\ncycle: none: the run stopped before a pass ended (see '{said}' below)"
    elif doc["main_loop"] or len(passes) > 1:
        head += f"\ncycle: {doc['cycle_s']:.2f} s, {_which_pass(doc)}"
    else:
        head += f"\ncycle: {doc['cycle_s']:.2f} s, one run of {doc['routine']}"
    head += f"; {doc['axis_limits']['summary']}"
    if doc.get("tool"):
        head += f"\ntool: {doc['tool']['given']}, checked against every link but its own, the meshes and the floor"
    if doc.get("loads"):
        head += "\nloads: " + "; ".join(_load(x) for x in doc["loads"])
    return head


def _load(load: dict) -> str:
    """A load the moves carry and the range of the factors it puts on the axes' accelerations."""
    f = load["acceleration_factor"]
    return (f"{load['mass']:g} kg ({load['source']}; {load['moves']} move{'s' * (load['moves'] != 1)}): "
            f"accelerations x{min(f):.2f}-{max(f):.2f}")


def _seconds(values: list[float], shown: int = 6) -> str:
    text = ", ".join(f"{v:.2f}" for v in values[:shown])
    return text + (f", ... ({len(values) - shown} more)" if len(values) > shown else "")


def _findings(moves: list[dict], several: bool) -> list[str]:
    """The findings of the moves made (a target the robot could not take is an error, said
    apart), one line per move line, kind and links, with how many times."""
    found = [(f, m) for m in moves if not m.get("error") for f in m["findings"]]
    if not found:
        return ["findings: none"]
    fails = sum(1 for f, _ in found if f["severity"] == "fail")
    shown = grouped(found)
    head = f"findings: {len(found)} ({fails} fail, {len(found) - fails} warn)"
    if len(shown) < len(found):
        head += f" at {len(shown)} place{'s' * (len(shown) != 1)}"
    lines = [head] + [f"  {_where(f, several)}: {f['severity']}: {f['text']}{_assumes(f)}" for f in shown[:MAX_ROWS]]
    if len(shown) > MAX_ROWS:
        lines.append(f"  ... {len(shown) - MAX_ROWS} more (--json lists them all)")
    return lines


def _assumes(f: dict) -> str:
    """A finding of a move that uses a stand-in says which."""
    return f" (the move uses the stand-in {', '.join(f['assumed'])})" if f.get("assumed") else ""


def _assumed(assumed: list[dict], several: bool) -> list[str]:
    """``--assume-missing``'s stand-ins, one line each: name, type and value, the line first using it."""
    if not assumed:
        return []
    lines = [f"assumed: {len(assumed)} name{'s' * (len(assumed) != 1)} declared nowhere, run with stand-ins "
             "(--assume-missing)"]
    for a in assumed[:MAX_ROWS]:
        where = f"{Path(a['file']).name}:{a['line']}" if several else f"line {a['line']}"
        value = {"num": "0"}.get(a["type"], f"as {a['value']}")
        lines.append(f"  {a['name']}: a {a['type']} {value} ({where}, {a['uses']} use{'s' * (a['uses'] != 1)})")
    if len(assumed) > MAX_ROWS:
        lines.append(f"  ... {len(assumed) - MAX_ROWS} more (--json lists them all)")
    return lines


def _slow(moves: list[dict], several: bool) -> list[str]:
    """The moves slower than their programmed speed away from a stop, a line per program line
    (its slowest pass), the slowest first, with what holds each; none where none is."""
    worst, counts = {}, {}
    for m in moves:
        s = m.get("tcp_speed")
        if not s or not s["programmed_m_s"] or s["least_m_s"] >= SLOW * s["programmed_m_s"]:
            continue
        if (s["mean_m_s"] or 0.0) < STILL_M_S:  # a reorientation in place: the TCP's speed says nothing
            continue
        share, key = s["least_m_s"] / s["programmed_m_s"], (m["file"], m["line"], m["instruction"])
        counts[key] = counts.get(key, 0) + 1
        if key not in worst or share < worst[key][0]:
            worst[key] = (share, m)
    if not worst:
        return []
    shown = sorted(((share, counts[key], m) for key, (share, m) in worst.items()), key=lambda w: w[0])
    total = sum(counts.values())
    lines = [f"slow: {total} move{'s' * (total != 1)} under {SLOW:.0%} of the programmed TCP speed away from a "
             f"stop, at {len(shown)} line{'s' * (len(shown) != 1)} (tcp_speed, limited_by: --json); the slowest:"]
    for _, count, m in shown[:SLOW_LINES]:
        s = m["tcp_speed"]
        times = f" (the slowest of {count})" if count > 1 else ""
        lines.append(f"  {_where(m, several)}: {m['instruction']}{times}: {1000 * s['least_m_s']:.0f} of "
                     f"{1000 * s['programmed_m_s']:.0f} mm/s at {s['least_at_s']:.2f} s "
                     f"({s['least_at_share']:.0%} in), held by {_held(m['limited_by'])}")
    return lines


def _held(held: dict) -> str:
    """What holds a move, in words: an axis's speed, acceleration or jerk, the TCP's programmed
    speed or turn, its zone's blend, its \\T; with the ratio to that bound."""
    limit, axis, ratio = held["limit"], held.get("axis"), held.get("ratio")
    if limit == "synchronized":
        return f"the synchronized move ({held['ident']}) of {' and '.join(held['robots'])}, the slower"
    if limit in ("zone", "time"):
        near = held["nearest"]
        what = "its zone (a corner's blend: the speed changes to the next move's)" if limit == "zone" else "its \\T"
        return f"{what}; nearest bound {_held({**near, 'ratio': ratio})}"
    words = {"velocity": f"{axis}'s top speed", "acceleration": f"{axis}'s acceleration", "jerk": f"{axis}'s jerk",
             "tcp_speed": "the programmed TCP speed", "orientation_speed": "the programmed turn (v_ori)"}
    return f"{words.get(limit, limit)} ({ratio:.2f})"


def _resolved(m: dict) -> str:
    """The move's target as resolved (where a jointtarget puts the TCP), in its work object, mm."""
    at = m.get("target_m")
    return "-" if at is None else "[" + ", ".join(f"{1000 * v:.1f}" for v in at) + "]"


def _where(m: dict, several: bool) -> str:
    return f"{Path(m['file']).name}:{m['line']}" if several else f"line {m['line']}"
