"""The batch engine and the cable-solver seam (issue "One batch engine, one cable-solver seam"): a
job's items cut into tasks by index and merged exactly in any order, one progress count; a second
cable model, registered by name, runs through runs, reports and the command line untouched."""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np

import rswarp
from rswarp.cli import main
from rswarp.sim.cable import models as cable_models
from rswarp.sim.cable.rod import CosseratRod
from rswarp.sim.engine import Job, run_batch, spans

from conftest import DATA

ID = DATA.parent.parent / "examples" / "irb2600id" / "IRB2600ID_8_200__03.rsxml"


@dataclass
class Squares:
    """An accumulator: the sum of squares of the items seen, and which items."""

    total: int = 0
    seen: tuple = ()

    def merge(self, other: "Squares") -> None:
        self.total += other.total
        self.seen = tuple(sorted(self.seen + other.seen))


@dataclass(frozen=True)
class SquareJob(Job):
    """A toy batch: item k adds k squared; local runs go in steps of ``step`` items."""

    name = "squares"
    n: int
    step: int

    @property
    def count(self) -> int:
        return self.n

    def task_items(self, cluster) -> int:
        return self.step

    def local_spans(self) -> list[range]:
        return spans(self.n, self.step)

    def tools_key(self) -> tuple:
        return ()

    def tools(self, model, device, threads):
        return np.square

    def empty(self) -> Squares:
        return Squares()

    def run(self, square, acc: Squares, span: range, tick) -> None:
        part = Squares(int(square(np.arange(span.start, span.stop)).sum()), tuple(span))
        acc.merge(part)
        tick(len(span) / 2)  # half way: the engine completes the span's count itself


def test_a_job_runs_its_items_once_with_one_progress_count():
    """However the local run cuts the items, the accumulator holds each once and progress counts
    up to the job's size, never past it."""
    mech = rswarp.load(ID)
    for step in (1, 7, 100):
        seen: list[tuple[float, float]] = []
        acc = run_batch(SquareJob(100, step), mech, progress=lambda done, total, seen=seen: seen.append((done, total)))
        assert acc.total == sum(k * k for k in range(100)) and acc.seen == tuple(range(100))
        assert seen[0] == (0.0, 100.0) and seen[-1] == (100.0, 100.0)
        assert all(b[0] >= a[0] for a, b in zip(seen, seen[1:]))


def test_a_second_cable_model_runs_untouched(monkeypatch, tmp_path, capsys):
    """A second model registered by name (here the rod again, under another name) runs through
    simulate_cables, the report and the command line, and gives the rod's results."""
    copy = type("RodAgain", (CosseratRod,), {"kind": "rod-again"})
    monkeypatch.setitem(cable_models.CABLE_MODELS, "rod-again", copy)
    csv = tmp_path / "j5.csv"
    csv.write_text("time,J1,J2,J3,J4,J5,J6\n0,0,0,0,0,0,0\n1,0,0,0,0,60,0\n")
    docs = []
    for model in ("rod", "rod-again"):
        out = tmp_path / model
        assert main(["cable", str(ID), "--envs", "2", "--trajectory", str(csv), "--out", str(out),
                     "--cable-model", model, "--json"]) == 0
        docs.append(json.loads(capsys.readouterr().out))
    assert docs[1].pop("cable_model") == "rod-again" and docs[0].pop("cable_model") == "rod"
    for doc in docs:
        doc.pop("files")
    assert docs[0] == docs[1]


def test_an_unknown_cable_model_is_one_line(tmp_path, capsys):
    assert main(["cable", str(ID), "--random", "--out", str(tmp_path / "k"), "--cable-model", "rope"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["rswarp: no cable model 'rope' (models: rod)"] and not (tmp_path / "k").exists()
