"""SRDF collision matrices: ``<disable_collisions link1 link2 reason/>`` as MoveIt writes and reads
them. Written from a sweep (``rswarp collisions``) or from an export's filtered pairs (beside a
URDF); read back by ``rswarp export --collision-matrix``."""

from __future__ import annotations

from pathlib import Path
from xml.sax.saxutils import quoteattr

from ..errors import Diagnostic, RsxmlError
from ..rsxml.parse import parse_xml

# the reasons an export's own filtered pairs carry, in MoveIt's words; "User" is MoveIt's reading
# of any reason it does not know
EXPORT_REASONS = {"adjacent": "Adjacent", "overlap at home": "User"}


def srdf_text(robot: str, disabled, comment: str = "") -> str:
    """An SRDF holding one ``disable_collisions`` per (link1, link2, reason)."""
    lines = ['<?xml version="1.0" encoding="utf-8"?>']
    if comment:
        lines.append(f"<!-- {comment.replace('--', '- -')} -->")
    lines.append(f"<robot name={quoteattr(robot)}>")
    for a, b, reason in disabled:
        lines.append(f"  <disable_collisions link1={quoteattr(a)} link2={quoteattr(b)} reason={quoteattr(reason)}/>")
    lines.append("</robot>")
    return "\n".join(lines) + "\n"


def read_srdf(path: str | Path, links) -> tuple[tuple[str, str, str], ...]:
    """The disabled pairs of an SRDF: (link1, link2, reason), each link one of ``links``. Anything
    else is an RsxmlError at its line."""
    path = str(path)
    root = parse_xml(path)  # entities, DTDs and the network off, like every XML rswarp reads
    if root.tag != "robot":
        raise RsxmlError([Diagnostic(path, root.sourceline or 0, f"an SRDF's root is <robot>, not <{root.tag}>")])
    known, out = set(links), []
    for el in root.iter("disable_collisions"):
        a, b = el.get("link1"), el.get("link2")
        for name in (a, b):
            if name is None:
                raise RsxmlError([Diagnostic(path, el.sourceline or 0, "disable_collisions needs link1 and link2")])
            if name not in known:
                names = ", ".join(sorted(known))
                raise RsxmlError([Diagnostic(path, el.sourceline or 0,
                                             f"link '{name}' is not a link of this robot ({names})")])
        out.append((a, b, el.get("reason") or "User"))
    return tuple(out)


def collision_matrix(mech, srdf: str | Path | None = None,
                     samples: int | None = None) -> tuple[tuple[str, str, str], ...]:
    """The pairs a collision matrix disables for an export: those of the SRDF ``srdf``, or of a
    collision sweep of ``samples`` samples run now; none without either."""
    if srdf is not None:
        return read_srdf(srdf, mech.link_names)
    if samples is None:
        return ()
    from ..sim.collisions import collisions  # Warp and the collision kernels, only for a sweep

    return tuple(collisions(mech, samples=samples).disabled())
