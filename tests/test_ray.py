"""Batches on Ray (issue "Beyond one machine"): on a local Ray instance of 2 CPUs and small batches
cut into several tasks, each of the three commands gives the results of a local run, bit for bit;
a worker killed mid-batch changes nothing; bad input fails on the driver before anything is
scheduled; models travel as files by content hash."""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import signal
import threading
import time

import numpy as np
import pytest

import rswarp
from rswarp.cli import main
from rswarp.kinematics.trajectory import Trajectory, random_trajectory
from rswarp.sim import collisions as collisions_module
from rswarp.sim import engine
from rswarp.sim import workspace as workspace_module
from rswarp.sim.bodies import placed_environments
from rswarp.sim.cables import CableOptions, simulate_cables
from rswarp.sim.engine import Cluster, identical
from rswarp.sim.package import package, unpack

from conftest import DATA

ray = pytest.importorskip("ray")

EXAMPLES = DATA.parent.parent / "examples"
IRB = EXAMPLES / "irb2600_12_165" / "IRB2600_12_165__01.rsxml"
ID = EXAMPLES / "irb2600id" / "IRB2600ID_8_200__03.rsxml"
FOLD = DATA / "collisions" / "fold.rsxml"
DRAPED = DATA / "cables" / "draped.rsxml"


# local_ray (conftest.py): one local Ray instance of 2 CPUs for the session, shared with test_api.py


@pytest.fixture
def small_chunks(monkeypatch):
    """Chunks of 4096 samples, so small sweeps make several tasks (the chunk size travels with
    each task: workers draw the same samples)."""
    monkeypatch.setattr(workspace_module, "SAMPLE_CHUNK", 4096)
    monkeypatch.setattr(collisions_module, "CHUNK", 4096)




@pytest.mark.parametrize("method", ["random", "sobol", "grid"])
def test_sweep_on_ray_is_the_local_sweep(local_ray, small_chunks, method):
    """Voxel grids, views, counts and refined extremes are identical to a local run, over 4 to 6
    tasks of two chunks each."""
    mech = rswarp.load(IRB)
    here = rswarp.workspace(mech, samples=40_000, seed=5, method=method)
    there = rswarp.workspace(mech, samples=40_000, seed=5, method=method, cluster=Cluster(task_samples=8192))
    assert identical(here, there)
    assert np.array_equal(here.flange_voxels, there.flange_voxels) and np.array_equal(here.side, there.side)
    assert here.samples == there.samples >= 40_000


def test_collisions_on_ray_are_the_local_sweep(local_ray, small_chunks):
    """Counts, examples, clearances and the matrix of the IRB 2600 and of a fold with an environment
    mesh (shipped to the workers by content hash) are identical to a local run."""
    for path, env in ((IRB, []), (FOLD, [f"{DATA / 'collisions' / 'room.stl'}@0,0,0.3"])):
        mech = rswarp.load(path)
        placed = placed_environments(mech, env)
        here = rswarp.collisions(mech, samples=30_000, seed=2, environment=placed)
        there = rswarp.collisions(mech, samples=30_000, seed=2, environment=placed,
                                  cluster=Cluster(task_samples=8192))
        assert identical(here, there) and here.report() == there.report()
        assert any(p.collisions for p in here.pairs) and any(p.examples for p in here.pairs)


def test_cable_runs_on_ray_are_the_local_run(local_ray):
    """A hose draped over a lifted block (its mesh shipped) in 5 environments over 3 tasks: every
    per-environment result, the spread over environments, and the recorded environment's
    playback are identical to a local run."""
    mech = rswarp.load(DRAPED)
    lift = Trajectory("lift", np.array([0.0, 1.0]), np.array([[0.15], [0.35]]))  # the block meets the wire at 0.2 m/s
    held = Trajectory("held", np.array([0.0, 1.0]), np.array([[0.0], [0.0]]))
    options = CableOptions(record=3)
    here = simulate_cables(mech, [lift, held], envs=5, seconds=1.0, options=options)
    there = simulate_cables(mech, [lift, held], envs=5, seconds=1.0, options=options,
                            cluster=Cluster(task_envs=2))
    assert identical(here, there)
    assert np.isfinite(here.cables[0].contact_time).any()  # the shipped block mesh was touched
    assert len(here.cables[0].recorded) == 60


