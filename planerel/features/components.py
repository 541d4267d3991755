"""Connected components by union-find: the proposals' plane graph
(:func:`planerel.features.proposals.propose_objects`), the curved clusters and the pieces of one
tread (:mod:`planerel.features.tread_pieces`) group their nodes with it.  Moved out of
``relations`` (review71) so that ``tread_pieces``, which ``relations`` imports, needs no import
of ``relations``; ``relations.Components`` is the same class.
"""

from __future__ import annotations

__all__ = ["Components"]


class Components:
    """Connected components of an undirected graph grown by nodes and edges (union-find; the
    components networkx's ``connected_components`` gives, without building its graph)."""

    def __init__(self, nodes=()):
        #: node -> parent, in the order the nodes came
        self.parent: dict = {}
        for k in nodes:
            self.parent.setdefault(k, k)

    @property
    def nodes(self) -> list:
        """The nodes, in the order they came."""
        return list(self.parent)

    def _root(self, k):
        parent = self.parent
        r = k
        while parent[r] != r:
            r = parent[r]
        while parent[k] != r:  # path compression
            parent[k], k = r, parent[k]
        return r

    def add_edges(self, pairs) -> None:
        """Join the two ends of each pair (a node seen first here is added)."""
        parent = self.parent
        for a, b in pairs:
            parent.setdefault(a, a)
            parent.setdefault(b, b)
            ra, rb = self._root(a), self._root(b)
            if ra != rb:
                parent[rb] = ra

    def together(self, a, b) -> bool:
        """Whether ``a`` and ``b`` are in one component (False for a node not seen)."""
        if a not in self.parent or b not in self.parent:
            return False
        return self._root(a) == self._root(b)

    def groups(self) -> list[list]:
        """The components, each a list of its nodes in the order they came."""
        out: dict = {}
        for k in self.parent:
            out.setdefault(self._root(k), []).append(k)
        return list(out.values())
