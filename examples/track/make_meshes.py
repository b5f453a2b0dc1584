"""Writes the simple meshes of the IRBT2005_4m example track (binary STL, millimetres, the zero
position in world coordinates as the RSXML expects): a floor rail and a carriage, boxes only.

Run once from anywhere (``python examples/track/make_meshes.py``); the STL files it writes beside it
are committed, so nothing runs this at install or test time. The dimensions are the ones
docs/cells.md lists, in the manner of ABB's IRBT 2005 (not its CAD).
"""

from pathlib import Path

import trimesh

HERE = Path(__file__).parent
RAIL_X = (-300.0, 4300.0)  # mm: 4.6 m of rail, the carriage's 4 m of travel plus its length less 400 mm
RAIL_TOP = 200.0  # mm: top of the rails, where the carriage runs
PLATE_TOP = 400.0  # mm: the carriage's top plate, where a robot's base is bolted


def box(lo, hi) -> trimesh.Trimesh:
    """An axis-aligned box from corner ``lo`` to corner ``hi`` (mm)."""
    extents = [b - a for a, b in zip(lo, hi)]
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    return trimesh.creation.box(extents=extents, transform=trimesh.transformations.translation_matrix(centre))


def rail() -> trimesh.Trimesh:
    """The floor beam (0.7 m wide, 150 mm high) with two guide rails on it, 500 mm apart."""
    x0, x1 = RAIL_X
    parts = [box((x0, -350, 0), (x1, 350, 150))]
    parts += [box((x0, y - 25, 150), (x1, y + 25, RAIL_TOP)) for y in (-250.0, 250.0)]
    return trimesh.util.concatenate(parts)


def carriage() -> trimesh.Trimesh:
    """The carriage at the zero position, centred on x = 0: running blocks on the rails, a body,
    and the top plate 1.0 m x 0.8 m x 30 mm whose top is the robot's mounting face."""
    parts = [box((-400, y - 60, RAIL_TOP), (400, y + 60, 260)) for y in (-250.0, 250.0)]
    parts.append(box((-450, -330, 260), (450, 330, PLATE_TOP - 30)))
    parts.append(box((-500, -400, PLATE_TOP - 30), (500, 400, PLATE_TOP)))
    return trimesh.util.concatenate(parts)


def main() -> None:
    for name, mesh in (("track_rail", rail()), ("track_carriage", carriage())):
        mesh.export(HERE / f"{name}.stl", file_type="stl")


if __name__ == "__main__":
    main()
