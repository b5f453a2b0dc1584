"""The exports' view of a model: the mechanism a file holds (inside a SmartComponent or not) and
the passive joints of its loops at home. The link frames themselves are ``geometry.frames``'."""

from __future__ import annotations

import numpy as np

from ..errors import model_error
from ..kinematics.loops import UnsolvedLoop, passive_map, passive_values
from ..rsxml.model import Mechanism


def mechanism_of(model):
    """The mechanism to export, and the SmartComponent around it (None if there is none)."""
    from ..rsxml.model import SmartComponent

    if isinstance(model, SmartComponent):
        mechs = [c for c in model.components if isinstance(c, Mechanism)]
        if not mechs:
            raise model_error(model, f"SmartComponent '{model.name}' holds no mechanism to export")
        return mechs[0], model
    return model, None


def home_passive(mech: Mechanism) -> dict[int, float]:
    """The passive joints of the loops at the home position, by link index; a loop that cannot be
    solved (unless home is the zero position), or cannot close at home, is the file's error at its
    closing joint."""
    if not mech.graph.closing:
        return {}
    home = mech.home_position()
    try:
        values = passive_values(passive_map(mech.graph), home[None])
    except UnsolvedLoop as exc:
        if not home.any():
            return {}  # the zero position is assembled (the spec): every passive joint at zero
        raise exc.error(mech, "an export cannot start closed at home") from None
    if not all(np.isfinite(v[0]) for v in values.values()):
        j = mech.graph.closing[0]
        raise model_error(mech, "the home position lies past a dead point: a loop cannot close there", j.line)
    return {k: float(v[0]) for k, v in values.items()}
