"""The README's Measured table holds only figures its scripts printed: each row names the benchmark
(or the test) it comes from, and each measured number in it (a number with a decimal point) is in
that script's output as ``benchmarks/run_all.py`` recorded it in ``benchmarks/results.json``, or
in that test's text."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results.json"
MEASURED = re.compile(r"(?<![\d.,])\d+\.\d+(?![\d])")  # a measured figure: a number with decimals


def _rows() -> list[str]:
    text = (ROOT / "README.md").read_text()
    table = text.split("## Measured", 1)[1].split("\n## ", 1)[0]
    return [line for line in table.splitlines() if line.startswith("| ") and not line.startswith("| what")]


def _figures(row: str) -> list[str]:
    """The measured numbers of a row: in its ours, peer and ratio cells (the first cell says what
    was measured, with its sizes), outside the links."""
    cells = [re.sub(r"\([^)]*\.md[^)]*\)", "", c) for c in row.strip("|").split("|")[1:]]
    return [m.group(0) for c in cells for m in MEASURED.finditer(c)]


def test_the_results_file_is_a_whole_run_with_its_machine():
    def refuse(name):  # strict JSON: run_all.py writes a non-finite figure as null
        raise AssertionError(f"{name} in {RESULTS.name}")

    doc = json.loads(RESULTS.read_text(), parse_constant=refuse)
    assert not doc["quick"] and doc["machine"]["cores"] and doc["versions"]["rswarp"]
    for name, entry in doc["benchmarks"].items():
        assert entry["returncode"] == 0 and entry["output"].strip(), name


@pytest.mark.parametrize("row", _rows(), ids=lambda r: r.strip("| ").split(" |")[0][:40])
def test_each_measured_figure_is_in_the_output_of_the_script_it_names(row):
    benches = re.findall(r"`(bench_\w+?)(?:\.py)?`", row)
    tests = re.findall(r"`(tests/test_\w+\.py)`", row)
    assert benches or tests, f"the row names no benchmark or test: {row}"
    doc = json.loads(RESULTS.read_text())["benchmarks"]
    # a script run more than one way (bench_cable and bench_cable_whole_run) counts with each
    outputs = [e["output"] for b in benches for k, e in doc.items() if k == b or k.startswith(f"{b}_")] + \
        [(ROOT / t).read_text() for t in tests]
    assert len(outputs) >= len(benches) + len(tests), f"{benches} not all in results.json"
    for figure in _figures(row):
        pattern = re.compile(rf"(?<![\d.]){re.escape(figure)}(?!\d)")
        assert any(pattern.search(out) for out in outputs), f"{figure} is not in the output of {benches or tests}"


def _doc_tables() -> list[tuple[str, list[str], list[str]]]:
    """(doc, benchmarks named, rows) of each table in docs/ that follows text naming a benchmark
    (``bench_x``) under the same heading: a table of measured figures."""
    found = []
    for md in sorted((ROOT / "docs").glob("*.md")):
        named, table = [], []
        for line in [*md.read_text().splitlines(), ""]:
            if line.startswith("|"):
                table.append(line)
                continue
            if table and named:
                found.append((md.name, sorted(set(named)), table))
            table = []
            named = [] if line.startswith("#") else named + re.findall(r"(bench_\w+?)(?:\.py|`)", line)
    return found


def test_docs_name_their_benchmarks():
    assert {doc for doc, _, _ in _doc_tables()} >= {"cables.md", "collisions.md", "kinematics.md", "ray.md"}


@pytest.mark.parametrize("doc, benches, rows", _doc_tables(), ids=lambda v: v if isinstance(v, str) else None)
def test_each_figure_in_a_docs_table_is_in_the_output_of_its_benchmark(doc, benches, rows):
    runs = json.loads(RESULTS.read_text())["benchmarks"]
    outputs = [e["output"] for b in benches for k, e in runs.items() if k == b or k.startswith(f"{b}_")]
    assert outputs, f"{doc}: {benches} not in results.json"
    for row in rows:
        for figure in _figures("| " + row.strip("|")):
            pattern = re.compile(rf"(?<![\d.]){re.escape(figure)}(?!\d)")
            assert any(pattern.search(out) for out in outputs), f"{doc}: {figure} ({row}) is not in {benches}"
