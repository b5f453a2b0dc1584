"""A mechanism's link tree as the flat arrays the kernels take (``rswarp.kernels.types.Chain``),
asked of the link graph."""

from __future__ import annotations

import numpy as np

from ..kernels.types import FIXED, PRISMATIC, REVOLUTE, Chain
from ..rsxml.graph import LinkGraph
from ..rsxml.loops import UnsolvedLoop, passive_map
from ..rsxml.model import Mechanism


def chain_of(graph: LinkGraph) -> Chain:
    """The tree joints of the graph as arrays, links in the file's order (closing joints are not in
    the tree; a link off the tree keeps the root's identity pose). The passive joints of loops
    follow the active ones (``rswarp.rsxml.loops.passive_map``); ``UnsolvedLoop`` for a loop that
    cannot be solved yet."""
    n = len(graph.links)
    jtype = np.full(n, FIXED, np.int32)
    qidx = np.full(n, -1, np.int32)
    axis = np.zeros((n, 3))
    point = np.zeros((n, 3))
    for k, j in graph.tree_order:
        jtype[k] = REVOLUTE if j.revolute else PRISMATIC
        qidx[k] = graph.column(j.name)
        axis[k] = j.axis
        point[k] = j.point1
    return Chain(parent=np.asarray(graph.parent, np.int32), jtype=jtype, qidx=qidx, axis=axis, point=point,
                 order=np.asarray(graph.order, np.int32), **vars(passive_map(graph)))


def mechanism_chain(mech: Mechanism) -> Chain:
    """``chain_of`` the mechanism's graph; a loop it cannot solve is the file's error, at the joint
    that closes the loop."""
    from ..errors import model_error

    try:
        return chain_of(mech.graph)
    except UnsolvedLoop as exc:
        j = exc.loop.closing
        raise model_error(mech, f"joint '{j.name}' closes a kinematic loop that kinematics, sweeps and collision "
                                f"checks cannot follow yet: {exc}", j.line) from None


def closes(chain: Chain, q: np.ndarray) -> np.ndarray:
    """``(N,)`` True where every loop of the chain closes at ``q`` (float64): False past a dead point
    of a four-bar or of a loop the Newton solve takes, where the kernels' poses are NaN. The other
    closed forms close everywhere."""
    from ..rsxml.closed import FOUR_BAR
    from ..rsxml.general import general_values
    from ..rsxml.loops import closed_values

    q = np.atleast_2d(np.asarray(q, np.float64))
    ok = np.ones(len(q), bool)
    for k in np.nonzero(chain.closed[:, 0] == FOUR_BAR)[0]:
        ok &= np.isfinite(closed_values(chain.closed[k], q @ chain.closed_coef[k]))
    if len(chain.general):
        ok &= np.isfinite(general_values(chain.general, q, int(chain.unknown.max()) + 1)).all(axis=1)
    return ok
