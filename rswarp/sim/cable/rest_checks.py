"""Checks of a cable's rest shape before a run: a shape that starts through the floor or a link
cannot be settled by the run (the contact would read it as a crush at the first frame), so it is
the model's error, said at the cable's line with what to change."""

from __future__ import annotations

import numpy as np

from ...errors import model_error
from ...rsxml.model import Mechanism
from .layout import RodLayout

ALONG = np.array([0.25, 0.5, 0.75])  # where along each segment its centre line is tested


def above_floor(mech: Mechanism, layout: RodLayout, floor: float | None) -> None:
    """A cable whose rest shape passes through the floor cannot be held up by it: an error at its line."""
    if floor is None:
        return
    for c, cable in zip(layout.cables, mech.cables):
        depth = floor - (c.points[:, 2] - c.section.radius).min()
        if depth > c.section.radius / 2:
            raise model_error(mech, f"cable '{cable.name}' starts {depth:.3g} m into the floor (z = {floor:g} m): "
                                    "route it above the floor, or give a lower --floor", cable.line)


def outside_links(mech: Mechanism, layout: RodLayout) -> None:
    """A cable whose rest shape (at the zero position) lies half its radius or more inside a link,
    where the run lets it touch that link (not beside its own clamps): an error at its line, naming
    the link, where along the cable and the span. Links with no closed mesh are left to the run,
    whose contact judges them by winding number."""
    import trimesh

    from ...geometry.meshes import closed_link_meshes

    for j, name, closed in closed_link_meshes(mech):
        for c, cable in zip(layout.cables, mech.cables):
            free = layout.touch[c.first:c.first + c.segments, j] > 0
            if not free.any():
                continue
            a, b = c.points[:-1][free], c.points[1:][free]
            samples = (a[:, None] + ALONG[None, :, None] * (b - a)[:, None]).reshape(-1, 3)
            inside = trimesh.proximity.signed_distance(closed, samples).reshape(-1, len(ALONG)).max(axis=1)
            r = c.section.radius
            if inside.max() > -r / 2:
                raise _crossing(mech, cable, c, np.flatnonzero(free)[int(np.argmax(inside))], name, inside.max() + r)


def _crossing(mech: Mechanism, cable, c, segment: int, link: str, depth: float) -> Exception:
    """The error for a rest shape ``depth`` m into ``link`` at ``segment``, naming its span."""
    nodes = [int(np.argmin(np.linalg.norm(c.points - np.asarray(p.position, float), axis=1)))
             for p in cable.control_points]  # each control point is a node of the rest shape
    span = max(sum(n <= segment for n in nodes), 1)
    at = 0.5 * (c.arc[segment] + c.arc[segment + 1])
    return model_error(mech, f"cable '{cable.name}' at rest lies {depth * 1000:.0f} mm deep in '{link}', {at:.3g} m "
                            f"along it: its span between control points {span} and {span + 1}, bowed down to its "
                            "length, crosses the link; add a ControlPoint to route it around", cable.line)
