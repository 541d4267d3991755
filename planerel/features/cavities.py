"""Concave cavities: the inside of one open object, seen through its open side.

The locally-convex rule of :func:`planerel.features.proposals.convex_pairs` cuts every concave
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
**Occluded channels** (:func:`occluded_channel_pairs`): seen from beside its open side, a
shelf shows the inside of its far side panel and of its back panel (one whole concave edge)
and the *outside* of its near side panel, which hides part of the back panel: a channel whose
near wall is seen from outside and shares no edge with the bottom, only an occluding one.

Parameters: ``angle_tol`` (degrees; ``ProposalParams.concave_tol``, 10) for "parallel";
shared edges are those with at least ``MIN_EDGE`` pixel pairs of
:func:`~planerel.features.proposals.edge_means`.
"""

from __future__ import annotations

import math

import numpy as np

from planerel.features.vectors import cross3, lo_hi, vec_norm

__all__ = ["cavity_pairs", "edge_overlap", "follows_flight", "group_channel_pairs", "occluded_channel_pairs", "occluding_edge",
           "split_panel_pairs"]


def _towards_sensor(p) -> np.ndarray:
    n = np.asarray(p.normal, float)
    return -n if float(n @ np.asarray(p.centroid, float)) > 0 else n


def edge_overlap(pa, pb) -> float:
    """Interval IoU (0-1) of two planes' extents (their 3-D hulls, ``hull3d``) along the line
    where they meet, ``n_a x n_b``; 0 for parallel planes."""
    axis = cross3(pa.normal, pb.normal)
    nrm = vec_norm(axis)
    if nrm < 1e-6:
        return 0.0
    (a0, a1), (b0, b1) = (lo_hi(np.asarray(p.hull3d, float) @ (axis / nrm)) for p in (pa, pb))
    union = max(a1, b1) - min(a0, b0)
    inter = min(a1, b1) - max(a0, b0)
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
                        min_overlap: float = 0.5, side_members: int = 0,
                        wall_rise_max: float = 0.0, follow: float = 0.0, xyz=None,
                        rise_min: float = 0.08, window: float = 0.05) -> set:
    """Two parallel planes facing each other across a *group* of joined planes (a channel
    whose bottom is several planes: a flight's treads and risers between its side walls).

    A side wall runs along a whole flight, a tread is one step deep: no edge between them is
    whole, but the flight's planes together span the wall.  Walls ``A`` and ``C`` (parallel,
    facing each other, neither in the group) each meeting some plane of the group at a shared
    concave edge join the group when, for each wall, the group's extent (all its planes'
    hulls) along the edge line overlaps the wall's by at least ``min_overlap``; the landing a
    descending flight starts from, between the same walls, spans a fraction of them.

    With ``side_members`` (>= 1), one such wall alone joins the group when at least that many
    distinct members meet it at shared concave edges (a flight seen with one side wall: each
    tread meets it).  A box against a panel or a larger box meets it with its top and a side
    at most; the panel behind a row of boxes meets them at a chain of concave edges but runs
    along the row, and the boxes are no group of joined planes.

    With ``wall_rise_max`` (> 0, metres; needs ``planes.up``), a wall that stands higher than
    that anywhere above the line through the group's horizontal members (height against
    position along the wall, least squares over two or more treads) is a room wall beside the
    flight, not its side wall, and does not join (:func:`wall_rise`).

    With ``follow`` (> 0; needs ``planes.up``, ``planes.labels`` and ``xyz``), one wall alone
    also joins the group, whether the group spans it or not, when its top *follows the flight*
    (:func:`follows_flight`) and it passes ``wall_rise_max``: at least
    two horizontal members meet it at shared concave edges, and over the members where its top
    is in view it stands at one height above each of them (the spread of those heights at most
    ``follow`` times the spread of the members' tops, which is at least ``rise_min``): a closed
    side with its rail seen on one side of the flight.  A room wall's top is level: it stands
    higher above the lower treads by as much as they are lower.

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
    up = getattr(planes, "up", None) if wall_rise_max > 0 else None
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
        if vec_norm(axis) < 1e-6:
            return False
        axis /= vec_norm(axis)
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
        near = walls
        walls = [(w, m) for w, m in walls if whole(w, gid, m)]
        if up is not None:
            walls = [(w, m) for w, m in walls
                     if wall_rise(byl[w], [byl[k] for k in members[gid]], up) <= wall_rise_max]
        if side_members:
            for w, m in walls:
                if len(set(touch[(w, gid)])) >= side_members:
                    out.add((w, m))
        if follow > 0 and xyz is not None and getattr(planes, "labels", None) is not None \
                and getattr(planes, "up", None) is not None:
            # the group need not span the wall (the far treads of a flight are often not
            # segmented); a wall standing higher than wall_rise_max above the flight does not join
            for w, m in near:
                if wall_rise_max > 0 and wall_rise(byl[w], [byl[k] for k in members[gid]],
                                                   planes.up) > wall_rise_max:
                    continue
                flat = sorted({k for k in touch[(w, gid)] if byl[k].orientation == "horizontal"})
                if len(flat) < 2 or byl[w].orientation != "vertical":
                    continue
                if follows_flight(byl[w], [byl[k] for k in flat], planes.up, xyz, planes.labels,
                                  follow, rise_min, window):
                    out.add((w, m))
        for i, (a, ma) in enumerate(walls):
            for d, md in walls[i + 1:]:
                na, nd = _towards_sensor(byl[a]), _towards_sensor(byl[d])
                if abs(float(na @ nd)) < cos_tol:
                    continue
                off = np.asarray(byl[d].centroid, float) - np.asarray(byl[a].centroid, float)
                if float(na @ off) > 0 and float(nd @ -off) > 0:
                    out |= {(a, ma), (d, md)}
    return out


def follows_flight(wall, treads, up, xyz, labels, follow: float = 0.5, rise_min: float = 0.08,
                   window: float = 0.05) -> bool:
    """True when vertical plane ``wall``'s top follows the ``treads`` it meets: over each tread's
    extent along the wall (:func:`planerel.features.walls.side_caps`; only where the wall's top
    points lie off the image border), the wall's top stands at one height above the tread:
    those heights spread by at most ``follow`` times the spread of the treads' tops, which is at
    least ``rise_min`` metres, over two or more treads (False when the wall's top is in view
    over fewer than two: nothing to tell)."""
    from planerel.features.walls import side_caps

    caps = [(above, top) for above, top, ok in side_caps(wall, treads, up, xyz, labels, window)
            if ok and np.isfinite(above)]
    if len(caps) < 2:
        return False
    above = np.array([c[0] for c in caps])
    tops = np.array([c[1] for c in caps])
    span = float(np.ptp(tops))
    return span >= rise_min and float(np.ptp(above)) <= follow * span


def wall_rise(wall, members, up) -> float:
    """How high a wall stands above a flight: the largest height of the wall's hull above the
    line through the flight's treads (the horizontal ``members``; their centroids' heights
    against their positions along the wall, least squares), in metres.

    The treads' middles lie half a rise below the line of nosings, so a side wall ``r``
    above the nosings gives ``r`` plus half a rise.  Fewer than two treads, or treads not
    apart along the wall (a vertical wall across the flight): ``-inf`` (nothing to tell).
    """
    u = np.asarray(up, float)
    u = u / vec_norm(u)
    along = cross3(np.asarray(wall.normal, float), u)
    if vec_norm(along) < 1e-6:
        return float("-inf")
    along = along / vec_norm(along)
    treads = [p for p in members if p.orientation == "horizontal"]
    if len(treads) < 2:
        return float("-inf")
    x = np.array([float(np.asarray(p.centroid, float) @ along) for p in treads])
    h = np.array([float(np.asarray(p.centroid, float) @ u) for p in treads])
    if float(np.ptp(x)) < 0.05:
        return float("-inf")
    slope, icpt = np.polyfit(x, h, 1)
    hull = np.asarray(wall.hull3d, float)
    return float(np.max(hull @ u - (icpt + slope * (hull @ along))))


def occluding_edge(labels, xyz, front: int, back: int, window=None, band: int = 2,
                   jump: float = 0.05) -> int:
    """Pixel pairs along which plane ``front`` hides plane ``back`` in the image: a pixel of
    ``back`` within ``band`` pixels (along a row or a column) of a pixel of ``front`` whose
    range is larger by more than ``jump * max(1, range)`` (an occluding edge, not a shared one).

    Parameters
    ----------
    labels, xyz : ndarray, shapes (H, W) int and (H, W, 3) float
        The plane label image and the organized points.
    window : (row0, col0, row1, col1), optional
        Pixel box holding both planes: only it is looked at.

    Returns
    -------
    int
        The number of such pixel pairs.
    """
    lab = np.asarray(labels)
    xyz = np.asarray(xyz)
    if window is not None:
        r0, c0, r1, c1 = (int(v) for v in window)
        lab, xyz = lab[r0:r1, c0:c1], xyz[r0:r1, c0:c1]
    rng = np.sqrt((np.asarray(xyz, float) ** 2).sum(-1))
    isf, isb = lab == front, lab == back
    n = 0
    for k in range(1, band + 1):
        for ax in (0, 1):
            for f_sl, b_sl in (((slice(None, -k), slice(k, None))), ((slice(k, None), slice(None, -k)))):
                fs = (f_sl, slice(None)) if ax == 0 else (slice(None), f_sl)
                bs = (b_sl, slice(None)) if ax == 0 else (slice(None), b_sl)
                m = isf[fs] & isb[bs]
                if m.any():
                    rf, rb = rng[fs][m], rng[bs][m]
                    n += int(np.count_nonzero(rb - rf > jump * np.maximum(1.0, rf)))
    return n


def _interval(p, axis) -> tuple[float, float]:
    t = np.asarray(p.hull3d, float) @ axis
    return float(t.min()), float(t.max())


def occluded_channel_pairs(planes, concave, labels, xyz, angle_tol: float = 10.0,
                           min_overlap: float = 0.5, reach: float = 0.05,
                           min_occluded: int = 5, trace=None) -> set:
    """A channel seen past its near wall: the near wall's *outside* face hides the bottom.

    Seen from beside its open side, a shelf shows the inside of its far side panel ``A``, the
    inside of its back panel ``B`` (meeting ``A`` at a whole concave edge) and the *outside*
    of its near side panel ``C``: ``C`` is parallel to ``A`` and faces the same way (both
    towards the sensor), and hides the part of ``B`` next to it, so ``B`` and ``C`` share no
    edge, only an occluding one.  The three are one open object when ``C`` stands where
    ``B`` ends: ``C`` lies in front of ``A`` (along ``A``'s normal), ``B`` reaches no farther
    than ``C`` from ``A`` (``reach`` metres of slack), ``C``'s back end lies at ``B``'s plane
    (within ``reach``), ``C`` spans ``A`` along the ``A``-``B`` edge (interval IoU at least
    ``min_overlap``) and ``C`` hides ``B`` along at least ``min_occluded`` pixel pairs
    (:func:`occluding_edge`).  A box against a larger face shows its front face where ``C``
    would be, but that face shares a convex edge with the box's side (no occluding edge
    between them) and stands off the larger face's plane, not at the side's.

    Parameters
    ----------
    planes : PlaneSet or sequence of Plane
    concave : iterable of (int, int)
        Pairs meeting at a shared concave edge (as for :func:`cavity_pairs`).
    labels, xyz : ndarray
        The plane label image and the organized points.

    Returns
    -------
    set of (int, int)
        ``(A, B)`` and ``(B, C)`` of each such channel.
    """
    byl = {p.label: p for p in planes}
    cos_tol = math.cos(math.radians(angle_tol))
    out: set = set()
    whole = [(a, b) for a, b in concave if a in byl and b in byl and a != b
             and edge_overlap(byl[a], byl[b]) >= min_overlap]
    if not whole:
        return out
    n = {k: _towards_sensor(p) for k, p in byl.items()}
    for x, y in whole:
        for a, b in ((x, y), (y, x)):
            pa, pb = byl[a], byl[b]
            ca = np.asarray(pa.centroid, float)
            axis = cross3(n[a], n[b])
            axis /= max(float(np.linalg.norm(axis)), 1e-12)
            ib = _interval(pb, n[a])
            ea = _interval(pa, axis)
            for c, pc in byl.items():
                if c in (a, b) or float(n[a] @ n[c]) < cos_tol:
                    continue
                s = float(n[a] @ (np.asarray(pc.centroid, float) - ca))
                if s <= reach:
                    continue
                # B ends at C: reaches no farther from A than C stands
                if ib[1] - float(n[a] @ ca) > s + reach:
                    continue
                # C's back end at B's plane (C cut by the image border: not behind it)
                tol = reach * max(1.0, float(np.asarray(pc.centroid, float)[2]))
                ic = _interval(pc, n[b])
                back = ic[0] - float(n[b] @ np.asarray(pb.centroid, float))
                cut = bool(pc.touches_border)
                if back < -tol or (back > tol and not cut):
                    continue
                # C spans A along the edge (cut by the border: lies within A's extent)
                ec = _interval(pc, axis)
                inter = min(ea[1], ec[1]) - max(ea[0], ec[0])
                whole_c = (ec[1] - ec[0]) if cut else max(ea[1], ec[1]) - min(ea[0], ec[0])
                if whole_c <= 0 or inter / whole_c < min_overlap:
                    continue
                bb, bc = pb.bbox, pc.bbox
                box = (min(bb[0], bc[0]), min(bb[1], bc[1]), max(bb[2], bc[2]), max(bb[3], bc[3]))
                occ = occluding_edge(labels, xyz, c, b, window=box)
                if trace is not None:
                    trace.append((a, b, c, round(s, 3), round(back, 3), round(inter / whole_c, 2), cut, occ))
                if occ >= min_occluded:
                    out |= {(a, b), (b, c)}
    return out


def split_panel_pairs(planes, concave, labels, xyz, angle_tol: float = 10.0,
                      coplanar_depth: float = 0.03, min_overlap: float = 0.5,
                      reach: float = 0.05, trace=None) -> set:
    """A panel in coplanar pieces, each meeting one plane at a shared concave edge.

    A shelf's back panel seen past a board that is not segmented (a thin plate seen nearly
    edge-on) comes out in two pieces, one above and one below the board; each meets the side
    panel ``S`` at a concave edge, neither spans it alone, and they share no edge with each
    other.  Pieces ``P1`` and ``P2`` join ``S`` when: they are parallel (normals within
    ``angle_tol``) and not parallel to ``S``; each lies within ``coplanar_depth * max(1, z)``
    of the other's plane (one surface); along the ``S``-``P`` edge line they follow one another
    (their extents overlap by at most ``reach * max(1, z)``) and each lies within ``S``'s
    extent (``reach * max(1, z)`` of slack); their joint extent spans ``S`` (interval IoU at
    least ``min_overlap``, as a whole edge of :func:`cavity_pairs`); and what the image shows
    between them is no gap (:func:`planerel.features.gaps.gap_behind`: under half of the
    valid pixels on the lines between them lie behind both, or none is valid: the board seen
    nearly edge-on lies at the panel's depth or in front of it).  A box
    against a wall makes one concave edge; a wall cut in two by something in front of it runs
    beyond the box's side along the edge, and two boxes in a row against one face have the
    floor or a face behind them seen between them.

    Parameters
    ----------
    planes : PlaneSet or sequence of Plane
    concave : iterable of (int, int)
        Pairs meeting at a shared concave edge (as for :func:`cavity_pairs`).
    labels, xyz : ndarray
        The plane label image and the organized points.

    Returns
    -------
    set of (int, int)
        ``(S, P1)`` and ``(S, P2)`` of each such panel.
    """
    from planerel.features.gaps import gap_behind

    byl = {p.label: p for p in planes}
    cos_tol = math.cos(math.radians(angle_tol))
    nbrs: dict = {}
    for a, b in concave:
        if a in byl and b in byl and a != b:
            nbrs.setdefault(a, set()).add(b)
            nbrs.setdefault(b, set()).add(a)
    out: set = set()
    for s, around in sorted(nbrs.items()):
        if len(around) < 2:
            continue
        ps = byl[s]
        ns = _towards_sensor(ps)
        around = sorted(around)
        for i, p1 in enumerate(around):
            for p2 in around[i + 1:]:
                a, b = byl[p1], byl[p2]
                na, nb = _towards_sensor(a), _towards_sensor(b)
                if float(na @ nb) < cos_tol or abs(float(na @ ns)) >= cos_tol:
                    continue
                ca, cb = np.asarray(a.centroid, float), np.asarray(b.centroid, float)
                z = max(1.0, 0.5 * abs(float(ca[2] + cb[2])))
                if max(abs(float(na @ (cb - ca))), abs(float(nb @ (ca - cb)))) > coplanar_depth * z:
                    continue
                axis = cross3(ns, na)
                axis /= max(float(np.linalg.norm(axis)), 1e-12)
                ia, ib, i_s = _interval(a, axis), _interval(b, axis), _interval(ps, axis)
                slack = reach * z
                if min(ia[1], ib[1]) - max(ia[0], ib[0]) > slack:
                    continue
                if any(iv[0] < i_s[0] - slack or iv[1] > i_s[1] + slack for iv in (ia, ib)):
                    continue
                lo, hi = min(ia[0], ib[0]), max(ia[1], ib[1])
                union = max(hi, i_s[1]) - min(lo, i_s[0])
                span = (min(hi, i_s[1]) - max(lo, i_s[0])) / union if union > 0 else 0.0
                if span < min_overlap:
                    continue
                ba, bb = a.bbox, b.bbox
                box = (min(ba[0], bb[0]), min(ba[1], bb[1]), max(ba[2], bb[2]), max(ba[3], bb[3]))
                f = gap_behind(labels, xyz, p1, p2, window=box)
                if trace is not None:
                    trace.append((s, p1, p2, round(span, 2), f))
                if f is None or f < 0.5:
                    out |= {(s, p1), (s, p2)}
    return out
