"""Writes the simple meshes of the IRBP_A250 example positioner (binary STL, millimetres, the zero
position in world coordinates as the RSXML expects): a box stand (floor plate and column), a
tilting frame (an L-shaped arm and the turn unit's round housing) and a round face plate. Each is
nearly convex, so the convex hull rswarp exports for collisions stays close to it.

Run once from anywhere (``python examples/positioner/make_meshes.py``); the STL files it writes
beside it are committed, so nothing runs this at install or test time. The dimensions are the ones
docs/cells.md lists, in the manner of ABB's IRBP A-250 (not its CAD).
"""

from pathlib import Path

import numpy as np
import trimesh

HERE = Path(__file__).parent
TILT_Z = 900.0  # mm: height of the tilt axis (axis 1, along +x through y = 0)
PLATE_TOP = 800.0  # mm: the face plate's top at the zero position, 100 mm below the tilt axis
PLATE_R = 300.0  # mm: face plate radius (0.6 m across)
SECTIONS = 64  # facets round a cylinder


def box(lo, hi) -> trimesh.Trimesh:
    """An axis-aligned box from corner ``lo`` to corner ``hi`` (mm)."""
    extents = [b - a for a, b in zip(lo, hi)]
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    return trimesh.creation.box(extents=extents, transform=trimesh.transformations.translation_matrix(centre))


def cylinder(radius, z0, z1, axis="z", at=(0.0, 0.0)) -> trimesh.Trimesh:
    """A cylinder of ``radius`` from ``z0`` to ``z1`` along ``axis`` (z or x), its centre line
    through ``at`` (the other two coordinates: x, y for z; y, z for x)."""
    mesh = trimesh.creation.cylinder(radius=radius, height=z1 - z0, sections=SECTIONS)
    mesh.apply_translation((0.0, 0.0, (z0 + z1) / 2))
    if axis == "x":  # z -> x, x -> y, y -> z
        mesh.apply_transform(np.array([[0, 0, 1, 0], [1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 1]], float))
        mesh.apply_translation((0.0, *at))
    else:
        mesh.apply_translation((*at, 0.0))
    return mesh


def floor_plate() -> trimesh.Trimesh:
    """The stand's floor plate, 1.3 m x 1.0 m x 40 mm."""
    return box((-800, -500, 0), (500, 500, 40))


def column() -> trimesh.Trimesh:
    """The stand's column at -x that carries the tilt drive, its top 1.08 m above the floor."""
    return box((-800, -300, 40), (-560, 300, 1080))


def tilt_arm() -> trimesh.Trimesh:
    """Axis 1's arm: the hub on the tilt axis and an L down to the turn unit."""
    hub = cylinder(150, -560, -450, axis="x", at=(0.0, TILT_Z))
    upright = box((-450, -150, 620), (-350, 150, 1000))
    arm = box((-350, -140, 630), (-240, 140, 760))  # meets the housing (r 250) inside its round
    return trimesh.util.concatenate([hub, upright, arm])


def turn_housing() -> trimesh.Trimesh:
    """Axis 1's turn unit: the round housing of axis 2's drive under the face plate."""
    return cylinder(250, 600, PLATE_TOP - 30)


def face_plate() -> trimesh.Trimesh:
    """Axis 2's link: the round face plate, 30 mm thick, its top at ``PLATE_TOP``."""
    return cylinder(PLATE_R, PLATE_TOP - 30, PLATE_TOP)


def main() -> None:
    meshes = {"positioner_floor": floor_plate(), "positioner_column": column(), "positioner_tilt_arm": tilt_arm(),
              "positioner_turn_housing": turn_housing(), "positioner_faceplate": face_plate()}
    for name, mesh in meshes.items():
        mesh.export(HERE / f"{name}.stl", file_type="stl")


if __name__ == "__main__":
    main()
