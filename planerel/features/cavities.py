"""Concave cavities: the inside of one open object, seen through its open side.

The locally-convex rule of :func:`planerel.features.relations.convex_pairs` cuts every concave
edge: a box against a wall, a box on a box come apart.  An open object (a shelf, an open box,
a drawer) is concave *inside*: its back panel meets each side panel and each board at a concave
edge, and the rule cuts it into its panels.  What tells the inside of one object from two
objects that touch is the *shape of the concave edges*, not one edge alone:

- a **channel** (U): a plane ``B`` that meets two planes ``A`` and ``C`` at shared concave
  edges, where ``A`` and ``C`` are parallel, face each other (each one's visible side turned
  towards the other) and stand on opposite sides of ``B``: a shelf's back panel between its
  side panels, a board between them, an open box's bottom between two walls;
- an **inside corner**: three planes, no two parallel, each pair meeting at a shared concave
  edge: a shelf's back panel, a side panel and a board; the corner inside an open box.

Two convex objects touching along a face make one concave edge (a box against a wall) or a
chain of them (boxes in a row against a wall), not a channel or a corner: that needs a third
plane on the far side (an object squeezed between two others, a box in a room's corner,
whose walls are support and never take part).  A staircase's treads between its side walls
make channels too, but a side wall runs along the whole flight and a tread is one step deep:
those edges are not whole (below); the flight's planes together span the walls
(:func:`group_channel_pairs`).

**Rule** (:func:`cavity_pairs`): the concave pairs of a channel or an inside corner are
joined when every concave edge of it is *whole*: the two planes' extents along the edge line
overlap by at least ``min_overlap`` (interval IoU, 0.5; ``ProposalParams.cavity_overlap``).
A board spans its shelf's width and a side panel its height; the floor or a platform a shelf
stands on, or two panels a box is pushed against, run far beyond it (a box in a corner of two
panels meets both at concave edges, and they meet each other: a corner, but not a whole one).
Parameters: ``angle_tol`` (degrees; ``ProposalParams.concave_tol``, 10) for "parallel";
shared edges are those with at least ``MIN_EDGE`` pixel pairs of
:func:`~planerel.features.relations.edge_means`.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["cavity_pairs", "edge_overlap", "group_channel_pairs"]


def cross3(u, v) -> np.ndarray:
    """``np.cross(u, v)`` of two 3-vectors of floats: the same products and differences in
    Python floats (``a1 b2 - a2 b1``, ...; the floats numpy's cross gives) without its
    overhead (about 15 us a call)."""
    (u0, u1, u2), (v0, v1, v2) = (float(x) for x in u), (float(x) for x in v)
    return np.array([u1 * v2 - u2 * v1, u2 * v0 - u0 * v2, u0 * v1 - u1 * v0])


def _towards_sensor(p) -> np.ndarray:
    n = np.asarray(p.normal, float)
    return -n if float(n @ np.asarray(p.centroid, float)) > 0 else n


def edge_overlap(pa, pb) -> float:
    """Interval IoU (0-1) of two planes' extents (their 3-D hulls, ``hull3d``) along the line
    where they meet, ``n_a x n_b``; 0 for parallel planes."""
    axis = cross3(pa.normal, pb.normal)
    nrm = float(np.linalg.norm(axis))
    if nrm < 1e-6:
        return 0.0
    ta = np.asarray(pa.hull3d, float) @ (axis / nrm)
    tb = np.asarray(pb.hull3d, float) @ (axis / nrm)
    union = max(ta.max(), tb.max()) - min(ta.min(), tb.min())
    inter = min(ta.max(), tb.max()) - max(ta.min(), tb.min())
    return max(0.0, float(inter)) / float(union) if union > 0 else 0.0


def cavity_pairs(planes, concave, angle_tol: float = 10.0, min_overlap: float = 0.5) -> set:
    """Concave pairs that are the inside of one open object (a channel or an inside corner).

    Parameters
    ----------
    planes : PlaneSet or sequence of Plane
        The measured planes (``label``, ``normal``, ``centroid``, ``hull3d``).
    concave : iterable of (int, int)
        Label pairs meeting at a *shared* concave edge (adjacent, cut by the convexity rule,
        with enough edge pixel pairs).
    angle_tol : float
        Degrees: normals within this are parallel.
    min_overlap : float
        An edge is *whole* when the two planes' extents along it overlap by at least this
        (interval IoU, :func:`edge_overlap`): a shelf's board spans its back panel's width;
        the floor or a platform a shelf stands on runs far beyond its sides.  A channel and
        a corner need all their edges whole.

    Returns
    -------
    set of (int, int)
        The pairs of ``concave`` (as given) that belong to a channel or an inside corner.
    """
    byl = {p.label: p for p in planes}
    cos_tol = math.cos(math.radians(angle_tol))

    def key(a, b):
        return (min(a, b), max(a, b))

    # the whole concave edges: each plane spans the other's side along the edge
    conc = {key(a, b) for a, b in concave if a in byl and b in byl and a != b
            and edge_overlap(byl[a], byl[b]) >= min_overlap}
    nbrs: dict = {}
    for a, b in conc:
        nbrs.setdefault(a, set()).add(b)
        nbrs.setdefault(b, set()).add(a)
    n = {k: _towards_sensor(byl[k]) for k in nbrs}
    c = {k: np.asarray(byl[k].centroid, float) for k in nbrs}

    def parallel(x, y) -> bool:
        return abs(float(n[x] @ n[y])) >= cos_tol

    keep: set = set()
    for b, around in nbrs.items():
        around = sorted(around)
        for i, a in enumerate(around):
            for d in around[i + 1:]:
                ab, db, ad = key(a, b), key(d, b), key(a, d)
                if parallel(a, b) or parallel(d, b):
                    continue
                if parallel(a, d):
                    # a channel: b between a and d, which face each other across it
                    off = c[d] - c[a]
                    if float(n[a] @ off) > 0 and float(n[d] @ -off) > 0:
                        keep |= {ab, db}
                elif ad in conc:
                    # an inside corner: three faces, each pair at a concave edge (a box
                    # against a larger one's face makes two and a convex one: its top and side)
                    keep |= {ab, db, ad}
    return {(a, b) for a, b in concave if key(a, b) in keep}


def group_channel_pairs(planes, concave, group_of, angle_tol: float = 10.0,
                        min_overlap: float = 0.5) -> set:
    """Two parallel planes facing each other across a *group* of joined planes (a channel
    whose bottom is several planes: a flight's treads and risers between its side walls).

    A side wall runs along a whole flight, a tread is one step deep: no edge between them is
    whole, but the flight's planes together span the wall.  Walls ``A`` and ``C`` (parallel,
    facing each other, neither in the group) each meeting some plane of the group at a shared
    concave edge join the group when, for each wall, the group's extent (all its planes'
    hulls) along the edge line overlaps the wall's by at least ``min_overlap``; the landing a
    descending flight starts from, between the same walls, spans a fraction of them.

    Parameters
    ----------
    planes : PlaneSet or sequence of Plane
    concave : iterable of (int, int)
        Pairs meeting at a shared concave edge.
    group_of : dict
        Label -> group id (the connected components of the pairs joined so far).

    Returns
    -------
    set of (int, int)
        ``(wall, member)`` pairs joining each such wall to the group.
    """
    byl = {p.label: p for p in planes}
    cos_tol = math.cos(math.radians(angle_tol))
    members: dict = {}
    for k, gid in group_of.items():
        if k in byl:
            members.setdefault(gid, []).append(k)
    touch: dict = {}  # (wall, group) -> members of the group the wall meets concavely
    for a, b in concave:
        for w, m in ((a, b), (b, a)):
            if w in byl and m in byl and group_of.get(m) is not None and group_of.get(w) != group_of[m]:
                touch.setdefault((w, group_of[m]), []).append(m)

    def whole(w, gid, m) -> bool:
        nw, nm = np.asarray(byl[w].normal, float), np.asarray(byl[m].normal, float)
        axis = cross3(nw, nm)
        if float(np.linalg.norm(axis)) < 1e-6:
            return False
        axis /= np.linalg.norm(axis)
        tw = np.asarray(byl[w].hull3d, float) @ axis
        tg = np.concatenate([np.asarray(byl[k].hull3d, float) @ axis for k in members[gid]])
        union = max(tw.max(), tg.max()) - min(tw.min(), tg.min())
        inter = min(tw.max(), tg.max()) - max(tw.min(), tg.min())
        return union > 0 and inter / union >= min_overlap

    out: set = set()
    by_group: dict = {}
    for (w, gid), ms in touch.items():
        by_group.setdefault(gid, []).append((w, ms[0]))
    for gid, walls in by_group.items():
        walls = [(w, m) for w, m in walls if whole(w, gid, m)]
        for i, (a, ma) in enumerate(walls):
            for d, md in walls[i + 1:]:
                na, nd = _towards_sensor(byl[a]), _towards_sensor(byl[d])
                if abs(float(na @ nd)) < cos_tol:
                    continue
                off = np.asarray(byl[d].centroid, float) - np.asarray(byl[a].centroid, float)
                if float(na @ off) > 0 and float(nd @ -off) > 0:
                    out |= {(a, ma), (d, md)}
    return out
