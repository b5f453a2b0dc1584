"""Mesh files stand in for CAD sources (same stem, any case), scaled and placed in the world."""

import numpy as np
import pytest

import rswarp
from rswarp import examples
from rswarp.geometry import link_mesh, mesh_candidates, part_mesh, part_mesh_path

from conftest import DATA


def test_irb2600_meshes_are_found_watertight_and_placed():
    m = rswarp.load(examples.IRB2600)
    meshes = {name: link_mesh(m, name) for name in m.link_names}
    assert all(mesh.is_watertight for mesh in meshes.values())
    assert [len(mesh.faces) for mesh in meshes.values()] == [436, 768, 960, 1482, 1162, 886, 390]
    # link 6 (the flange disc) sits just behind the flange at x = 1.03 m, on the J6 axis z = 1.26 m
    lo, hi = meshes["Link6"].bounds
    assert hi[0] == pytest.approx(1.03, abs=1e-3) and (lo[2] + hi[2]) / 2 == pytest.approx(1.26, abs=1e-3)
    # the base stands on the floor
    assert meshes["Base"].bounds[0][2] == pytest.approx(0.0, abs=1e-3)


def test_lookup_is_case_insensitive_and_takes_backslash_folders():
    m = rswarp.load(DATA / "meshes" / "Cell.rsxml")
    parts = {p.name: (p, t) for link in m.link_names for p, t in m.parts(link)}
    assert part_mesh_path(m, parts["Arm"][0]).name == "ARM.OBJ"
    assert part_mesh_path(m, parts["Base"][0]).relative_to(DATA / "meshes").as_posix() == "parts/base.stl"


def test_mesh_is_read_in_the_file_length_unit_and_moved_by_its_part():
    m = rswarp.load(DATA / "meshes" / "Cell.rsxml")
    arm = link_mesh(m, "Arm")
    assert np.allclose(arm.bounds, [[0, 0, 0.1], [0.01, 0.01, 0.11]])  # 10 mm tetrahedron lifted 100 mm
    assert arm.volume == pytest.approx(0.01 ** 3 / 6)


def test_missing_mesh_names_every_file_tried():
    m = rswarp.load(DATA / "meshes" / "Cell.rsxml")
    (ghost, t), = m.parts("Ghost")
    with pytest.raises(rswarp.MeshNotFoundError) as info:
        part_mesh(m, ghost, t)
    message = str(info.value)
    assert message.startswith(f"{m.path}:8: no mesh for part 'Ghost' (source 'missing.SAT'); looked for ")
    for cand in mesh_candidates("missing.SAT", DATA / "meshes"):
        assert str(cand) in message
    assert [c.suffix for c in mesh_candidates("missing.SAT", DATA)] == [".stl", ".obj", ".ply", ".glb", ".gltf", ".off"]


def test_kinematics_need_no_meshes():
    m = rswarp.load(examples.IRB1300)
    assert all(part_mesh_path(m, p) is None for link in m.link_names for p, _ in m.parts(link))
