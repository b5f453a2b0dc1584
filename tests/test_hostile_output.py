"""Careless commands and hostile settings: outputs that cannot be written, sweeps that would eat
memory, meshes that cannot be used, long chains, and a fuzz over the whole command line. The user's
mistakes end in one line and exit 1; nothing half-written is left; memory stays bounded."""

import errno
import json
import os
import signal
import subprocess
import sys
import tracemalloc
import warnings

import numpy as np
import pytest
from generated import mechanism
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import rswarp
from rswarp import examples
from rswarp.cli import main
from rswarp.report import output, sweep
from rswarp.sim import workspace as ws_module

from conftest import DATA

BRANCHING = DATA / "branching.rsxml"


def run(argv, capsys) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    return code, out.out, out.err


# -- 6. sweep outputs: one set, swapped in whole; memory bounded by the arguments ------------------------


def test_interrupted_sweep_keeps_the_previous_set(tmp_path, capsys, monkeypatch):
    out = tmp_path / "sweep"
    assert run(["sweep", BRANCHING, "--samples", 500, "--out", out], capsys)[0] == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}

    def interrupted(path, *args, **kwargs):
        raise KeyboardInterrupt  # after workspace.npz was written into the temporary folder

    monkeypatch.setattr(sweep, "atomic_write", interrupted)
    assert run(["sweep", BRANCHING, "--samples", 900, "--seed", 3, "--out", out], capsys)[0] == 130
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sweep"]  # no temporary folder left


def test_sweep_never_replaces_a_folder_with_files_it_did_not_write(tmp_path, capsys):
    mine = tmp_path / "notes.txt"
    mine.write_text("keep me")
    code, _, err = run(["sweep", BRANCHING, "--samples", 100, "--out", tmp_path], capsys)
    assert code == 1 and err == f"rswarp: {tmp_path}: holds files rswarp did not write (notes.txt); name a new or empty folder\n"
    assert mine.read_text() == "keep me"
    code, _, err = run(["sweep", BRANCHING, "--samples", 100, "--out", mine], capsys)
    assert code == 1 and err == f"rswarp: {mine}: is a file, not a folder\n"


def test_grid_sampling_memory_is_one_chunk():
    tracemalloc.start()
    try:
        chunk = next(ws_module.sample_chunks(np.array([-1.0]), np.array([1.0]), 400_000_000, "grid"))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert chunk.shape == (ws_module.SAMPLE_CHUNK, 1) and chunk[0, 0] == -1.0
    assert peak < 64 * 2**20  # linspace(4e8) was 3.2 GB
    last = np.linspace(-1, 1, 7)
    assert np.allclose(np.concatenate(list(ws_module.sample_chunks(np.array([-1.0]), np.array([1.0]), 7, "grid")))[:, 0], last)


def test_voxel_grid_over_the_cap_names_a_resolution_that_fits(capsys, tmp_path):
    code, _, err = run(["sweep", BRANCHING, "--samples", 100, "--resolution", 1, "--out", tmp_path / "s"], capsys)
    assert code == 1 and "over the cap of 6.71e+07; use a resolution of 7 mm or coarser" in err
    side = ws_module.voxels_per_side(1.23, 0.007)
    assert side ** 3 <= ws_module.MAX_VOXELS
    assert not (tmp_path / "s").exists()


def test_report_json_never_holds_nan():
    doc = output.json_safe({"a": float("nan"), "b": [1.0, float("inf")], "c": {"d": -float("inf")}, "e": "x"})
    assert doc == {"a": None, "b": [1.0, None], "c": {"d": None}, "e": "x"}
    json.dumps(doc, allow_nan=False)


@pytest.mark.parametrize("active", [False, True])
def test_sweep_without_active_joints(tmp_path, capsys, active):
    path = tmp_path / "m.rsxml"
    path.write_text(mechanism(2 if not active else 0, active=active))
    code, _, err = run(["sweep", path, "--samples", 10, "--out", tmp_path / "s"], capsys)
    assert (code, err) == (1, f"{path}:1: mechanism 'Chain' has no active joints: there is no workspace to sweep\n")


# -- 7. long chains use the generic kernel ---------------------------------------------------------------


def test_thousand_axis_chain_uses_the_generic_kernel(tmp_path, capsys):
    from rswarp.kernels.fk import MAX_UNROLLED_LINKS

    path = tmp_path / "long.rsxml"
    path.write_text(mechanism(1000))
    mech = rswarp.load(path)
    kin = rswarp.Kinematics(mech)
    assert not kin.unrolled and len(mech.links) > MAX_UNROLLED_LINKS
    q = np.full((1, 1000), 0.001)
    flange = kin.flange(q)[0]
    # axis i is parallel to x through (0, 0, i mm): the flange point (0, 0, 10 mm) is turned about
    # the last axis first, then each one before it (planar rotations in y-z, in float64)
    p = np.array([0.0, 0.010])
    for i in reversed(range(1000)):
        c, s = np.cos(0.001), np.sin(0.001)
        y, z = p[0], p[1] - i * 0.001
        p = np.array([c * y - s * z, s * y + c * z + i * 0.001])
    assert np.allclose(flange[:3, 3], [0.0, *p], atol=1e-4)
    assert run(["fk", path, "--q", ",".join(["0"] * 1000)], capsys)[0] == 0