def _kill_first(name: bytes, killed: list, stop: threading.Event) -> None:
    """SIGKILL the first worker process found running task ``name`` (Ray titles it ray::name)."""
    while not stop.is_set() and not killed:
        for pid in os.listdir("/proc"):
            try:
                with open(f"/proc/{pid}/cmdline", "rb") as f:
                    if f.read().startswith(b"ray::" + name):
                        os.kill(int(pid), signal.SIGKILL)
                        killed.append(int(pid))
                        return
            except (OSError, ValueError):
                continue
        time.sleep(0.002)


@pytest.mark.skipif(not os.path.isdir("/proc"), reason="finds Ray's workers in /proc")
def test_a_worker_killed_mid_batch_changes_nothing(local_ray):
    """A worker is killed while it runs a cable task: Ray runs the task again, and the results
    are those of a local run."""
    mech = rswarp.load(ID)
    trajectories = [random_trajectory(mech, 1.0, seed) for seed in range(6)]
    here = simulate_cables(mech, trajectories, envs=6, seconds=1.0)
    killed, stop = [], threading.Event()
    killer = threading.Thread(target=_kill_first, args=(b"rswarp-cable", killed, stop))
    killer.start()
    try:
        there = simulate_cables(mech, trajectories, envs=6, seconds=1.0, cluster=Cluster(task_envs=1))
    finally:
        stop.set()
        killer.join()
    assert killed, "no worker was found running a task"
    assert identical(here.cables, there.cables)


def test_bad_input_fails_before_anything_is_scheduled(monkeypatch, tmp_path, capsys):
    """A bad model, a trajectory beyond a limit, a sample count of 0: the usual one line, exit 1,
    and Ray never asked for anything."""
    def refuse(*args, **kwargs):
        raise AssertionError("a task was scheduled")

    monkeypatch.setattr(engine, "connect", refuse)
    bad = DATA / "bad" / "home_outside_limits.rsxml"
    beyond = DATA / "trajectories" / "beyond_limits.csv"
    runs = [["sweep", str(bad), "--samples", "100", "--out", str(tmp_path / "s"), "--ray"],
            ["collisions", str(bad), "--samples", "100", "--out", str(tmp_path / "c"), "--ray"],
            ["cable", str(ID), "--envs", "2", "--trajectory", str(beyond), "--out", str(tmp_path / "k"), "--ray"]]
    for argv in runs:
        assert main(argv) == 1
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith(str(bad if "cable" not in argv else beyond) + ":"), err
    assert not any(tmp_path.iterdir())
    with pytest.raises(rswarp.InputError, match="samples"):
        rswarp.collisions(rswarp.load(IRB), samples=0, cluster=Cluster())


def test_a_gpu_asked_of_a_cluster_without_one_is_refused(local_ray):
    with pytest.raises(rswarp.InputError, match="no GPU"):
        rswarp.workspace(rswarp.load(IRB), samples=1000, cluster=Cluster(device="cuda"))


def test_without_ray_the_option_says_how_to_install(monkeypatch, tmp_path, capsys):
    monkeypatch.setitem(__import__("sys").modules, "ray", None)  # import ray fails
    assert main(["sweep", str(IRB), "--samples", "100", "--out", str(tmp_path / "s"), "--ray"]) == 1
    err = capsys.readouterr().err
    assert "pip install 'rswarp[ray]'" in err and len(err.strip().splitlines()) == 1


def test_models_travel_as_files_by_content_hash(local_ray):
    """The package holds the RSXML file and each mesh by its SHA-256; a worker's copy reads as the
    same mechanism from its own folder."""
    mech = rswarp.load(FOLD)
    pkg, blobs = package(mech, [DATA / "collisions" / "room.stl"])
    names = {rel: digest for rel, digest in pkg.files}
    assert set(names) == {"fold.rsxml", "slab.stl", "post.stl", "arm.stl", "room.stl"}
    for rel, digest in names.items():
        assert hashlib.sha256((DATA / "collisions" / rel).read_bytes()).hexdigest() == digest
        assert blobs[digest] == (DATA / "collisions" / rel).read_bytes()
    shipped = unpack(pkg, blobs.__getitem__)
    assert shipped.mech == mech and str(shipped.folder) not in str(FOLD)
    assert shipped.local(str(DATA / "collisions" / "room.stl")).startswith(str(shipped.folder))


def test_meshes_reached_through_links_keep_their_place(tmp_path):
    """A model whose meshes are symbolic links into another folder ships them beside the model,
    where its parts look for them, not where the links point."""
    (tmp_path / "fold.rsxml").write_bytes(FOLD.read_bytes())
    for name in ("slab.stl", "post.stl", "arm.stl"):
        (tmp_path / name).symlink_to(DATA / "collisions" / name)
    pkg, _ = package(rswarp.load(tmp_path / "fold.rsxml"))
    assert {rel for rel, _ in pkg.files} == {"fold.rsxml", "slab.stl", "post.stl", "arm.stl"}


