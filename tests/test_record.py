"""``benchmarks/run_all.py``'s results file: strict JSON (a non-finite number is null), written whole
or not at all (a temporary file beside it, then a rename), and bad input (``--record``'s OUTPUT
missing, a folder, not UTF-8, without a metric line or with a broken one; a truncated results
file) one line and exit 1 with the file left as it was."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

RUN_ALL = Path(__file__).parents[1] / "benchmarks" / "run_all.py"
OLD = {"machine": {"cores": 2}, "date": "2026-01-01", "versions": {}, "quick": False,
       "benchmarks": {"bench_dresspack_h200": {"results": [{"metric": "old", "ratio": 2.0}]}}}


def strict(text: str):
    def refuse(name):
        raise ValueError(f"{name} in the file")

    return json.loads(text, parse_constant=refuse)


def record(tmp_path: Path, output: Path, *more: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(RUN_ALL), "--results", str(tmp_path / "results.json"), "--record",
                           "bench_dresspack_h200", str(output), "--on", "H200", "--command", "python bench.py",
                           *more], capture_output=True, text=True, timeout=60)


@pytest.fixture
def results(tmp_path) -> Path:
    path = tmp_path / "results.json"
    path.write_text(json.dumps(OLD, indent=1) + "\n")
    return path


def test_a_non_finite_figure_is_recorded_as_null_and_the_file_replaced_whole(tmp_path, results):
    out = tmp_path / "out.txt"
    out.write_text('a table\n{"metric": "sweep", "ours": 1.5, "peer": NaN, "ratio": 2.0, "big": 1e999}\n')
    before = results.stat().st_ino
    p = record(tmp_path, out)
    assert p.returncode == 0, p.stderr
    doc = strict(results.read_text())  # strict JSON: no NaN, no Infinity
    assert doc["benchmarks"]["bench_dresspack_h200"]["results"] == [
        {"metric": "sweep", "ours": 1.5, "peer": None, "ratio": 2.0, "big": None}]
    assert results.stat().st_ino != before  # a new file renamed into place, not the old one rewritten
    assert sorted(f.name for f in tmp_path.iterdir()) == ["out.txt", "results.json"]  # no temporary file left


@pytest.mark.parametrize("make, says", [
    (lambda p: p.write_text("a table, and no JSON line\n"), "no metric line"),
    (lambda p: None, "cannot read: No such file or directory"),
    (lambda p: p.mkdir(), "cannot read: a folder"),
    (lambda p: p.write_bytes(b'\xff\xfe{"metric": "x"}\n'), "not UTF-8 text"),
    (lambda p: p.write_text('ok\n{"metric": "x", "ratio": \n'), "out.txt:2: a metric line that is not JSON"),
    (lambda p: p.write_text('{"metric": "x", "ours": 1.0, "ratio": NaN}\n'), "out.txt:1: ratio is not a finite number"),
    (lambda p: p.write_text('{"metric": "x", "ours": 1e999, "ratio": 2}\n'), "out.txt:1: ours is not a finite number"),
    (lambda p: p.write_text('{"metric": "x", "deep": ' + "[" * 100_000 + "]" * 100_000 + "}\n"), "nested too deep"),
])
def test_output_that_cannot_be_recorded_is_one_line_and_keeps_the_old_entry(tmp_path, results, make, says):
    out = tmp_path / "out.txt"
    make(out)
    before = results.read_bytes()
    p = record(tmp_path, out)
    err = p.stderr.strip().splitlines()
    assert p.returncode == 1 and len(err) == 1 and says in err[0] and err[0].startswith("run_all.py: "), p.stderr
    assert results.read_bytes() == before


@pytest.mark.parametrize("broken, says", [
    (lambda text: text[:len(text) // 2], "results.json:"),  # truncated
    (lambda text: text.replace("2.0", "NaN"), "not strict JSON"),
    (lambda text: "[]", "not a results file"),
    (lambda text: "[" * 100_000 + "]" * 100_000, "nested too deep"),
])
def test_a_broken_results_file_is_one_line_before_anything_runs(tmp_path, results, broken, says):
    results.write_text(broken(results.read_text()))
    before = results.read_bytes()
    out = tmp_path / "out.txt"
    out.write_text('{"metric": "x", "ratio": 1.0}\n')
    for p in (record(tmp_path, out), subprocess.run([sys.executable, str(RUN_ALL), "--results", str(results),
                                                     "--only", "bench_fk"], capture_output=True, text=True,
                                                    timeout=60)):
        err = p.stderr.strip().splitlines()
        assert p.returncode == 1 and len(err) == 1 and says in err[0] and "Traceback" not in p.stderr, p.stderr
    assert results.read_bytes() == before


def test_a_results_file_behind_a_symlink_is_replaced_where_it_is_and_the_link_kept(tmp_path, results):
    kept = tmp_path / "kept"
    kept.mkdir()
    target = kept / "results.json"
    results.rename(target)
    results.symlink_to(target)  # tmp_path/results.json -> kept/results.json
    out = tmp_path / "out.txt"
    out.write_text('{"metric": "new", "ours": 1.0, "ratio": 3.0}\n')
    p = record(tmp_path, out)
    assert p.returncode == 0, p.stderr
    assert results.is_symlink() and results.resolve() == target.resolve()
    assert strict(target.read_text())["benchmarks"]["bench_dresspack_h200"]["results"][0]["metric"] == "new"
    assert sorted(f.name for f in kept.iterdir()) == ["results.json"]  # no temporary file left beside it
