"""The link graph of a mechanism as topology, built once and asked by everything else: validation,
kinematics, the exporters and the sweeps. Nothing else walks the joints. (How a loop's passive
joints move is kinematics: ``rswarp.kinematics.loops``.)

Rules (the same for every user):
- Joints go from ``parent`` to ``child``. A joint naming an unknown link, repeating a joint name,
  joining a link to itself or moving the base link is left out (``ignored``); validation reports it.
- The tree: breadth-first from the base over the active joints first, then over the passive ones,
  each link's joints in file order. A link keeps the first joint that reaches it (``tree_joint``).
  Every other joint between reached links closes a loop (``closing``); preferring active joints for
  the tree means a passive joint closes each loop wherever one can.
- A loop is the closing joint plus the tree paths from its two links to their common ancestor.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field
from functools import cached_property
from types import MappingProxyType
from typing import Iterable, Mapping, Protocol, Sequence


class Joint(Protocol):
    """What the graph reads of a joint (``rswarp.rsxml.model.Joint``): the model builds its graph,
    so the graph does not import the model."""

    name: str
    parent: str
    child: str
    active: bool


class Mechanism(Protocol):
    """What the graph reads of a mechanism (``rswarp.rsxml.model.Mechanism``)."""

    link_names: tuple[str, ...]
    joints: Sequence[Joint]
    base_link: str


@dataclass(frozen=True, eq=False)
class LinkGraph:
    """The joint graph of one mechanism. Links are indexed in the file's order."""

    base: str
    links: tuple[str, ...]  # file order
    index: Mapping[str, int]  # link name -> position in ``links`` (first of a repeated name)
    order: tuple[int, ...]  # reached links, parents before children (breadth-first), base first
    parent: tuple[int, ...]  # per link: the parent link's index, -1 for the base and unreached links
    tree_joint: tuple[Joint | None, ...]  # per link: the joint that moves it (None: base, unreached)
    depth: tuple[int, ...]  # per link: tree joints between it and the base (-1 unreached)
    closing: tuple[Joint, ...]  # joints that close a loop, file order
    joints: tuple[Joint, ...]  # the joints in the graph, file order
    ignored: tuple[Joint, ...]  # joints left out of the graph (bad references, repeated names)
    active: tuple[Joint, ...]  # active joints in file order: the columns of joint values q
    joints_by_name: Mapping[str, Joint] = field(repr=False)
    _late: tuple[bool, ...] = field(repr=False)  # per link: reached only through a passive joint

    # -- building ------------------------------------------------------------------------------------
    @staticmethod
    def of(mech: Mechanism) -> "LinkGraph":
        """The mechanism's graph (``mech.graph`` caches it)."""
        return mech.graph

    @classmethod
    def build(cls, mech: Mechanism) -> "LinkGraph":
        links = mech.link_names
        index: dict[str, int] = {}
        for i, name in enumerate(links):
            index.setdefault(name, i)
        valid, ignored = _sort_joints(mech.joints, index, mech.base_link)
        n = len(links)
        parent, tree_joint, depth = [-1] * n, [None] * n, [-1] * n
        late = [False] * n
        order: list[int] = []
        base = index.get(mech.base_link)
        if base is not None:
            depth[base] = 0
            order.append(base)
            by_parent: dict[int, list[Joint]] = {}
            for j in valid:
                by_parent.setdefault(index[j.parent], []).append(j)
            for phase in (0, 1):  # active joints span the tree first, then passive ones join
                queue = deque(order)
                while queue:
                    p = queue.popleft()
                    for j in by_parent.get(p, ()):
                        c = index[j.child]
                        if depth[c] >= 0 or (phase == 0 and not j.active):
                            continue
                        parent[c], tree_joint[c], depth[c] = p, j, depth[p] + 1
                        late[c] = phase == 1
                        order.append(c)
                        queue.append(c)
        in_tree = {id(j) for j in tree_joint if j is not None}
        closing = tuple(j for j in valid if id(j) not in in_tree and depth[index[j.parent]] >= 0)
        return cls(base=mech.base_link, links=links, index=MappingProxyType(index), order=tuple(order),
                   parent=tuple(parent), tree_joint=tuple(tree_joint), depth=tuple(depth), closing=closing,
                   joints=tuple(valid), ignored=tuple(ignored), active=tuple(j for j in mech.joints if j.active),
                   joints_by_name=MappingProxyType({j.name: j for j in reversed(mech.joints)}),
                   _late=tuple(late))

    # -- questions -----------------------------------------------------------------------------------
    def link_index(self, link: str) -> int:
        try:
            return self.index[link]
        except KeyError:
            raise KeyError(f"no link '{link}' (links: {', '.join(self.links)})") from None

    def joint(self, name: str) -> Joint:
        return self.joints_by_name[name]

    @property
    def is_tree(self) -> bool:
        return not self.closing

    @property
    def unreachable(self) -> tuple[str, ...]:
        """Links not connected to the base, file order."""
        return tuple(name for i, name in enumerate(self.links) if self.depth[i] < 0 and self.index[name] == i)

    @property
    def tree_order(self) -> tuple[tuple[int, Joint], ...]:
        """(link index, joint that moves it) for every reached link but the base, parents first."""
        return tuple((k, self.tree_joint[k]) for k in self.order if self.tree_joint[k] is not None)

    @cached_property
    def depth_first(self) -> tuple[tuple[int, Joint], ...]:
        """``tree_order`` depth first: each subtree whole before its sibling's (the joint order
        MuJoCo keeps, so a Newton model built in it converts without reordering)."""
        children: dict[int, list[tuple[int, Joint]]] = {}
        for k, j in self.tree_order:
            children.setdefault(self.parent[k], []).append((k, j))
        out, stack = [], list(reversed(children.get(self.index[self.base], [])))
        while stack:
            k, j = stack.pop()
            out.append((k, j))
            stack.extend(reversed(children.get(k, [])))
        return tuple(out)

    def column(self, joint: str) -> int:
        """The joint's column in joint values q, or -1 for a passive joint."""
        return self._columns.get(joint, -1)

    @cached_property
    def _columns(self) -> dict[str, int]:
        return {j.name: i for i, j in enumerate(self.active)}

    def path(self, link: str) -> tuple[Joint, ...]:
        """The tree joints from the base to ``link``."""
        out, k = [], self.link_index(link)
        while self.tree_joint[k] is not None:
            out.append(self.tree_joint[k])
            k = self.parent[k]
        return tuple(reversed(out))

    def joints_from(self, link: str) -> tuple[Joint, ...]:
        """Every joint in the graph whose parent is ``link`` (tree and closing), file order."""
        return self._joints_from.get(link, ())

    @cached_property
    def _joints_from(self) -> dict[str, tuple[Joint, ...]]:
        acc: dict[str, list[Joint]] = {}
        for j in self.joints:
            acc.setdefault(j.parent, []).append(j)
        return {k: tuple(v) for k, v in acc.items()}

    def loop(self, closing: Joint) -> tuple[Joint, ...]:
        """The joints of the loop a closing joint closes: the tree path from its parent's side up to
        the common ancestor, down to its child, then the closing joint."""
        up, down, _ = self._meet(self.index[closing.parent], self.index[closing.child])
        return tuple(self.tree_joint[k] for k in up) + tuple(self.tree_joint[k] for k in reversed(down)) + (closing,)

    def common_ancestor(self, closing: Joint) -> int:
        """The link where the two tree paths of a closing joint's links meet (its loop's base)."""
        return self._meet(self.index[closing.parent], self.index[closing.child])[2]

    def _meet(self, a: int, b: int) -> tuple[list[int], list[int], int]:
        """The links passed going up from a and from b until the paths meet, and where they meet."""
        up, down = [], []
        while a != b:
            if self.depth[a] >= self.depth[b]:
                up.append(a)
                a = self.parent[a]
            else:
                down.append(b)
                b = self.parent[b]
        return up, down, a

    def closes_all_active_loop(self, closing: Joint) -> bool:
        """True when a loop has no passive joint: nothing in it can follow the others. The active
        joints alone reach both its links, so the tree path between them is active too."""
        late = self._late
        return closing.active and not late[self.index[closing.parent]] and not late[self.index[closing.child]]

    @cached_property
    def joints_in_loops(self) -> frozenset[str]:
        """Names of every joint on some loop, marked in near-linear time: each tree edge is marked
        once, and a union-find skips edges already marked."""
        up = list(range(len(self.links)))

        def find(x: int) -> int:
            while up[x] != x:
                up[x] = up[up[x]]
                x = up[x]
            return x

        marked = {j.name for j in self.closing}
        for j in self.closing:
            a, b = find(self.index[j.parent]), find(self.index[j.child])
            while a != b:
                if self.depth[a] < self.depth[b]:
                    a, b = b, a
                marked.add(self.tree_joint[a].name)
                up[a] = self.parent[a]
                a = find(a)
        return frozenset(marked)

    def adjacent_pairs(self, has_geometry: Iterable[str] | None = None) -> frozenset[frozenset[str]]:
        """Pairs of links joined by a joint. With ``has_geometry``, links without geometry are
        contracted away first (MoveIt's rule): links joined through them count as joined."""
        links = set(self.links) if has_geometry is None else set(has_geometry)
        neighbours: dict[str, set[str]] = {}
        for j in self.joints:
            neighbours.setdefault(j.parent, set()).add(j.child)
            neighbours.setdefault(j.child, set()).add(j.parent)
        pairs = set()
        for a in links:
            seen, queue = {a}, deque(neighbours.get(a, ()))
            while queue:
                b = queue.popleft()
                if b in seen:
                    continue
                seen.add(b)
                if b in links:
                    pairs.add(frozenset((a, b)))
                else:
                    queue.extend(neighbours.get(b, ()))
        return frozenset(pairs)

    # -- ABB conventions -------------------------------------------------------------------------------
    @property
    def first_axis(self) -> Joint | None:
        """J1: the first active joint, whose axis datasheets measure reach from."""
        return self.active[0] if self.active else None

    @property
    def wrist_joints(self) -> tuple[Joint, Joint] | None:
        """J4 and J5, whose axes define the wrist centre; None below five axes."""
        return (self.active[3], self.active[4]) if len(self.active) >= 5 else None


def _sort_joints(joints: Iterable[Joint], index: Mapping[str, int], base: str) -> tuple[list[Joint], list[Joint]]:
    """Joints the graph can use, and those it leaves out (validation reports why)."""
    valid, ignored, names = [], [], set()
    for j in joints:
        ok = (j.name not in names and j.parent in index and j.child in index and j.parent != j.child
              and j.child != base)
        names.add(j.name)
        (valid if ok else ignored).append(j)
    return valid, ignored
