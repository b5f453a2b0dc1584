"""Checking a large model: ``rswarp.check`` against the floor of lxml parsing the same file.

Generated serial chains of N links, N active joints with limits and N passive joints that each
close a loop back to the base (the case that was quadratic: a path walk per closing joint). The
peer is lxml parsing the bytes (with the same safe settings), which any reader pays; the ratio
says how much reading, validating and building the link graph cost on top. Linear time shows as
a flat time per link across sizes. Peak memory is the process's maximum resident size after the
largest size (Linux reports it in KiB).

Run: python benchmarks/bench_check.py [--sizes 10000,100000,1000000]
"""

from __future__ import annotations

import argparse
import json
import resource
import tempfile
import time
from pathlib import Path

from lxml import etree

import rswarp
from rswarp.rsxml.parse import _parser

NS = "urn:abb-robotics-robotstudio-graphiccomponent"


def chain(n: int) -> str:
    out = [f'<Mechanism xmlns="{NS}" type="Other" name="Long" lengthUnit="mm" angleUnit="deg">',
           '<Links baseLink="L0">']
    out += [f'<Part name="L{i}"/>' for i in range(n + 1)]
    out.append("</Links><Joints>")
    out += [f'<Joint name="J{i}" parent="L{i}" child="L{i + 1}" type="Rotational" active="true" '
            f'point1="0,0,{i % 1000}" point2="1,0,{i % 1000}"/>' for i in range(n)]
    out += [f'<Joint name="C{i}" parent="L0" child="L{i + 1}" type="Rotational" active="false" '
            f'point1="0,0,{i % 1000}" point2="1,0,{i % 1000}"/>' for i in range(n)]
    out.append("</Joints><Limits>")
    out += [f'<Limit joint="J{i}" min="-90" max="90"/>' for i in range(n)]
    out.append(f'</Limits><Flanges><Flange name="tool0" link="L{n}" t="0,0,10"/></Flanges></Mechanism>')
    return "\n".join(out)


def measure(n: int, folder: Path) -> dict:
    path = folder / f"chain_{n}.rsxml"
    path.write_text(chain(n))
    t = time.perf_counter()
    etree.fromstring(path.read_bytes(), _parser())
    parse = time.perf_counter() - t
    t = time.perf_counter()
    report = rswarp.check(path, max_file_size=2**31)
    ours = time.perf_counter() - t
    assert report.ok, report.errors[:3]
    return {"links": n, "mib": round(path.stat().st_size / 2**20, 1), "check_s": round(ours, 3),
            "lxml_parse_s": round(parse, 3), "ratio": round(ours / parse, 1), "us_per_link": round(ours / n * 1e6, 1)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", default="10000,100000,1000000")
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in (int(s) for s in args.sizes.split(",")):
            rows.append(measure(n, Path(tmp)))
            r = rows[-1]
            print(f"{r['links']:>9} links {r['mib']:>7} MiB  check {r['check_s']:>8.2f} s  "
                  f"lxml parse {r['lxml_parse_s']:>6.2f} s"
                  f"  ratio {r['ratio']:>5.1f}x  {r['us_per_link']:>6.1f} us/link", flush=True)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
    last = rows[-1]
    print(json.dumps({"metric": f"check seconds, {last['links']} links", "ours": last["check_s"],
                      "peer": last["lxml_parse_s"], "ratio": last["ratio"], "rows": rows,
                      "peak_rss_gib": round(peak, 2)}))


if __name__ == "__main__":
    main()
