"""What a robot programmer reads of ``rswarp program``: one row per move (``file:line`` when the
task has several files, the routine when it has several), its findings under the table, the
cycle time, and every error of a target the robot cannot take."""

from __future__ import annotations

from pathlib import Path

MAX_ROWS = 200  # moves shown one by one; a longer task's table is cut, its findings are not


def program_text(mech, doc: dict) -> str:
    moves = doc["moves"]
    files = doc["files"]
    several = len(files) > 1
    routines = len({m["routine"] for m in moves}) > 1
    lines = [_head(doc, files)]
    rows = [["line" if not several else "file:line"] + (["routine"] if routines else []) +
            ["instruction", "target", "start [s]", "duration [s]", "findings"]]
    for m in moves[:MAX_ROWS]:
        where = f"{Path(m['file']).name}:{m['line']}" if several else str(m["line"])
        count = "error" if m.get("error") else str(len(m["findings"])) if m["findings"] else "-"
        rows.append([where] + ([m["routine"]] if routines else []) +
                    [m["instruction"], m["target"], f"{m['start_s']:.2f}", f"{m['end_s'] - m['start_s']:.2f}", count])
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    lines += ["  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip() for r in rows]
    if len(moves) > MAX_ROWS:
        lines.append(f"... {len(moves) - MAX_ROWS} more moves and waits (--json lists them all)")
    found = [f for m in moves for f in m["findings"]]
    fails = sum(1 for f in found if f["severity"] == "fail")
    lines.append(f"findings: {len(found)} ({fails} fail, {len(found) - fails} warn)" if found else "findings: none")
    lines += [f"  {_where(f, several)}: {f['severity']}: {f['text']}" for f in found[:MAX_ROWS]]
    if len(found) > MAX_ROWS:
        lines.append(f"  ... {len(found) - MAX_ROWS} more (--json lists them all)")
    if doc["errors"]:
        lines.append(f"errors: {len(doc['errors'])} (targets the robot cannot take; their moves are skipped)")
    if doc["csv"]:
        lines.append(f"trajectory: {doc['csv']}")
    if doc.get("video"):
        lines.append(f"video: {doc['video']['path']} ({doc['video']['frames']} frames)")
    return "\n".join(lines)


def _head(doc: dict, files: list[str]) -> str:
    moves = doc["moves"]
    count = sum(1 for m in moves if m["kind"] != "wait")
    source = Path(files[0]).name if len(files) == 1 else f"{len(files)} files"
    head = (f"{doc['robot']}: {doc['routine']} of {source}, {count} move{'s' * (count != 1)}, "
            f"{doc['duration_s']:.2f} s in all (zones blended; fine stops)")
    passes = doc["cycles_s"]
    if doc["main_loop"]:
        loop = doc["main_loop"]
        where = f"{Path(loop.rsplit(':', 1)[0]).name}:{loop.rsplit(':', 1)[1]}"
        what = f"one pass of the main loop at {where}"
        if len(passes) > 1:
            what = f"the last of {len(passes)} passes of the main loop at {where}: {_seconds(passes)} s"
        head += f"\ncycle: {doc['cycle_s']:.2f} s, {what} (--cycles {len(passes)})"
    elif len(passes) > 1:
        head += (f"\ncycle: {doc['cycle_s']:.2f} s, the last of {len(passes)} runs of {doc['routine']}: "
                 f"{_seconds(passes)} s")
    else:
        head += f"\ncycle: {doc['cycle_s']:.2f} s, one run of {doc['routine']}"
    head += f"; {doc['axis_limits']['summary']}"
    if doc.get("tool"):
        head += f"\ntool: {doc['tool']['given']}, checked against every link but its own, the meshes and the floor"
    return head


def _seconds(values: list[float], shown: int = 6) -> str:
    text = ", ".join(f"{v:.2f}" for v in values[:shown])
    return text + (f", ... ({len(values) - shown} more)" if len(values) > shown else "")


def _where(m: dict, several: bool) -> str:
    return f"{Path(m['file']).name}:{m['line']}" if several else f"line {m['line']}"
