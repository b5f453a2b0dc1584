"""The demo's cells: the IRB 2600 on the 4 m track and beside the two-axis positioner, each with
the RAPID module beside its cell file run over the whole cell (``rswarp program CELL.toml``), its
table, the external axes' values, its trajectory and a video of the cell; the two-robot MultiMove
weld cell, both tasks on one clock."""

from __future__ import annotations

from pathlib import Path
from typing import Callable

CELL_PROGRAMS = (("track_cell.toml", "track_transfer.mod"), ("positioner_cell.toml", "positioner_weld.mod"))
HOSE_CELL = ("track_dresspack_cell.toml", "track_transfer.mod")  # the dress pack run with the carriage moving


def demo_cells(out: Path, say: Callable[[str], None], video_size: int) -> list[dict]:
    """Each bundled cell's program run over the cell, with its video; what it found."""
    from .. import examples
    from ..config import VideoOptions
    from .program import run_program

    out.mkdir(parents=True, exist_ok=True)
    done = []
    for cell_name, module in CELL_PROGRAMS:
        cell, program = examples.CELLS / cell_name, examples.CELLS / module
        stem = Path(cell_name).stem
        csv, video = out / f"{stem}-{Path(module).stem}.csv", out / f"{stem}-{Path(module).stem}.gif"
        said: list[str] = []
        result = run_program(str(cell), [str(program)], csv=str(csv),
                             video=VideoOptions(str(video), video_size=video_size), warn=said.append)
        lines = [f"== cell {cell_name}: {module} over the robot and its external axes (rswarp program {cell_name}), "
                 f"trajectory -> {csv}:"]
        lines += [f"     {line}" for line in result.text.splitlines() if not line.startswith("trajectory:")]
        lines += [f"     note: {line.split(': warning: ', 1)[-1]}" for line in said]
        say("\n".join(lines + [""]))
        doc = result.doc
        done.append({"cell": str(cell), "program": str(program), "cycle_s": doc["cycle_s"], "csv": str(csv),
                     "video": doc.get("video", {}).get("path"), "errors": doc["errors"]})
    done.append(_multimove(say))
    done.append(_hose(out, say))
    return done


def _multimove(say: Callable[[str], None]) -> dict:
    """The two-robot weld cell: both tasks of its backup on one clock, checked against each other."""
    from .. import examples
    from .program import run_program

    cell, backup = examples.MULTIMOVE_CELL, examples.MULTIMOVE_BACKUP
    result = run_program(str(cell), [str(backup)])
    lines = [f"== cell {cell.name}: each robot's task of the backup {backup.name}/, on one clock (rswarp program "
             f"{cell.name} {backup.name}):"]
    lines += [f"     {line}" for line in result.text.splitlines()]
    say("\n".join(lines + [""]))
    return {"cell": str(cell), "program": str(backup), "cycle_s": result.doc["cycle_s"], "csv": None, "video": None,
            "errors": result.doc["errors"]}


def _hose(out: Path, say: Callable[[str], None]) -> dict:
    """The IRB 2600's process hose over the track program, the carriage carrying the robot."""
    from .. import examples
    from .cables import run_cables

    cell, program = (examples.CELLS / name for name in HOSE_CELL)
    folder = out / "track-dresspack"
    result = run_cables(str(cell), str(folder), program=[str(program)])
    keep = ("  verdict", "  bend radius", "  control point", "  floor")
    lines = [f"== cell {cell.name}: the dress pack over {program.name}, the carriage moving the robot "
             f"(rswarp cable {cell.name} --program {program.name}) -> {folder}:"]
    lines += [f"     {line.strip()}" for line in result.text.splitlines() if line.startswith(keep)]
    say("\n".join(lines + [""]))
    return {"cell": str(cell), "program": str(program), "hose": str(folder), "errors": []}