def test_the_cli_on_ray_writes_what_a_local_run_writes(local_ray, tmp_path, capsys):
    """``rswarp collisions --ray``: the same report and SRDF as without."""
    for name, extra in (("here", []), ("there", ["--ray"])):
        assert main(["collisions", str(FOLD), "--samples", "5000", "--out", str(tmp_path / name), "--json",
                     *extra]) == 0
    capsys.readouterr()
    docs = [json.loads((tmp_path / n / "report.json").read_text()) for n in ("here", "there")]
    for doc in docs:
        doc.pop("files")
    assert docs[0] == docs[1]
    assert (tmp_path / "here" / "collision_matrix.srdf").read_bytes() == \
        (tmp_path / "there" / "collision_matrix.srdf").read_bytes()


def test_an_unreachable_cluster_is_one_line(monkeypatch, tmp_path, capsys):
    """A head node that does not answer: one line and exit 1 within seconds (Ray alone would retry
    for minutes), before anything is scheduled."""
    monkeypatch.setattr(ray, "is_initialized", lambda: False)
    t = time.perf_counter()
    assert main(["sweep", str(IRB), "--samples", "100", "--out", str(tmp_path / "s"), "--ray", "127.0.0.1:1"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["rswarp: cannot reach the Ray cluster at '127.0.0.1:1': Connection refused"]
    assert time.perf_counter() - t < 30 and not (tmp_path / "s").exists()


def test_a_task_failing_on_every_try_is_an_internal_error(local_ray):
    """Bytes that do not match their hash fail the task on each of its tries (Ray retries it); the
    driver then raises TaskFailed, an internal error (exit 2), never the user's fault."""
    mech = rswarp.load(FOLD)
    pkg, blobs = package(mech)
    pkg = dataclasses.replace(pkg, key="corrupted")  # not the model a worker may already hold
    blobs = {digest: b"not the file" for digest in blobs}
    job = workspace_module.SweepJob(*mech.bounds(), samples=1, method="random", seed=0, radius=1.0,
                                    resolution=0.5, has_wrist=False, chunk=1, base=np.zeros(3))
    with pytest.raises(engine.TaskFailed, match="failed 4 times"):
        engine.run_tasks(Cluster(), job, pkg, blobs, [range(1)], lambda span, part: None)
    assert not isinstance(engine.TaskFailed("x"), rswarp.InputError)


def test_cuda_asked_of_a_machine_without_one_is_one_line(tmp_path, capsys):
    """Warp's own CUDA driver errors are not passed on: locally one line; with --ray a warning that
    this machine's share goes on the CPU, then the cluster's refusal."""
    from rswarp.launch import init_warp

    if init_warp().get_cuda_device_count():
        pytest.skip("this machine has a GPU")
    assert main(["collisions", str(FOLD), "--samples", "100", "--out", str(tmp_path / "c"), "--device", "cuda"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("rswarp: device 'cuda' is not available here"), err
    monkeypatch = pytest.MonkeyPatch()
    monkeypatch.setattr(ray, "cluster_resources", lambda: {"CPU": 2.0})
    monkeypatch.setattr(ray, "is_initialized", lambda: True)
    try:
        assert main(["collisions", str(FOLD), "--samples", "100", "--out", str(tmp_path / "c"), "--device", "cuda",
                     "--ray"]) == 1
    finally:
        monkeypatch.undo()
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and "its share of the run goes on the CPU" in err[0] and "it has no GPU" in err[1], err
    assert not (tmp_path / "c").exists()


def test_place_on_ray_is_the_local_placement(local_ray, tmp_path, capsys):
    """``rswarp place`` cut into tasks of a few bases each on Ray: the same candidates.csv."""
    from rswarp.report.placement import reach as reach_module

    module = DATA / "place" / "pick_table.mod"
    args = ["place", str(IRB), str(module), "--vary", "x=-300:300:5", "--vary", "yaw=-30:30:3", "--top", "1"]
    old = reach_module.CHUNK
    reach_module.CHUNK = 40  # 3 bases a chunk, fixed on the driver: the batch is several tasks
    try:
        assert main(args + ["--out", str(tmp_path / "here")]) == 0
        assert main(args + ["--out", str(tmp_path / "there"), "--ray"]) == 0
    finally:
        reach_module.CHUNK = old
    capsys.readouterr()
    assert (tmp_path / "here" / "candidates.csv").read_text() == (tmp_path / "there" / "candidates.csv").read_text()
