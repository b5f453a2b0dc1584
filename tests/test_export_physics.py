"""Exports that simulate, the parts around the solvers: collision geometry computed once and
cached, reserved names, the command's options and mass table, safe component outputs, signals,
and large meshes."""

import json
import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
import trimesh
from generated import mechanism, torus_ply

import rswarp
from rswarp import examples
from rswarp.cli import main
from rswarp.export import export
from rswarp.geometry import convex

from conftest import DATA

pxr = pytest.importorskip("pxr")
from pxr import Usd, UsdGeom, UsdPhysics  # noqa: E402

ENV = {**os.environ, "PYTHONPATH": str(Path(__file__).parent)}


def u_shape() -> trimesh.Trimesh:
    """A U of three boxes: far from convex, so a decomposition must split it."""
    boxes = [trimesh.creation.box((0.1, 0.1, 0.5), trimesh.transformations.translation_matrix(t))
             for t in ((-0.2, 0, 0.25), (0.2, 0, 0.25), (0, 0, 0.05))]
    boxes[2] = trimesh.creation.box((0.5, 0.1, 0.1), trimesh.transformations.translation_matrix((0, 0, 0.05)))
    return trimesh.boolean.union(boxes) if trimesh.boolean.engines_available else trimesh.util.concatenate(boxes)


def test_convex_pieces_are_convex_and_cached(monkeypatch):
    mesh = u_shape()
    hull = convex.convex_pieces(mesh.vertices, mesh.faces, "convexHull")
    assert len(hull) == 1 and trimesh.Trimesh(hull[0].vertices, hull[0].faces).is_convex
    pieces = convex.convex_pieces(mesh.vertices, mesh.faces, "convexDecomposition")
    assert len(pieces) >= 3
    for p in pieces:
        t = trimesh.Trimesh(p.vertices, p.faces)
        assert t.is_convex and t.volume > 0
    assert sum(trimesh.Trimesh(p.vertices, p.faces).volume for p in pieces) < 0.8 * hull_volume(hull)
    import coacd

    monkeypatch.setattr(coacd, "run_coacd", lambda *a, **k: pytest.fail("recomputed a cached decomposition"))
    again = convex.convex_pieces(mesh.vertices, mesh.faces, "convexDecomposition")
    assert len(again) == len(pieces) and all(np.array_equal(a.vertices, b.vertices) for a, b in zip(again, pieces))


def hull_volume(pieces) -> float:
    return trimesh.Trimesh(pieces[0].vertices, pieces[0].faces).volume


def test_a_large_mesh_hull_is_reduced_but_inside_the_exact_hull():
    rng = np.random.default_rng(0)
    points = rng.normal(size=(convex.EXACT_HULL_VERTICES + 1, 3))
    reduced = convex.convex_pieces(points, np.zeros((0, 3), np.int64))[0]
    exact = trimesh.convex.convex_hull(points)
    assert len(reduced.vertices) <= convex.HULL_DIRECTIONS
    assert np.all(exact.contains(reduced.vertices * 0.999))  # a subset of the exact hull's vertices
    assert trimesh.Trimesh(reduced.vertices, reduced.faces).volume > 0.97 * exact.volume


def test_usd_collision_meshes_are_explicit_convex_pieces(tmp_path):
    mech = rswarp.load(examples.IRB2600)
    result = export(mech, tmp_path / "r.usda", collision="convexDecomposition")
    stage = Usd.Stage.Open(str(tmp_path / "r.usda"))
    colliders = [p for p in stage.Traverse() if p.HasAPI(UsdPhysics.CollisionAPI)]
    assert len(colliders) == sum(len(p.pieces) for b in result.physics.bodies.values() for p in b.parts) >= 7
    for prim in colliders:
        assert UsdPhysics.MeshCollisionAPI(prim).GetApproximationAttr().Get() == "convexHull"
        assert prim.GetCustomDataByKey("rsxml")["collision"] == "convexDecomposition"
        mesh = UsdGeom.Mesh(prim)
        points = np.asarray(mesh.GetPointsAttr().Get(), float)
        piece = trimesh.Trimesh(points, np.asarray(mesh.GetFaceVertexIndicesAttr().Get()).reshape(-1, 3), process=False)
        assert piece.volume == pytest.approx(trimesh.convex.convex_hull(points).volume, rel=1e-5)  # its own hull


def test_reserved_names_get_their_own_prims_with_a_warning(tmp_path):
    mech = rswarp.load(DATA / "meshes" / "Reserved.rsxml")
    result = export(mech, tmp_path / "r.usda")
    assert [w.split(":")[0] for w in result.warnings] == ["link 'joints'", "flange 'visuals'"]
    stage = Usd.Stage.Open(str(tmp_path / "r.usda"))
    link = stage.GetPrimAtPath("/Reserved/joints_1")
    assert link.HasAPI(UsdPhysics.RigidBodyAPI) and link.GetDisplayName() == "joints"
    assert stage.GetPrimAtPath("/Reserved/joints").GetTypeName() == "Scope"
    assert stage.GetPrimAtPath("/Reserved/joints/J1").IsA(UsdPhysics.RevoluteJoint)
    flange = stage.GetPrimAtPath("/Reserved/joints_1/visuals_1")
    assert flange.GetDisplayName() == "visuals" and flange.GetCustomDataByKey("rsxml") == {"flange": True}
    assert stage.GetPrimAtPath("/Reserved/joints_1/visuals").GetTypeName() == "Scope"
    assert [c.GetName() for c in stage.GetPrimAtPath("/Reserved/joints_1/visuals").GetChildren()] == ["collisions"]


