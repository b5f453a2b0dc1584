"""The demo's placement: where the IRB 2600 should stand for its palletizing task (the bundled
``irb2600_12_165/cell``), over a grid of bases around where it stands now; the map and the best."""

from __future__ import annotations

from pathlib import Path
from typing import Callable

DEMO_VARY = ("x=-400:400:5", "y=-400:400:5", "yaw=-45:45:3")  # 75 bases: mm, mm, degrees
DEMO_TOP = 2


def demo_placement(out: Path, say: Callable[[str], None]) -> dict:
    """``rswarp place`` of the IRB 2600 for its palletizing task into ``out``; what it found."""
    from ... import examples
    from ...config import PlaceOptions
    from .run import run_place

    result = run_place(str(examples.IRB2600), [str(examples.IRB2600_CELL)], place=PlaceOptions(DEMO_VARY, top=DEMO_TOP),
                       out=str(out))
    flags = " ".join(f"--vary {v}" for v in DEMO_VARY)
    lines = [f"== place: where {examples.IRB2600.name} should stand for its palletizing task (rswarp place "
             f"{examples.IRB2600.name} cell/ {flags} --top {DEMO_TOP}) -> {out}, the map {out}/map.png:"]
    lines += [f"     {line}" for line in result.text.splitlines()]
    say("\n".join(lines + [""]))
    return result.doc
