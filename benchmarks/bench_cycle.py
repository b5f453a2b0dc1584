"""ABB's standard pick cycle, "25 x 300 x 25 mm with 1 kg", timed by ``rswarp program`` on the three
bundled robots (IRB 1300-11/0.9, IRB 2600-12/1.65, IRB 2600ID-8/2.00) and held against the cycle
time ABB publishes for each, where one was found.

The cycle, as data sheets define it: from the pick point up 25 mm, across 300 mm, down 25 mm to the
place point, and back the same way, with a 1 kg load; the bundled ``examples/standard_cycle.mod``
(the one ``rswarp demo`` runs): MoveL at vmax in a main loop, a fine point at the pick and at the
place, the four upper corners blended in z10, ConfL off, the load on a tooldata whose TCP is the
flange. It is centred on the same place relative to each arm: ``CalcRobT`` of the joint values
[0, 20, 20, 0, 50, 0] deg (axes 2 and 3 tilted forward, the tool pointing straight down, some
60 % of the reach out and 0.6 m high on all three), the 300 mm across the front of the robot
(along y). ``--cycles 3``; rswarp's figure is the JSON's ``cycle_s``, the steady pass (the
second; here every pass starts and ends at rest at the pick point, so all three take the same).

ABB's published figures: none was found in the sources searched (this project's search of public
pages, documentation and code, for the IRB 1300, IRB 2600 and IRB 2600ID data sheets and product
specifications); each is then printed as "none found" with no gap. A figure found later goes in
``PUBLISHED`` with the document it comes from.

Usage: python benchmarks/bench_cycle.py. Prints a table, then one JSON line per robot
(``{"metric": ..., "ours": cycle s, "peer": ABB's s or null, "ratio": ABB's / ours or null}``).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from rswarp.examples import IRB1300, IRB2600, IRB2600ID, STANDARD_CYCLE
from rswarp.report.program import run_program

CYCLES = 3
ROBOTS = (("IRB 1300-11/0.9", IRB1300), ("IRB 2600-12/1.65", IRB2600), ("IRB 2600ID-8/2.00", IRB2600ID))
# ABB's figure for this cycle, per robot: (seconds, the document it is from); None: none found
PUBLISHED: dict[str, tuple[float, str] | None] = {name: None for name, _ in ROBOTS}



def cycle(robot: Path, module: Path) -> dict:
    """The standard cycle on ``robot``: rswarp's steady cycle (s), every pass, and what it found."""
    t0 = time.perf_counter()
    out = run_program(str(robot), [str(module)], cycles=CYCLES)
    wall = time.perf_counter() - t0
    doc = out.doc
    if out.code != 0 or doc.get("cycle_s") is None:
        raise SystemExit(f"bench_cycle.py: {robot.name}: the cycle did not run: {'; '.join(out.errors) or doc}")
    findings = sorted({f["kind"] for f in doc["findings"]})
    return {"cycle_s": doc["cycle_s"], "cycles_s": doc["cycles_s"], "findings": findings, "wall_s": wall,
            "limits": doc["axis_limits"]["summary"]}


def row(name: str, result: dict) -> dict:
    """One robot's line: rswarp's cycle against ABB's, the gap in % (rswarp's minus ABB's, of ABB's)."""
    published = PUBLISHED.get(name)
    ours = result["cycle_s"]
    abb, source = published if published is not None else (None, None)
    gap = None if abb is None else 100.0 * (ours - abb) / abb
    return {"robot": name, "ours": ours, "abb": abb, "source": source, "gap_pct": gap, **result}


def main() -> None:
    argparse.ArgumentParser(description=__doc__.splitlines()[0]).parse_args()
    rows = []
    for name, robot in ROBOTS:
        rows.append(row(name, cycle(robot, STANDARD_CYCLE)))
    print(f"{'robot':<19}{'rswarp s':>9}{'ABB s':>8}{'gap':>8}  passes (s)            findings; axis limits")
    for r in rows:
        abb = f"{r['abb']:.3f}" if r["abb"] is not None else "none"
        gap = f"{r['gap_pct']:+.0f} %" if r["gap_pct"] is not None else "-"
        passes = ", ".join(f"{c:.3f}" for c in r["cycles_s"])
        print(f"{r['robot']:<19}{r['ours']:>9.3f}{abb:>8}{gap:>8}  {passes:<22}{', '.join(r['findings']) or '-'}; "
              f"{r['limits']}")
    for r in rows:
        print(f"  {r['robot']}: ABB's figure: {r['source'] or 'none found in the sources searched'}")
    for r in rows:
        print(json.dumps({"metric": f"steady 25 x 300 x 25 mm cycle with 1 kg, s, {r['robot']}",
                          "ours": round(r["ours"], 4), "peer": r["abb"], "peer_name": "ABB's published figure",
                          "source": r["source"],
                          "gap_pct": None if r["gap_pct"] is None else round(r["gap_pct"], 1),
                          "ratio": None if r["abb"] is None else round(r["abb"] / r["ours"], 3)}))


if __name__ == "__main__":
    main()