def test_export_command_prints_the_mass_table_and_refuses_options_of_other_formats(tmp_path, capsys):
    out = tmp_path / "r.usda"
    assert main(["export", str(examples.IRB2600), "-o", str(out), "--mass", "272"]) == 0
    text = capsys.readouterr().out
    assert "Link6" in text and "total 272.000 kg" in text and "drives: 6 joints hold home" in text
    assert "1 touching at home (Link4/Link6)" in text
    assert main(["export", str(examples.IRB2600), "-o", str(out), "--json", "--drive-hz", "0", "--armature", "2"]) == 0
    doc = json.loads(capsys.readouterr().out)
    # the robot-data file beside the RSXML gives the mass (272 kg), not the density (425 kg at 2700 kg/m^3)
    assert doc["total_mass"] == pytest.approx(272.0, rel=1e-6) and len(doc["links"]) == 7
    assert all(j["stiffness"] == 0 and j["armature"] == 2 for j in doc["joints"])
    assert {"link1": "Link4", "link2": "Link6", "reason": "overlap at home"} in doc["filtered_pairs"]
    assert main(["export", str(examples.IRB2600), "-o", str(tmp_path / "r.urdf"), "--layout", "component"]) == 1
    assert capsys.readouterr().err.startswith("rswarp: --layout applies to USD outputs only")
    assert main(["export", str(examples.IRB2600), "-o", str(out), "--mesh-paths", "relative"]) == 1
    assert main(["export", str(examples.IRB2600), "-o", str(out), "--mass", "0"]) == 1
    assert not (tmp_path / "r.urdf").exists() and not (tmp_path / "meshes").exists()


def test_component_layout_keeps_the_users_files_and_survives_a_concurrent_export(tmp_path):
    payload = tmp_path / "r_Payload"
    payload.mkdir()
    (payload / "notes.txt").write_text("mine")
    (payload / "Contents.usda").write_text("stale")
    cmd = [sys.executable, "-m", "rswarp.cli", "export", str(examples.IRB2600), "-o", str(tmp_path / "r.usda"),
           "--layout", "component"]
    runs = [subprocess.Popen(cmd, env=ENV, stdout=subprocess.PIPE, stderr=subprocess.PIPE) for _ in range(2)]
    results = [(p.wait(timeout=300), p.stderr.read().decode()) for p in runs]
    assert results == [(0, ""), (0, "")]
    assert (payload / "notes.txt").read_text() == "mine"
    assert sorted(p.name for p in payload.iterdir()) == [
        "Contents.usda", "Geometry.usdc", "Materials.usda", "Physics.usda", "notes.txt"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.usda", "r_Payload"]  # no temporary folder left
    stage = Usd.Stage.Open(str(tmp_path / "r.usda"))
    assert len([p for p in stage.Traverse() if p.HasAPI(UsdPhysics.RigidBodyAPI)]) == 7


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
@pytest.mark.parametrize("suffix", [".usda", ".urdf"])
def test_a_signal_during_an_export_leaves_nothing_behind(tmp_path, sig, suffix):
    """The signal arrives while the files are being written (sent by the process to itself from
    inside the writer, so the timing is certain)."""
    script = textwrap.dedent(f"""
        import os, signal, sys
        import rswarp.export.usd as usd, rswarp.export.urdf as urdf
        real = usd.build_stage if {suffix!r} != ".urdf" else urdf._Files.write
        def late(*args, **kwargs):
            out = real(*args, **kwargs)
            os.kill(os.getpid(), {int(sig)})
            return out
        if {suffix!r} != ".urdf":
            import rswarp.export.usd_layout as layout; layout.build_stage = late
        else:
            urdf._Files.write = late
        from rswarp.cli import main
        sys.exit(main(["export", {str(examples.IRB2600)!r}, "-o", {str(tmp_path / "out" / ("r" + suffix))!r}]))
    """)
    run = subprocess.run([sys.executable, "-c", script], env=ENV, capture_output=True, text=True, timeout=300)
    assert run.returncode == (143 if sig == signal.SIGTERM else 130), run.stderr
    assert "Traceback" not in run.stderr
    assert list(tmp_path.iterdir()) == []  # not even the output folder it made


def test_a_two_million_triangle_mesh_exports_in_bounded_memory(tmp_path):
    """Arrays go to USD through NumPy: the peak is measured in a fresh process against its own
    baseline after the imports."""
    triangles = torus_ply(tmp_path / "part.ply", 1000, 1000)
    assert triangles == 2_000_000
    (tmp_path / "big.rsxml").write_text(mechanism(1, part_source="part.SAT"))
    script = textwrap.dedent(f"""
        import resource, time
        import rswarp
        from rswarp.export import export
        from pxr import Usd
        mech = rswarp.load({str(tmp_path / "big.rsxml")!r})
        base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        start = time.perf_counter()
        export(mech, {str(tmp_path / "big.usdc")!r})
        print(time.perf_counter() - start, (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - base) * 1024)
    """)
    run = subprocess.run([sys.executable, "-c", script], env=ENV, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    seconds, grown = map(float, run.stdout.split())
    file_size = (tmp_path / "part.ply").stat().st_size
    assert grown < 40 * file_size, f"{grown / 2**20:.0f} MiB for a {file_size / 2**20:.0f} MiB mesh"
    stage = Usd.Stage.Open(str(tmp_path / "big.usdc"))
    mesh = UsdGeom.Mesh(stage.GetPrimAtPath("/Chain/L1/visuals/L1"))
    assert len(mesh.GetFaceVertexCountsAttr().Get()) == triangles
