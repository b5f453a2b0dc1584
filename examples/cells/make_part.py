"""Writes ``weld_part.stl``, the work piece positioner_cell.toml clamps on the face plate: a block
400 x 200 x 100 mm (binary STL in metres, the IRB 2600 RSXML's length unit, which a cell's meshes
are read in), standing on the plate, centred on it; positioner_weld.mod's seam runs along its top.

Run once (``python examples/cells/make_part.py``); the STL is committed."""

from pathlib import Path

import trimesh

PART = (0.4, 0.2, 0.1)  # m: length (x), width (y), height (z) of the block


def part() -> trimesh.Trimesh:
    return trimesh.creation.box(extents=PART, transform=trimesh.transformations.translation_matrix(
        (0.0, 0.0, PART[2] / 2)))


if __name__ == "__main__":
    part().export(Path(__file__).parent / "weld_part.stl")
