"""The rod's contact slots, one table for the device code and the host (plain Python: the host
imports it without Warp). A slot is what a cable may meet, indexed alike in every per-slot array
the kernel writes (the least clearance to each, the wear map's sliding, a crush's status, the
pinch's two sides):

    slot 0 ...                  the meshes, in the order of ``RodParams.mesh``: each link's own
                                (slot = the link's index), then the environment's (fixed in the
                                world), then the tool's (riding its link)
    meshes + FLOOR              the floor
    meshes + CABLES             the cables: every capsule of the mechanism's cables, a cable's
                                own included (self-contact)

``meshes`` being the model's mesh count (``RodParams.mesh.shape[0]``); ``meshes + PAST_MESHES``
slots in all. Also here, the other values the kernel writes that the host reads back: an
environment's status and the "nothing within reach" of a clearance or bend radius."""

from __future__ import annotations

from typing import Iterable

# after the meshes: the floor, then the cables
FLOOR = 0
CABLES = 1
PAST_MESHES = 2  # slots after the meshes
FLOOR_NAME, CABLES_NAME = "floor", "cables"  # the names the host gives those two slots

# an environment's status; CRUSHED + slot: the robot pressed a cable into that slot half its radius deep
RUNNING, NOT_FINITE, RUNAWAY, CRUSHED = 0, 1, 2, 3

BIG = 1.0e30  # "nothing within reach": a clearance or bend radius none was found for (the host reads +inf)


def floor_slot(meshes: int) -> int:
    """The floor's slot in a model of ``meshes`` meshes."""
    return meshes + FLOOR


def cables_slot(meshes: int) -> int:
    """The cables' slot in a model of ``meshes`` meshes."""
    return meshes + CABLES


def slot_names(meshes: Iterable[str]) -> tuple[str, ...]:
    """Every slot's name, the meshes' (in ``RodParams.mesh`` order) given."""
    names = list(meshes)
    count = len(names)
    names += [""] * PAST_MESHES
    names[floor_slot(count)], names[cables_slot(count)] = FLOOR_NAME, CABLES_NAME
    return tuple(names)