# -- 8. the user's mistakes are exit 1, with the path --------------------------------------------------


def test_export_to_a_folder_a_read_only_place_or_a_long_name(tmp_path, capsys, monkeypatch):
    code, _, err = run(["export", BRANCHING, "-o", tmp_path], capsys)
    assert (code, err) == (1, f"rswarp: {tmp_path}: is a folder; name the file to write\n")
    long = tmp_path / ("x" * 300 + ".usda")
    code, _, err = run(["export", BRANCHING, "-o", long], capsys)
    assert code == 1 and err.endswith(": cannot write: File name too long\n")
    real = os.replace

    def read_only(src, dst):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS), str(dst))

    monkeypatch.setattr(os, "replace", read_only)
    for name in ("r.usda", "r.urdf"):
        code, _, err = run(["export", BRANCHING, "-o", tmp_path / name], capsys)
        assert (code, err) == (1, f"rswarp: {tmp_path / name}: cannot write: Read-only file system\n")
    monkeypatch.setattr(os, "replace", real)
    assert list(tmp_path.iterdir()) == []


def test_export_makes_missing_folders_and_removes_them_on_failure(tmp_path, capsys, monkeypatch):
    target = tmp_path / "new" / "dir" / "robot.usdc"
    assert run(["export", BRANCHING, "-o", target], capsys)[0] == 0 and target.is_file()
    from rswarp.export import usd_layout

    def broken(*args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(usd_layout, "build_stage", broken)
    code, _, err = run(["export", BRANCHING, "-o", tmp_path / "other" / "deep" / "r.usda"], capsys)
    assert code == 1 and "cannot write: No space left on device" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["new"]


def _robot_with_mesh(tmp_path, mesh_bytes: bytes):
    (tmp_path / "Link1.stl").write_bytes(mesh_bytes)
    path = tmp_path / "m.rsxml"
    path.write_text(mechanism(1, part_source="Link1.SAT"))
    return path


FLAT_STL = b"""solid f
facet normal 0 0 1
outer loop
vertex 0 0 0
vertex 1 0 0
vertex 0 1 0
endloop
endfacet
endsolid f
"""


# What trimesh makes of a corrupt STL depends on the optional modules it finds (without
# charset_normalizer it raises ImportError): either way the file is named as unusable.
@pytest.mark.parametrize("mesh, says", [
    (FLAT_STL, ("it is flat (all its points lie in one plane or line)",)),
    (b"solid x\n" + bytes(range(256)) * 8, ("the stl file holds no triangles", "not a readable stl file")),
    (b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 \xff\xfe\nendloop\nendfacet\nendsolid\n",
     ("not a readable stl file",)),
])
def test_unusable_mesh_is_the_same_error_in_every_export(tmp_path, capsys, mesh, says):
    path = _robot_with_mesh(tmp_path, mesh)
    for out in ("r.usda", "r.urdf"):
        code, _, err = run(["export", path, "-o", tmp_path / out], capsys)
        prefix = f"{path}:4: mesh {tmp_path / 'Link1.stl'} of part 'L1': "
        assert code == 1 and any(err.startswith(prefix + s) for s in says), err
        assert err.count("\n") == 1 and "charset" not in err and "Qhull" not in err and "module" not in err


def test_a_mesh_reader_missing_a_module_is_not_blamed_on_the_module(tmp_path, capsys, monkeypatch):
    """trimesh met a corrupt STL with ``No module named 'charset_normalizer'``: say the file is bad."""
    import trimesh

    def no_module(*args, **kwargs):
        raise ModuleNotFoundError("No module named 'charset_normalizer'")

    monkeypatch.setattr(trimesh, "load", no_module)
    path = _robot_with_mesh(tmp_path, b"solid odd\n")
    code, _, err = run(["export", path, "-o", tmp_path / "r.usda"], capsys)
    assert code == 1 and err == f"{path}:4: mesh {tmp_path / 'Link1.stl'} of part 'L1': not a readable stl file\n"


def test_missing_mesh_is_the_same_warning_in_every_export(tmp_path, capsys):
    path = tmp_path / "m.rsxml"
    path.write_text(mechanism(1, part_source="Gone.SAT"))
    for out in ("r.usda", "r.urdf"):
        code, _, err = run(["export", path, "-o", tmp_path / out], capsys)
        assert code == 0 and "warning: no mesh beside the file for any part" in err


def test_argument_errors_blame_the_argument(capsys):
    for argv, says in ((["sweep", BRANCHING, "--out", "x", "--seed", "-1"], "argument --seed: must be at least 0, not -1"),
                       (["export", BRANCHING, "-o", "x.usda", "--density", "inf"],
                        "argument --density: must be a finite number > 0, not 'inf'"),
                       (["sweep", BRANCHING, "--out", "x", "--samples", "0"], "argument --samples: must be at least 1")):
        code, out, err = run(argv, capsys)
        assert code == 1 and says in err and str(BRANCHING) not in err and err.count("\n") == 1


# -- 12. trip-ups of a new user --------------------------------------------------------------------------


def test_no_cuda_driver_line_on_a_machine_without_a_gpu():
    done = subprocess.run([sys.executable, "-m", "rswarp.cli", "fk", str(BRANCHING), "--q", "0,0,0,0"],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and "CUDA" not in done.stderr and done.stderr == ""


def test_info_shows_where_each_part_is_placed(capsys):
    code, out, _ = run(["info", DATA / "transforms.rsxml"], capsys)
    assert code == 0 and "placed at [mm]" in out
    assert [line.split()[-6:] for line in out.splitlines() if line.strip().startswith("Group   Deep")] == \
        [["(-20,", "0,", "1000)", "(0,", "0,", "90)"]]
    code, out, _ = run(["info", DATA / "transforms.rsxml", "--json"], capsys)
    deep = [p for link in json.loads(out)["model"]["links"] for p in link["parts"] if p["name"] == "Deep"][0]
    assert deep["placement"]["translation"] == [-0.02, 0.0, 1.0]


def test_save_keeps_the_note_before_the_root(tmp_path):
    mech = rswarp.load(examples.IRB2600)
    rswarp.save(mech, tmp_path / "copy.rsxml")
    text = (tmp_path / "copy.rsxml").read_text()
    assert "Apache-2.0" in text and text.index("Apache-2.0") < text.index("<Mechanism")
    assert rswarp.load(tmp_path / "copy.rsxml") == mech


def test_fk_warns_about_values_outside_the_limits(capsys):
    code, _, err = run(["fk", BRANCHING, "--q", "0,171,0,0"], capsys)
    assert code == 0 and err == "rswarp: warning: Shoulder = 171 is outside its limits [-170, 170]\n"


# -- a fuzz over the command line, each case bounded in time and memory -----------------------------------

FILES = [BRANCHING, DATA / "parallel_rod.rsxml", DATA / "transforms.rsxml", DATA / "cable.rsxml",
         DATA / "bad" / "billion_laughs.rsxml", DATA / "bad" / "home_outside_limits.rsxml", DATA / "library" / "Robots.xml",
         DATA / "smart" / "Counter.rsxml", "/dev/zero", "/nonexistent/x.rsxml", DATA]
VALUES = ["0", "1", "-1", "25", "1e308", "nan", "inf", "-inf", "0,0,0,0", "-90,0,0,0", "1_0", "\u0661", "", "x",
          "0.001", "1e-300", "100000"]
OPTIONS = {
    "check": [["--json"]],
    "info": [["--json"]],
    "fk": [["--q", VALUES], ["--json"]],
    "sweep": [["--samples", ["1", "50", "0", "-3", "2e3", "x"]], ["--method", ["random", "sobol", "grid", "bogus"]],
              ["--seed", VALUES], ["--resolution", VALUES], ["--json"]],
    "export": [["--layout", ["flat", "component", "x"]], ["--density", VALUES], ["--json"]],
}
SUFFIXES = [".usda", ".usdc", ".usdz", ".urdf", ".obj", "/"]


@st.composite
def command_lines(draw, out_dir):
    command = draw(st.sampled_from(sorted(OPTIONS)))
    argv = [command, str(draw(st.sampled_from(FILES)))]
    for option in draw(st.lists(st.sampled_from(OPTIONS[command]), max_size=3, unique_by=lambda o: o[0])):
        argv += [option[0]] + ([draw(st.sampled_from(option[1]))] if len(option) > 1 else [])
    if command == "sweep":
        argv += ["--out", str(out_dir / draw(st.sampled_from(["s1", "s2"])))]
    if command == "export":
        argv += ["-o", str(out_dir) + "/r" + draw(st.sampled_from(SUFFIXES))]
    if command == "fk" and "--q" not in argv:
        argv += ["--q", "0,0,0,0"]
    if command == "sweep" and "--samples" not in argv:
        argv += ["--samples", "200"]
    return argv


def _alarm(signum, frame):
    raise TimeoutError("a command line case ran over its time bound")


@pytest.mark.filterwarnings("error::RuntimeWarning")
@settings(max_examples=150, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_command_line_fuzz(data, tmp_path_factory, capsys):
    out_dir = tmp_path_factory.mktemp("fuzz")
    argv = data.draw(command_lines(out_dir))
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(120)  # generous: a case that hangs fails instead of stalling CI
    tracemalloc.start()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", RuntimeWarning)  # no numpy RuntimeWarning reaches the user
            code = main(argv)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
    out = capsys.readouterr()
    assert code in (0, 1), (argv, out.err)
    assert "Traceback" not in out.err and "internal error" not in out.err, (argv, out.err)
    assert peak < 512 * 2**20, argv
    if code == 1 and argv[0] == "check" and "--json" in argv:  # its failures are in the JSON
        assert json.loads(out.out)["ok"] is False, argv
    elif code == 1:
        assert out.err.strip(), argv
    if "--json" in argv and out.out:
        json.loads(out.out)
