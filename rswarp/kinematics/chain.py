"""A mechanism's link tree as the flat arrays the kernels take (``rswarp.kernels.types.Chain``),
asked of the link graph, with the passive joints of its loops folded in."""

from __future__ import annotations

import numpy as np

from ..kernels.specs import FOUR_BAR
from ..kernels.types import FIXED, PRISMATIC, REVOLUTE, Chain
from ..rsxml.graph import LinkGraph
from ..rsxml.model import Mechanism
from .loops import UnsolvedLoop, closed_values, passive_map


def chain_of(graph: LinkGraph) -> Chain:
    """The tree joints of the graph as arrays, links in the file's order (closing joints are not in
    the tree; a link off the tree keeps the root's identity pose). The passive joints of loops
    follow the active ones (``loops.passive_map``); ``UnsolvedLoop`` for a loop that cannot be
    solved yet."""
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
    try:
        return chain_of(mech.graph)
    except UnsolvedLoop as exc:
        raise exc.error(mech, "kinematics, sweeps and collision checks cannot follow yet") from None


def loops_close(chain: Chain, q: np.ndarray) -> np.ndarray:
    """``(N,)`` True where every closed-form loop of the chain closes at ``q`` (float64): False past
    a four-bar's dead point, where the kernels' poses are NaN (the other closed forms close
    everywhere). Loops the Newton solve takes are asked of the kernels: ``Kinematics.loops_close``."""
    q = np.atleast_2d(np.asarray(q, np.float64))
    ok = np.ones(len(q), bool)
    for k in np.nonzero(chain.closed_form[:, 0] == FOUR_BAR)[0]:
        ok &= np.isfinite(closed_values(chain.closed_form[k], q @ chain.closed_input[k]))
    return ok
